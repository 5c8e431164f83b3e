//! Lights own their emission: for every light type, emitted rays (`sample_le`) follow the position and direction
//! pdfs they report (chi-square of directions, pdf_le agreement), and the power estimated by Monte Carlo from
//! emitted rays (mean of `flux()`) equals `power()`, with `power()` itself checked against closed forms. Also the
//! spot light's irradiance law (inverse square, cosine, smoothstep cone) and spot light input errors.

use crate::common::{app_from_ron, data, render_ron, spp};
use crate::sampling::{Binning, check_sampler_with};
use glam::{Vec2, Vec3, Vec3A};
use prism::lights::{EnvStrategy, LightSampler, LightSet};
use prism::math::{Frame, luminance};
use prism::primitives::Primitives;
use prism::sampling::Rng;
use prism::settings::Overrides;
use std::f32::consts::PI;

/// The lights and primitives of a RON scene.
fn lights_of(ron: &str) -> (LightSet, Primitives) {
    let mut app = app_from_ron(ron, Overrides::default());
    app.setup().unwrap_or_else(|e| panic!("setup failed: {e}"));
    let scene = app.resources.scene.take().unwrap();
    (scene.lights, scene.prims)
}

/// Mean flux of `n` emitted rays of slot `slot` (through the power-choosing sampler, choice probability divided
/// out) against `power()`: relative error within 4 standard errors and `floor`.
fn check_power(name: &str, lights: &LightSet, prims: &Primitives, slot: usize, expected: Option<Vec3>) {
    let sampler = LightSampler::new(lights, prims, EnvStrategy::Quadtree);
    let power = lights.power(slot, prims);
    if let Some(e) = expected {
        assert!((power - e).abs().max_element() <= 1e-4 * e.max_element(), "{name}: power {power} vs closed form {e}");
    }
    let mut rng = Rng::new(7, slot as u64 + name.len() as u64);
    let n = 400_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        // Choose this slot only: u_choice inside its interval of the power cdf.
        let flux = match emit(&sampler, lights, prims, slot, &mut rng) {
            Some(f) => luminance(f) as f64,
            None => 0.0,
        };
        sum += flux;
        sum2 += flux * flux;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
    let target = luminance(power) as f64;
    assert!(
        (mean - target).abs() <= 4.0 * se + 2e-3 * target,
        "{name}: Monte Carlo power {mean:.5} +- {se:.5} vs power() {target:.5}"
    );
}

/// One emitted ray of `slot`, its flux (the sample's flux; slots are sampled directly, not by choice).
fn emit(sampler: &LightSampler, lights: &LightSet, prims: &Primitives, slot: usize, rng: &mut Rng) -> Option<Vec3> {
    let (u_pos, u_dir) = (rng.next_2d(), rng.next_2d());
    let le = if slot == lights.len() {
        lights.environment.as_ref()?.sample_le(sampler.env.as_ref()?, &lights.sphere, u_pos, u_dir)?
    } else {
        lights.sample_le(slot, prims, u_pos, u_dir)?
    };
    Some(le.flux())
}

/// Chi-square of the emitted directions of `slot` against `pdf_le`'s direction pdf (for lights whose direction
/// pdf does not depend on the position: point, spot, and area lights in the frame of a flat emitter), and
/// agreement of each sample's pdfs with `pdf_le`.
fn check_directions(name: &str, lights: &LightSet, prims: &Primitives, slot: usize, binning: Binning) {
    let mut mismatches = 0;
    check_sampler_with(
        name,
        &mut |u| {
            let le = lights.sample_le(slot, prims, Vec2::new(0.37, 0.61), u)?;
            let (pp, pd) = lights.pdf_le(slot, prims, le.ray.origin, le.n, le.ray.dir);
            if (pp - le.pdf_pos).abs() > 1e-3 * le.pdf_pos || (pd - le.pdf_dir).abs() > 1e-3 * le.pdf_dir {
                mismatches += 1;
            }
            Some(le.ray.dir)
        },
        &|d| {
            let le = lights.sample_le(slot, prims, Vec2::new(0.37, 0.61), Vec2::new(0.3, 0.3)).unwrap();
            lights.pdf_le(slot, prims, le.ray.origin, le.n, d).1 as f64
        },
        200_000,
        true,
        &binning,
    );
    assert_eq!(mismatches, 0, "{name}: sample pdfs differ from pdf_le");
}

