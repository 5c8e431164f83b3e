//! pbrt-v4's stochastic layered BSDF (`coateddiffuse`, `coatedconductor`) against closed forms:
//!
//! - a coat of index 1 over a Lambertian base is the base seen through an absorbing layer twice,
//!   `f = r / pi exp(-t / mu_o) exp(-t / mu_i)` (the walk's estimate is exact there);
//! - a smooth coat over a Lambertian base with a vanishing layer reflects, in all, the classic
//!   `F(mu_o) + (1 - F(mu_o)) r (1 - F_in) / (1 - r F_in)` (`F_in` the coat's diffuse reflectance from inside,
//!   `1 - (1 - F_dr(eta)) / eta^2`): the walk's sample weights average to it;
//! - the walk's samples and its value agree: per band of `cos theta_i`, the mean sample weight equals the
//!   integral of `f cos` over the band (rough coat, scattering medium, conductor base). With pbrt-v4's own MIS
//!   weights for the exit connections (the exit interface's density of `wi` given the inner direction, where the
//!   other strategy's density is of the inner direction given `wi`; pbrt-v4 issue #187) the value is 5-15% above
//!   the samples on rough coats;
//! - the smooth coat's mirror reflection is a delta direction exactly when the lobe number says so (what
//!   estimators that plan ahead, like `ppm`'s eye pass, rely on);
//! - determinism: the same directions give the same estimate bit for bit;
//! - a coated sphere in a white furnace (smooth coat, vanishing layer) renders the closed form's mean under
//!   `envlight` with and without MIS, `ppm`, `vcm` and `vcm(mode: bdpt)` (within 1%; within 0.2% with MIS).

use glam::{Vec2, Vec3, Vec3A};
use prism::bsdf::layered::{LayerBase, LayerSpec, Layers};
use prism::bsdf::{Bsdf, Lobe, TransportMode};
use prism::sampling::Rng;
use std::f32::consts::PI;

fn spec(base: LayerBase, eta: f32, thickness: f32, g: f32, max_depth: u32) -> &'static LayerSpec {
    LayerSpec { base, eta, thickness, g, max_depth, samples: 1 }.intern()
}

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3A {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3A::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn lobe(spec: &'static LayerSpec, coat_alpha: f32, base: Vec3, albedo: Vec3) -> Lobe {
    Lobe::Layered { coat_alpha, base, base_k: Vec3::ZERO, base_alpha: 0.0, albedo, scale: 1.0, spec }
}

#[test]
fn an_index_one_coat_is_the_base_seen_through_an_absorbing_layer_twice() {
    let t = 0.3;
    let s = spec(LayerBase::Diffuse, 1.0, t, 0.0, 10);
    let r = Vec3::new(0.8, 0.5, 0.2);
    let layers = Layers::new(s, 0.0, r, Vec3::ZERO, 0.0, Vec3::ZERO);
    for (to, ti, phi) in [(0.0, 0.0, 0.0), (30.0, 60.0, 90.0), (75.0, 10.0, 200.0), (85.0, 85.0, 33.0)] {
        let (wo, wi) = (dir(to, 0.0), dir(ti, phi));
        let want = r / PI * (-t / wo.z).exp() * (-t / wi.z).exp();
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let got = layers.f(wo, wi, mode);
            assert!((got - want).abs().max_element() < 1e-5 * want.max_element().max(1.0), "{got} vs {want}");
        }
    }
}

/// Mean of the walk's sample weights from `wo` over `n` stratified samples (the directional albedo), and the
/// same per band of `cos theta_i` (`bands` equal bands).
fn sampled_albedo(bsdf: &Bsdf, n: u32, bands: usize) -> (Vec3, Vec<Vec3>) {
    let mut rng = Rng::new(7, 11);
    let (mut sum, mut per) = (Vec3::ZERO, vec![Vec3::ZERO; bands]);
    for i in 0..n {
        let ul = (i as f32 + rng.next_f32()) / n as f32;
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = bsdf.sample_mode(ul, u, TransportMode::Radiance) {
            sum += s.weight;
            if !s.delta {
                let c = s.wi.z.clamp(0.0, 0.999_999);
                per[(c * bands as f32) as usize] += s.weight;
            }
        }
    }
    (sum / n as f32, per.into_iter().map(|v| v / n as f32).collect())
}

