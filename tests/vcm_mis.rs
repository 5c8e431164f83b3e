//! `vcm`'s multiple importance sampling on explicit paths: on random paths in random scenes (glossy and diffuse
//! walls, rough metal, plastic and glass spheres, two area lights of different power), the weights the renderer's
//! recursive bookkeeping gives every strategy that can build a path (emission hit, next-event estimation, each
//! connection, light tracing, merging at each vertex) sum to 1, and each equals the balance or power heuristic
//! written out as products of the strategies' densities (Veach 1997; Georgiev et al. 2012 for merging, whose
//! density is a connection's times `pi r^2 n_light` times the camera's density of the merged vertex).

use crate::common::app_from_ron;
use glam::{UVec2, Vec3A};
use prism::bsdf::TransportMode;
use prism::geometry::SurfaceHit;
use prism::lights::{EnvStrategy, LightSampler};
use prism::plugins::vcm::path_weights::{Iteration, Strategy, path_weights};
use prism::plugins::vcm::{Heuristic, VcmMode, VcmParams};
use prism::primitives::NO_LIGHT;
use prism::sampling::{PixelFilter, Rng};
use prism::scene::Scene;
use prism::settings::Overrides;

const MATERIALS: [&str; 6] = [
    "Lambert(albedo: (0.7, 0.5, 0.3))",
    "RoughConductor(alpha: 0.2, material: \"Au\")",
    "RoughConductor(alpha: 0.05, reflectance: (0.9, 0.9, 0.9))",
    "RoughPlastic(alpha: 0.15, ior: 1.5, diffuse: (0.2, 0.6, 0.3))",
    "RoughPlastic(alpha: 0.4, ior: 1.33, diffuse: 0.5)",
    "RoughDielectric(alpha: 0.3, ior: 1.5)",
];

/// A closed box with random materials on its walls and two spheres, a ceiling light and a dimmer one on the back.
fn random_scene(rng: &mut Rng) -> String {
    let mut pick = |glass: bool| {
        let n = if glass { MATERIALS.len() } else { MATERIALS.len() - 1 };
        format!("m{}", ((rng.next_f32() * n as f32) as usize).min(n - 1))
    };
    let m: Vec<String> = (0..7).map(|i| pick(i >= 5)).collect();
    let materials: Vec<String> = MATERIALS.iter().enumerate().map(|(i, s)| format!("\"m{i}\": {s}")).collect();
    format!(
        r#"(
    camera: (eye: (0, 0, 3.9), target: (0, 0, 0), up: (0, 1, 0), fov: 39.3, size: (64, 64)),
    render: (integrator: vcm),
    materials: {{ {mats}, "white": Lambert(albedo: 0.8) }},
    entities: [
        (shape: Quad(), material: "white", light: Area(radiance: (12, 10, 8)),
         transform: [Translate((0, 0.99, 0)), Rotate(axis: (1, 0, 0), degrees: 90), Scale((0.3, 0.25, 1))]),
        (shape: Quad(), material: "white", light: Area(radiance: (1, 2, 3)),
         transform: [Translate((0.4, 0.3, -0.99)), Scale((0.2, 0.2, 1))]),
        (shape: Quad(), material: "{m0}", transform: [Translate((0, -1, 0)), Rotate(axis: (1, 0, 0), degrees: -90)]),
        (shape: Quad(), material: "{m1}", transform: [Translate((0, 1, 0)), Rotate(axis: (1, 0, 0), degrees: 90)]),
        (shape: Quad(), material: "{m2}", transform: [Translate((0, 0, -1))]),
        (shape: Quad(), material: "{m3}", transform: [Translate((1, 0, 0)), Rotate(axis: (0, 1, 0), degrees: -90)]),
        (shape: Quad(), material: "{m4}", transform: [Translate((-1, 0, 0)), Rotate(axis: (0, 1, 0), degrees: 90)]),
        (shape: Sphere(center: (-0.4, -0.6, -0.2), radius: 0.35), material: "{m5}"),
        (shape: Sphere(center: (0.45, -0.5, 0.3), radius: 0.3), material: "{m6}"),
    ],
)"#,
        mats = materials.join(", "),
        m0 = m[0],
        m1 = m[1],
        m2 = m[2],
        m3 = m[3],
        m4 = m[4],
        m5 = m[5],
        m6 = m[6],
    )
}