/// Equal-area bins over the cap `cos >= zmin` around `axis`.
fn around(axis: Vec3A, zmin: f64) -> Binning {
    Binning { frame: Frame::from_normal(axis), zmin, ..Binning::sphere() }
}

const QUAD: &str =
    "(shape: Quad(), transform: [Translate((0, 1, 0)), Rotate(axis: (1, 0, 0), degrees: 90), Scale((0.3, 0.2, 1))]";

#[test]
fn area_light_emits_cosine_rays_and_power_pi_a_l() {
    let one = format!("(camera: (), entities: [{QUAD}, light: Area(radiance: (2, 1, 0.5)))])");
    let (lights, prims) = lights_of(&one);
    // The quad is 0.6 x 0.4, facing -y after the rotation.
    let area = 0.6 * 0.4;
    check_power("quad light", &lights, &prims, 0, Some(Vec3::new(2.0, 1.0, 0.5) * PI * area));
    check_directions("quad light directions", &lights, &prims, 0, around(Vec3A::NEG_Y, -1.0));
    let two = format!("(camera: (), entities: [{QUAD}, light: Area(radiance: (2, 1, 0.5), two_sided: true))])");
    let (lights, prims) = lights_of(&two);
    check_power("two-sided quad light", &lights, &prims, 0, Some(Vec3::new(2.0, 1.0, 0.5) * 2.0 * PI * area));
    check_directions("two-sided quad directions", &lights, &prims, 0, around(Vec3A::NEG_Y, -1.0));
}

#[test]
fn sphere_ellipsoid_and_mesh_lights_emit_their_power() {
    let sphere =
        "(camera: (), entities: [(shape: Sphere(center: (0, 1, 0), radius: 0.3), light: Area(radiance: (1, 1, 1)))])";
    let (lights, prims) = lights_of(sphere);
    check_power("sphere light", &lights, &prims, 0, Some(Vec3::ONE * PI * 4.0 * PI * 0.09));
    // Ellipsoid with semi-axes (0.6, 0.3, 0.3): a prolate spheroid, area 2 pi b^2 (1 + a/(b e) asin e).
    let ellipsoid = "(camera: (), entities: [(shape: Sphere(radius: 0.3), light: Area(radiance: (1, 1, 1)), transform: [Scale((2, 1, 1))])])";
    let (lights, prims) = lights_of(ellipsoid);
    let (a, b) = (0.6f64, 0.3f64);
    let e = (1.0 - b * b / (a * a)).sqrt();
    let area = 2.0 * std::f64::consts::PI * b * b * (1.0 + a / (b * e) * e.asin());
    check_power("ellipsoid light", &lights, &prims, 0, Some(Vec3::ONE * PI * area as f32));
    // A cube of unequal faces: area-weighted triangle choice.
    let cube = "(camera: (), entities: [(shape: Cube, light: Area(radiance: (1, 2, 3)), transform: [Rotate(axis: (1, 1, 0), degrees: 30), Scale((0.5, 0.2, 0.3))])])";
    let (lights, prims) = lights_of(cube);
    let area = 8.0 * (0.5 * 0.2 + 0.2 * 0.3 + 0.3 * 0.5);
    check_power("cube light", &lights, &prims, 0, Some(Vec3::new(1.0, 2.0, 3.0) * PI * area));
}

