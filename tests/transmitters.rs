//! pbrt-v4's thin transmitters (`diffusetransmission`, `thindielectric`):
//!
//! - a diffuse transmitter reflects `r` and transmits `t` in all (its value integrated over each hemisphere by
//!   quadrature, and its sample weights), and its sampling density integrates to 1;
//! - a thin dielectric slab reflects `2 R / (1 + R)` (`R` Fresnel's: the closed form of a lossless slab's
//!   inter-reflections) into the mirror direction and transmits the rest straight through;
//! - spheres of either in a white furnace, lossless (`r + t = 1`; any slab), render 1 everywhere under `envlight`
//!   with and without MIS, `ppm`, `vcm` and `vcm(mode: bdpt)`: light scattered to the other side is not lost.

use crate::common::{render_ron, spp};
use glam::{Vec2, Vec3, Vec3A};
use prism::bsdf::{Bsdf, Lobe};
use prism::sampling::Rng;
use std::f32::consts::PI;

fn dir(theta_deg: f32) -> Vec3A {
    let t = theta_deg.to_radians();
    Vec3A::new(t.sin(), 0.0, t.cos())
}

#[test]
fn a_diffuse_transmitter_reflects_r_and_transmits_t() {
    let (r, t) = (Vec3::new(0.6, 0.3, 0.1), Vec3::new(0.2, 0.5, 0.7));
    let wo = dir(40.0);
    let b = Bsdf::from_lobes(Vec3A::Z, wo, &[Lobe::DiffuseTransmission { r, t }]).unwrap();
    // Quadrature over the sphere: the value times the cosine per hemisphere, and the density.
    let (n, m) = (400, 200);
    let (mut up, mut down, mut pdf) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
    for i in 0..n {
        let z = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
        let s = (1.0 - z * z).sqrt();
        for j in 0..m {
            let phi = 2.0 * PI * (j as f32 + 0.5) / m as f32;
            let wi = Vec3A::new(s * phi.cos(), s * phi.sin(), z);
            let dw = 4.0 * PI / (n * m) as f32;
            let f = b.eval(wi) * z.abs() * dw;
            if z > 0.0 {
                up += f
            } else {
                down += f
            }
            pdf += b.pdf(wi) * dw;
        }
    }
    assert!((up - r).abs().max_element() < 2e-3 && (down - t).abs().max_element() < 2e-3, "{up} {down}");
    assert!((pdf - 1.0).abs() < 2e-3, "the density integrates to {pdf}");
    let mut rng = Rng::new(1, 2);
    let (mut su, mut sd, count) = (Vec3::ZERO, Vec3::ZERO, 100_000);
    for i in 0..count {
        let ul = (i as f32 + 0.5) / count as f32;
        let s = b.sample(ul, Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
        if s.wi.z > 0.0 { su += s.weight } else { sd += s.weight }
    }
    let (su, sd) = (su / count as f32, sd / count as f32);
    assert!((su - r).abs().max_element() < 1e-3 && (sd - t).abs().max_element() < 1e-3, "{su} {sd}");
}

#[test]
fn a_thin_slab_reflects_two_r_over_one_plus_r_and_transmits_the_rest_straight() {
    for (theta, eta) in [(0.0f32, 1.5f32), (45.0, 1.5), (80.0, 1.33), (30.0, 2.4)] {
        let wo = dir(theta);
        let fr = prism::math::fresnel_dielectric(wo.z, eta);
        let want = 2.0 * fr / (1.0 + fr);
        let b = Bsdf::from_lobes(Vec3A::Z, wo, &[Lobe::ThinDielectric { r: Vec3::ONE, t: Vec3::ONE, eta }]).unwrap();
        let (mut reflected, mut transmitted, n) = (0.0f32, 0.0f32, 20_000);
        for i in 0..n {
            let s = b.sample((i as f32 + 0.5) / n as f32, Vec2::splat(0.5)).unwrap();
            assert!(s.delta);
            if s.wi.z > 0.0 {
                assert!((s.wi - Vec3A::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
                reflected += s.weight.x / n as f32;
            } else {
                assert!((s.wi + wo).length() < 1e-6, "straight through");
                transmitted += s.weight.x / n as f32;
            }
        }
        assert!((reflected - want).abs() < 2e-4, "theta {theta}, eta {eta}: {reflected} vs {want}");
        assert!((transmitted - (1.0 - want)).abs() < 2e-4);
    }
}

#[test]
fn lossless_transmitters_in_a_white_furnace_render_one_under_every_integrator() {
    for material in [
        "DiffuseTransmission(reflectance: (0.7, 0.5, 0.2), transmittance: (0.3, 0.5, 0.8))",
        "ThinDielectric(ior: 1.5)",
    ] {
        let scene = format!(
            "(
    camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (32, 32)),
    render: (filter: Box()),
    materials: {{ \"m\": {material} }},
    entities: [(shape: Sphere(), material: \"m\"), (light: Environment(radiance: (1, 1, 1)))],
)"
        );
        for integrator in ["envlight", "envlight(mis: false)", "ppm", "vcm", "vcm(mode: bdpt)"] {
            let mut o = spp(64);
            o.integrator = Some(integrator.into());
            let img = render_ron(&scene, o);
            let mean = img.pixels.iter().fold(glam::DVec3::ZERO, |a, p| a + p.as_dvec3()) / img.pixels.len() as f64;
            let off = (mean - glam::DVec3::ONE).abs().max_element();
            assert!(off < 0.01, "{material} under {integrator}: furnace mean {mean}, want 1");
        }
    }
}