/// A random path through a random pixel: camera vertices by BSDF sampling, `segments - 1` of them, then the last
/// one joined to a random point of a random light it sees (light point first in the returned order).
fn random_path(scene: &Scene, rng: &mut Rng, segments: usize) -> Option<(Vec<SurfaceHit>, UVec2)> {
    let cam = &scene.camera;
    let pixel = UVec2::new((rng.next_f32() * 64.0) as u32 % 64, (rng.next_f32() * 64.0) as u32 % 64);
    let film = pixel.as_vec2() + glam::Vec2::new(rng.next_f32(), rng.next_f32());
    let mut ray = cam.generate_ray(film);
    let mut hits = Vec::new();
    for _ in 0..segments - 1 {
        let hit = scene.trace(&ray)?;
        if hit.light != NO_LIGHT {
            return None;
        }
        let bsdf = scene.bsdf(&hit, -ray.dir)?;
        let bs =
            bsdf.sample_mode(rng.next_f32(), glam::Vec2::new(rng.next_f32(), rng.next_f32()), TransportMode::Radiance)?;
        if bs.delta || !(bs.pdf > 0.0 && bs.pdf.is_finite()) {
            return None;
        }
        hits.push(hit);
        ray = hit.spawn(bs.wi);
    }
    // The light point: towards a random point of a random light's quad, the hit must be that light.
    let last = *hits.last()?;
    let target = if rng.next_f32() < 0.5 {
        Vec3A::new(0.3 * (2.0 * rng.next_f32() - 1.0), 0.99, 0.25 * (2.0 * rng.next_f32() - 1.0))
    } else {
        Vec3A::new(0.4 + 0.2 * (2.0 * rng.next_f32() - 1.0), 0.3 + 0.2 * (2.0 * rng.next_f32() - 1.0), -0.99)
    };
    let to_light = (target - last.p).normalize();
    let light = scene.trace(&last.spawn(to_light))?;
    if light.light == NO_LIGHT || scene.emitted(&light, -to_light) == glam::Vec3::ZERO {
        return None;
    }
    hits.push(light);
    hits.reverse();
    Some((hits, pixel))
}

/// The strategies' densities written out (area measure at every vertex; `pL` from the light, `pE` from the eye),
/// and their heuristic weights.
fn heuristic_weights(
    scene: &Scene,
    mode: VcmMode,
    h: Heuristic,
    it: &Iteration,
    path: &[SurfaceHit],
    pixel: UVec2,
) -> Option<Vec<(Strategy, f64)>> {
    let k = path.len();
    let cam = &scene.camera;
    let lights = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
    let pos = |i: usize| if i == k { cam.eye() } else { path[i].p };
    let to = |a: usize, b: usize| (pos(b) - pos(a)).normalize();
    // A solid-angle density at `a` of the direction to `b` as an area density at `b`.
    let area = |pdf: f32, a: usize, b: usize| {
        let d = pos(b) - pos(a);
        pdf as f64 * path[b].ng.dot(d.normalize()).abs() as f64 / d.length_squared() as f64
    };
    let slot = path[0].light as usize;
    let (pos0, dir0) = scene.lights.pdf_le(slot, &scene.prims, path[0].p, path[0].ng, to(0, 1));
    let mut pl = vec![0f64; k];
    pl[0] = lights.choice.prob(slot) as f64 * pos0 as f64;
    pl[1] = area(dir0, 0, 1);
    for i in 1..k - 1 {
        let b = scene.bsdf(&path[i], to(i, i - 1))?;
        pl[i + 1] = area(b.pdf(to(i, i + 1)), i, i + 1);
    }
    let mut pe = vec![0f64; k];
    let (film, to_eye, dist, ray_pdf) = cam.project(path[k - 1].p)?;
    let density = it.filter.density(film - (pixel.as_vec2() + glam::Vec2::splat(0.5)));
    pe[k - 1] = (ray_pdf * density) as f64 * path[k - 1].ng.dot(to_eye).abs() as f64 / (dist * dist) as f64;
    for i in (1..k).rev() {
        let b = scene.bsdf(&path[i], to(i, i + 1))?;
        pe[i - 1] = area(b.pdf(to(i, i - 1)), i, i - 1);
    }
    let n = it.light_paths as f64;
    // A zero density is a direction the BSDF or the light does not scatter into: the path carries nothing.
    if !pl.iter().chain(&pe).all(|p| *p > 0.0 && p.is_finite()) {
        return None;
    }
    let connection = |s: usize| pl[..s].iter().product::<f64>() * pe[s..].iter().product::<f64>();
    let mut q: Vec<(Strategy, f64)> = Vec::new();
    let connects = matches!(mode, VcmMode::Bdpt | VcmMode::Vcm);
    let merges = matches!(mode, VcmMode::Bpm | VcmMode::Vcm);
    if connects {
        q.push((Strategy::Emission, connection(0)));
        q.push((Strategy::NextEvent, connection(1)));
        for s in 2..k {
            q.push((Strategy::Connection { s }, connection(s)));
        }
    }
    if connects || mode == VcmMode::Light {
        q.push((Strategy::LightTracing, n * connection(k)));
    }
    if merges {
        let eta = std::f64::consts::PI * (it.radius as f64).powi(2) * n;
        for (i, pe_i) in pe.iter().enumerate().skip(1) {
            q.push((Strategy::Merge { vertex: i }, eta * pe_i * connection(i + 1)));
        }
    }
    let m = |x: f64| if h == Heuristic::Power { x * x } else { x };
    let total: f64 = q.iter().map(|(_, x)| m(*x)).sum();
    Some(q.into_iter().map(|(s, x)| (s, m(x) / total)).collect())
}