#[test]
fn point_and_spot_lights_emit_their_power_in_the_right_directions() {
    let point = "(camera: (), entities: [(light: Point(intensity: (3, 2, 1), position: (0, 1, 0)))])";
    let (lights, prims) = lights_of(point);
    check_power("point light", &lights, &prims, 0, Some(Vec3::new(3.0, 2.0, 1.0) * 4.0 * PI));
    check_directions("point light directions", &lights, &prims, 0, around(Vec3A::Z, -1.0));
    let spot = "(camera: (), entities: [(light: Spot(intensity: (3, 2, 1), position: (0, 1, 0), direction: (0.3, -1, 0.2), cone_angle: 40, falloff: 15))])";
    let (lights, prims) = lights_of(spot);
    let (cs, ce) = (25f32.to_radians().cos(), 40f32.to_radians().cos());
    let closed = Vec3::new(3.0, 2.0, 1.0) * 2.0 * PI * ((1.0 - cs) + 0.5 * (cs - ce));
    check_power("spot light", &lights, &prims, 0, Some(closed));
    let axis = Vec3A::new(0.3, -1.0, 0.2).normalize();
    check_directions("spot light directions", &lights, &prims, 0, around(axis, ce as f64));
}

#[test]
fn directional_light_emits_from_a_disk_covering_the_scene() {
    let ron = "(camera: (), entities: [(shape: Sphere(center: (1, 0, 0), radius: 0.5)), (light: Directional(irradiance: (2, 2, 2), direction: (0, -1, 1)))])";
    let (lights, prims) = lights_of(ron);
    let r = lights.sphere.radius;
    check_power("directional light", &lights, &prims, 0, Some(Vec3::splat(2.0) * PI * r * r));
    // Every emitted ray travels along the light's direction and passes within R of the scene centre, and the
    // disk is uniformly covered: the fraction of rays that hit the sphere is its projected area / disk area.
    let mut rng = Rng::new(3, 3);
    let (n, mut hits) = (100_000, 0);
    let dir = Vec3A::new(0.0, -1.0, 1.0).normalize();
    for _ in 0..n {
        let le = lights.sample_le(0, &prims, rng.next_2d(), rng.next_2d()).unwrap();
        assert!((le.ray.dir - dir).length() < 1e-5);
        let to_c = lights.sphere.center - le.ray.origin;
        let off = to_c - le.ray.dir * to_c.dot(le.ray.dir);
        assert!(off.length() <= r * (1.0 + 1e-4), "ray misses the covering disk");
        let closest = (Vec3A::new(1.0, 0.0, 0.0) - le.ray.origin).cross(le.ray.dir).length();
        hits += (closest < 0.5) as usize;
    }
    let frac = hits as f64 / n as f64;
    let expected = (0.25 / (r * r)) as f64;
    assert!((frac - expected).abs() < 4.0 * (expected / n as f64).sqrt() + 1e-3, "{frac} vs {expected}");
}

#[test]
fn environment_lights_emit_their_power() {
    let constant = "(camera: (), entities: [(shape: Sphere()), (light: Environment(radiance: (0.5, 1, 2)))])";
    let (lights, prims) = lights_of(constant);
    let r = lights.sphere.radius;
    let closed = Vec3::new(0.5, 1.0, 2.0) * 4.0 * PI * PI * r * r;
    check_power("constant environment", &lights, &prims, lights.len(), Some(closed));
    let map = data("envmaps/equirect/probulator_grace_256x128.hdr");
    let ron = format!(
        "(camera: (), entities: [(shape: Sphere()), (light: Environment(map: {:?}), transform: [Rotate(axis: (0, 1, 0), degrees: 60)])])",
        map.display().to_string()
    );
    let (lights, prims) = lights_of(&ron);
    check_power("grace environment (quad-tree)", &lights, &prims, lights.len(), None);
    // Emitted directions follow the quad-tree's pdf (pdf_le agreement on every sample).
    let sampler = LightSampler::new(&lights, &prims, EnvStrategy::Quadtree);
    let (env, es) = (lights.environment.as_ref().unwrap(), sampler.env.as_ref().unwrap());
    let mut rng = Rng::new(5, 5);
    for _ in 0..10_000 {
        let le = env.sample_le(es, &lights.sphere, rng.next_2d(), rng.next_2d()).unwrap();
        let (pp, pd) = env.pdf_le(es, &lights.sphere, le.ray.dir);
        assert!((pp - le.pdf_pos).abs() <= 1e-5 * pp && (pd - le.pdf_dir).abs() <= 1e-3 * pd);
    }
}