#[test]
fn a_smooth_coat_over_lambert_reflects_the_classic_total() {
    let eta = 1.5f32;
    let s = spec(LayerBase::Diffuse, eta, 1e-6, 0.0, 100);
    // The coat's diffuse reflectance from inside, by quadrature of Fresnel (independent of the walk).
    let n = 20_000;
    let mut f_in = 0.0f64;
    for i in 0..n {
        let mu = (i as f64 + 0.5) / n as f64;
        f_in += 2.0 * mu * prism::math::fresnel_dielectric(mu as f32, 1.0 / eta) as f64 / n as f64;
    }
    for (theta, r) in [(0.0f32, 0.5f32), (45.0, 0.8), (70.0, 0.3)] {
        let wo = dir(theta, 0.0);
        let fo = prism::math::fresnel_dielectric(wo.z, eta) as f64;
        let r64 = r as f64;
        let want = fo + (1.0 - fo) * r64 * (1.0 - f_in) / (1.0 - r64 * f_in);
        let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[lobe(s, 0.0, Vec3::splat(r), Vec3::ZERO)]).unwrap();
        let (albedo, _) = sampled_albedo(&bsdf, 400_000, 1);
        let got = albedo.x as f64;
        assert!((got / want - 1.0).abs() < 0.006, "theta {theta}, r {r}: walk {got:.5}, closed form {want:.5}");
    }
}

/// `int f cos` over bands of `cos theta_i`, by a stratified grid of directions (value estimates).
fn integrated_value(bsdf: &Bsdf, bands: usize) -> Vec<Vec3> {
    let (nc, np) = (400, 96);
    let mut per = vec![Vec3::ZERO; bands];
    for i in 0..nc {
        let c = (i as f32 + 0.5) / nc as f32;
        let s = (1.0 - c * c).sqrt();
        for j in 0..np {
            let phi = 2.0 * PI * (j as f32 + 0.37) / np as f32;
            let wi = Vec3A::new(s * phi.cos(), s * phi.sin(), c);
            let f = bsdf.eval(wi);
            per[(c * bands as f32) as usize] += f * c * (2.0 * PI / (nc * np) as f32);
        }
    }
    per
}

#[test]
fn the_walks_samples_and_its_value_estimate_agree() {
    let bands = 5;
    let cases = [
        (
            "rough coat over lambert",
            lobe(spec(LayerBase::Diffuse, 1.5, 0.01, 0.0, 10), 0.3, Vec3::splat(0.7), Vec3::ZERO),
        ),
        (
            "rough coat, scattering medium",
            lobe(spec(LayerBase::Diffuse, 1.33, 0.5, 0.4, 10), 0.2, Vec3::new(0.9, 0.4, 0.1), Vec3::splat(0.8)),
        ),
        (
            "rough coat over rough copper",
            Lobe::Layered {
                coat_alpha: 0.25,
                base: Vec3::new(0.2, 0.92, 1.1) / 1.5,
                base_k: Vec3::new(3.9, 2.45, 2.14) / 1.5,
                base_alpha: 0.3,
                albedo: Vec3::ZERO,
                scale: 1.0,
                spec: spec(LayerBase::Conductor, 1.5, 0.01, 0.0, 10),
            },
        ),
    ];
    for (name, l) in cases {
        for theta in [20.0, 65.0] {
            let bsdf = Bsdf::from_lobes(Vec3A::Z, dir(theta, 0.0), &[l]).unwrap();
            let (_, sampled) = sampled_albedo(&bsdf, 300_000, bands);
            let integrated = integrated_value(&bsdf, bands);
            for b in 0..bands {
                let (s, v) = (sampled[b], integrated[b]);
                let tol = 0.03 * v.max_element() + 2e-3;
                assert!(
                    (s - v).abs().max_element() < tol,
                    "{name}, theta {theta}, band {b}: mean sample weight {s}, integral of f cos {v}"
                );
            }
        }
    }
}