#[test]
fn the_weights_of_every_strategy_that_builds_a_path_sum_to_one_and_are_the_heuristics() {
    let mut rng = Rng::new(0x5eed_u64, 7);
    let (mut checked, mut worst_sum, mut worst_weight) = (0usize, 0f64, 0f64);
    let mut kinds = std::collections::BTreeSet::new();
    for scene_no in 0..6 {
        let text = random_scene(&mut rng);
        let mut app = app_from_ron(&text, Overrides::default());
        app.setup().unwrap_or_else(|e| panic!("setup failed: {e}"));
        let scene = app.resources.scene.as_ref().unwrap();
        // A radius of a few pixel footprints and a light path count as the renderer would use them; the
        // radius is large enough that merging's weight is neither negligible nor dominant.
        let it = Iteration { light_paths: 4096, radius: 0.02 + 0.05 * rng.next_f32(), filter: PixelFilter::default() };
        let mut found = 0;
        for attempt in 0..4000 {
            if found >= 40 {
                break;
            }
            let segments = 2 + attempt % 5;
            let Some((path, pixel)) = random_path(scene, &mut rng, segments) else { continue };
            if heuristic_weights(scene, VcmMode::Vcm, Heuristic::Balance, &it, &path, pixel).is_none() {
                continue;
            }
            for mode in [VcmMode::Vcm, VcmMode::Bdpt, VcmMode::Bpm, VcmMode::Light] {
                for h in [Heuristic::Balance, Heuristic::Power] {
                    let params = VcmParams { mode, heuristic: h, ..VcmParams::default() };
                    let Some(expected) = heuristic_weights(scene, mode, h, &it, &path, pixel) else { continue };
                    let w = path_weights(scene, &params, &it, &path, pixel).expect("a path the renderer weighs");
                    let sum: f64 = w.iter().map(|(_, x)| *x as f64).sum();
                    assert!(
                        (sum - 1.0).abs() < 2e-3,
                        "scene {scene_no}, {mode:?} {h:?}, {} segments: weights sum to {sum}: {w:?}\nexpected {expected:?}",
                        path.len()
                    );
                    assert_eq!(w.len(), expected.len(), "{mode:?}: strategies {w:?} vs {expected:?}");
                    for ((s, x), (se, xe)) in w.iter().zip(&expected) {
                        assert_eq!(s, se);
                        let d = (*x as f64 - xe).abs();
                        assert!(
                            d < 2e-3,
                            "scene {scene_no}, {mode:?} {h:?}, {} segments, {s:?}: weight {x}, heuristic {xe}\n{w:?}\n{expected:?}",
                            path.len()
                        );
                        worst_weight = worst_weight.max(d);
                        if *x > 0.01 {
                            kinds.insert(format!("{s:?}").split([' ', '{']).next().unwrap().to_string());
                        }
                    }
                    worst_sum = worst_sum.max((sum - 1.0).abs());
                    checked += 1;
                }
            }
            found += 1;
        }
        assert!(found >= 20, "scene {scene_no}: only {found} random paths were usable");
    }
    assert!(checked >= 6 * 20 * 8, "{checked} path weighings");
    // Every kind of strategy carried real weight on some path.
    for k in ["Emission", "NextEvent", "Connection", "LightTracing", "Merge"] {
        assert!(kinds.contains(k), "no path gave {k} a weight above 1%: {kinds:?}");
    }
    eprintln!("{checked} path weighings; worst |sum - 1| {worst_sum:.2e}, worst weight difference {worst_weight:.2e}");
}