#[test]
fn light_choice_follows_power_and_a_dark_scene_emits_nothing() {
    let ron = format!(
        "(camera: (), entities: [{QUAD}, light: Area(radiance: (1, 1, 1))), (light: Point(intensity: (1, 1, 1)))])"
    );
    let (lights, prims) = lights_of(&ron);
    let s = LightSampler::new(&lights, &prims, EnvStrategy::Quadtree);
    let (p0, p1) = (luminance(lights.power(0, &prims)), luminance(lights.power(1, &prims)));
    assert!((s.choice.prob(0) - p0 / (p0 + p1)).abs() < 1e-6);
    let dark = format!("(camera: (), entities: [{QUAD}, light: Area(radiance: (0, 0, 0)))])");
    let (lights, prims) = lights_of(&dark);
    let s = LightSampler::new(&lights, &prims, EnvStrategy::Quadtree);
    assert!(!s.has_power());
    assert!(s.sample_le(&lights, &prims, 0.5, Vec2::splat(0.5), Vec2::splat(0.5)).is_none());
}

#[test]
fn spot_light_irradiance_follows_inverse_square_cosine_and_its_cone() {
    // A spot 2 units above a white Lambertian floor pointing straight down: radiance = (0.8/pi) I cos / d^2 inside
    // the inner cone (20 deg), 0 outside the outer cone (30 deg), smoothstep between. Orthographic camera from
    // above, 64 px over 4 units.
    let ron = r#"(
        camera: (eye: (0, 5, 0), target: (0, 0, 0), up: (0, 0, -1), orthographic: 4, size: (64, 64)),
        render: (integrator: phong, spp: 1),
        materials: { "white": Lambert(albedo: (0.8, 0.8, 0.8)) },
        entities: [
            (shape: Plane(normal: (0, 1, 0), offset: 0), material: "white"),
            (light: Spot(intensity: (5, 5, 5), position: (0, 2, 0), direction: (0, -1, 0), cone_angle: 30, falloff: 10)),
        ],
    )"#;
    let img = render_ron(ron, spp(256));
    let radiance = |x: f32, z: f32| {
        let d = Vec3A::new(-x, 2.0, -z);
        let dist2 = d.length_squared();
        let cos = d.y / dist2.sqrt();
        let (cs, ce) = (20f32.to_radians().cos(), 30f32.to_radians().cos());
        let t = ((cos - ce) / (cs - ce)).clamp(0.0, 1.0);
        0.8 / PI * 5.0 * cos / dist2 * t * t * (3.0 - 2.0 * t)
    };
    for (x, y) in [(32u32, 32u32), (36, 32), (40, 30), (44, 32), (47, 32), (52, 40), (60, 60)] {
        // The pixel's mean radiance by a 16 x 16 midpoint rule over its footprint (1/16 unit wide).
        let mut expected = 0.0;
        for a in 0..16 {
            for b in 0..16 {
                let fx = (x as f32 + (a as f32 + 0.5) / 16.0) / 16.0 - 2.0;
                let fz = (y as f32 + (b as f32 + 0.5) / 16.0) / 16.0 - 2.0;
                expected += radiance(fx, fz) / 256.0;
            }
        }
        let got = img.get(x, y).x;
        assert!((got - expected).abs() <= 2e-3 * expected.max(1e-3), "pixel ({x},{y}): {got} vs {expected}");
    }
}