#[test]
fn a_smooth_coats_mirror_reflection_is_delta_exactly_when_the_lobe_number_says() {
    let l = lobe(spec(LayerBase::Diffuse, 1.5, 0.01, 0.0, 10), 0.0, Vec3::splat(0.6), Vec3::ZERO);
    let wo = dir(60.0, 0.0);
    let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[l]).unwrap();
    let f = prism::math::fresnel_dielectric(wo.z, 1.5);
    assert!((1.0 - bsdf.smooth_probability() - f).abs() < 1e-6);
    let mut rng = Rng::new(3, 5);
    for _ in 0..20_000 {
        let ul = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = bsdf.sample(ul, u) {
            assert_eq!(s.delta, bsdf.picks_delta(ul), "lobe number {ul}");
            if s.delta {
                assert!((s.wi - Vec3A::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
            }
        }
    }
}

#[test]
fn the_same_directions_give_the_same_estimate_bit_for_bit() {
    let l = lobe(spec(LayerBase::Diffuse, 1.5, 0.3, 0.2, 10), 0.2, Vec3::splat(0.6), Vec3::splat(0.5));
    let (wo, wi) = (dir(35.0, 0.0), dir(50.0, 120.0));
    let a = Bsdf::from_lobes(Vec3A::Z, wo, &[l]).unwrap();
    let b = Bsdf::from_lobes(Vec3A::Z, wo, &[l]).unwrap();
    assert_eq!(a.eval(wi).to_array().map(f32::to_bits), b.eval(wi).to_array().map(f32::to_bits));
    assert_eq!(a.pdf(wi).to_bits(), b.pdf(wi).to_bits());
    let mut walks = 0;
    for i in 0..64 {
        let (ul, u) = (0.3 + i as f32 / 100.0, Vec2::new(0.2 + i as f32 / 80.0, 0.9 - i as f32 / 90.0));
        let (sa, sb) = (a.sample(ul, u), b.sample(ul, u));
        assert_eq!(sa.is_some(), sb.is_some());
        if let (Some(sa), Some(sb)) = (sa, sb) {
            assert_eq!(sa.weight.to_array().map(f32::to_bits), sb.weight.to_array().map(f32::to_bits));
            assert_eq!(sa.wi.to_array().map(f32::to_bits), sb.wi.to_array().map(f32::to_bits));
            walks += 1;
        }
    }
    assert!(walks > 32, "only {walks} of 64 walks left the layers");
}

/// The closed-form directional albedo of a smooth coat of index `eta` over a Lambertian base `r` with a vanishing
/// layer (see the module doc), at view cosine `mu`.
fn smooth_coat_albedo(mu: f64, eta: f32, r: f64) -> f64 {
    let n = 4000;
    let f_in: f64 = (0..n)
        .map(|i| {
            let m = (i as f64 + 0.5) / n as f64;
            2.0 * m * prism::math::fresnel_dielectric(m as f32, 1.0 / eta) as f64 / n as f64
        })
        .sum();
    let fo = prism::math::fresnel_dielectric(mu as f32, eta) as f64;
    fo + (1.0 - fo) * r * (1.0 - f_in) / (1.0 - r * f_in)
}

#[test]
fn a_coated_sphere_in_a_white_furnace_reflects_the_closed_form_under_every_integrator() {
    // Camera at (0, 0, 4) looking at a unit sphere, 40 degree field of view, 48 x 48 pixels, box filter: each
    // pixel's reference is the closed form averaged over 8 x 8 rays through it (the sphere is convex: in a furnace
    // of radiance 1 a ray's radiance is the directional albedo at its view cosine).
    let (size, eta) = (48usize, 1.5f32);
    let base = [0.3f64, 0.6, 0.9];
    let scene = format!(
        "(
    camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: ({size}, {size})),
    render: (filter: Box()),
    materials: {{ \"c\": CoatedDiffuse(reflectance: ({}, {}, {}), alpha: 0, ior: {eta}, thickness: 1e-6, max_depth: 100) }},
    entities: [(shape: Sphere(), material: \"c\"), (light: Environment(radiance: (1, 1, 1)))],
)",
        base[0], base[1], base[2]
    );
    let tan = 20f64.to_radians().tan();
    let mut reference = vec![[0.0f64; 3]; size * size];
    let mut on_sphere = vec![true; size * size];
    for y in 0..size {
        for x in 0..size {
            let mut acc = [0.0; 3];
            for s in 0..64 {
                let (sx, sy) = ((s % 8) as f64 + 0.5, (s / 8) as f64 + 0.5);
                let px = (2.0 * (x as f64 + sx / 8.0) / size as f64 - 1.0) * tan;
                let py = (1.0 - 2.0 * (y as f64 + sy / 8.0) / size as f64) * tan;
                let d = glam::DVec3::new(px, py, -1.0).normalize();
                let o = glam::DVec3::new(0.0, 0.0, 4.0);
                let b = o.dot(d);
                let disc = b * b - (o.length_squared() - 1.0);
                if disc <= 0.0 {
                    on_sphere[y * size + x] = false;
                    continue;
                }
                let t = -b - disc.sqrt();
                let mu = -(o + t * d).normalize().dot(d);
                for c in 0..3 {
                    acc[c] += smooth_coat_albedo(mu, eta, base[c]) / 64.0;
                }
            }
            reference[y * size + x] = acc;
        }
    }
    let pixels: Vec<usize> = (0..size * size).filter(|&i| on_sphere[i]).collect();
    let mean_ref =
        pixels.iter().fold(glam::DVec3::ZERO, |a, &i| a + glam::DVec3::from(reference[i])) / pixels.len() as f64;
    for integrator in ["envlight", "envlight(mis: false)", "ppm", "vcm", "vcm(mode: bdpt)"] {
        let mut o = crate::common::spp(128);
        o.integrator = Some(integrator.into());
        let img = crate::common::render_ron(&scene, o);
        let mean = pixels.iter().fold(glam::DVec3::ZERO, |a, &i| a + img.pixels[i].as_dvec3()) / pixels.len() as f64;
        let rel = ((mean - mean_ref) / mean_ref).abs().max_element();
        // Estimators without MIS light the walk's value alone, one walk per direction: its noise sets the band.
        assert!(rel < 0.01, "{integrator}: sphere mean {mean}, closed form {mean_ref} ({:.2}% off)", rel * 100.0);
    }
}