#[test]
fn bad_spot_lights_are_clear_errors() {
    for (light, needle) in [
        ("Spot(intensity: (1, 1, 1), cone_angle: 0)", "cone_angle"),
        ("Spot(intensity: (1, 1, 1), cone_angle: 200)", "cone_angle"),
        ("Spot(intensity: (1, 1, 1), cone_angle: 20, falloff: 30)", "falloff"),
        ("Spot(intensity: (1, 1, 1), position: (1, 1, 1), target: (1, 1, 1))", "zero vector"),
        ("Spot(intensity: (1, 1, 1), direction: (0, 1, 0), target: (0, 0, 0))", "not both"),
        ("Spot(intensity: (1, -1, 1))", "intensity"),
    ] {
        let ron = format!("(camera: (), entities: [(name: \"spot\", light: {light})])");
        let mut app = app_from_ron(&ron, Overrides::default());
        let err = app.setup().expect_err(light).to_string();
        assert!(err.contains(needle) && err.contains("spot"), "{light}: {err}");
    }
}

/// A quad light (two triangles forming a parallelogram) is sampled as `o + u e1 + v e2`: every point lies on the
/// quad (within its error bound) and inside it, the points are uniform over its area (chi-square on an 8 x 8 grid
/// of the quad), a stratified grid of `u` lands one point per cell (the map keeps the sampler's strata), and the
/// solid-angle pdf is `dist^2 / (cos A)`.
#[test]
fn quad_light_points_are_uniform_on_the_quad_and_keep_the_strata() {
    let (lights, prims) = lights_of(&format!("(camera: (), entities: [{QUAD}, light: Area(radiance: (1, 1, 1)))])"));
    // The quad: x in [-0.3, 0.3], z in [-0.2, 0.2] at y = 1, facing -y; seen from below.
    let p = Vec3A::new(0.05, -0.5, 0.02);
    let cell = |q: Vec3A| {
        let (fx, fz) = ((q.x + 0.3) / 0.6, (q.z + 0.2) / 0.4);
        assert!((-1e-6..=1.0 + 1e-6).contains(&fx) && (-1e-6..=1.0 + 1e-6).contains(&fz), "point {q} off the quad");
        ((fx * 8.0).clamp(0.0, 7.0) as usize, (fz * 8.0).clamp(0.0, 7.0) as usize)
    };
    let mut rng = Rng::new(4, 4);
    let mut counts = vec![0f64; 64];
    let n = 64_000;
    for _ in 0..n {
        let ls = lights.sample_li(0, &prims, p, rng.next_2d()).expect("the quad faces p");
        assert!((ls.p.y - 1.0).abs() <= ls.p_err.y + 1e-7, "point {} off the plane (error bound {})", ls.p, ls.p_err);
        let d2 = (ls.p - p).length_squared();
        let pdf = d2 / (ls.wi.dot(Vec3A::NEG_Y).abs() * 0.24);
        assert!((ls.pdf - pdf).abs() <= 1e-3 * pdf, "pdf {} expected {pdf}", ls.pdf);
        let (i, j) = cell(ls.p);
        counts[j * 8 + i] += 1.0;
    }
    let (_, _, p_value) = crate::common::chi_square(&counts, &vec![n as f64 / 64.0; 64]);
    assert!(p_value > 1e-4, "points not uniform over the quad: p = {p_value}");
    // A stratified 8 x 8 grid of u: one point in every cell of the quad.
    let mut seen = vec![0; 64];
    for j in 0..8 {
        for i in 0..8 {
            let u = Vec2::new((i as f32 + 0.5) / 8.0, (j as f32 + 0.5) / 8.0);
            let (ci, cj) = cell(lights.sample_li(0, &prims, p, u).unwrap().p);
            seen[cj * 8 + ci] += 1;
        }
    }
    assert!(seen.iter().all(|&c| c == 1), "strata not kept: {seen:?}");
}
