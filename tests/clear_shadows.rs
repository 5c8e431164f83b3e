//! Shadow rays proven clear without tracing them (`prism::lights::ClearShadows`): every proof must be one the
//! occlusion query agrees with (a proven ray is never blocked), on the box scenes and on a cluttered random scene
//! built to put occluders beside the proofs' hulls; the proofs must cover a good share of the Cornell box's shadow
//! rays (or they buy nothing); and the separation test they rest on (GJK, checked on the points) answers as the
//! geometry says.

use crate::accel::{scene, setup_file, setup_ron};
use crate::common::scene_path;
use glam::{DVec3, Vec3A};
use prism::geometry::{Ray, hulls_apart};
use prism::lights::{EnvStrategy, LightSampler};
use prism::sampling::Rng;
use prism::scene::Scene;
use prism::settings::AccelKind;

/// Shadow-ray queries from random surface points to random light samples: (queries, proven clear, blocked).
/// Panics on the first proven ray the occlusion query finds blocked.
fn check_proofs(scene: &Scene, vertices: usize, seed: u64) -> (usize, usize, usize) {
    let sampler = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
    assert!(sampler.clear.is_some(), "the scene should be covered");
    let b = scene.prims.bounds;
    let mut rng = Rng::new(seed, 1);
    let (mut queries, mut proven, mut blocked) = (0, 0, 0);
    for _ in 0..vertices {
        let o = b.min + (b.max - b.min) * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let d = Vec3A::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5);
        if d.length_squared() < 1e-4 {
            continue;
        }
        let Some(s) = scene.trace(&Ray::new(o, d.normalize())) else { continue };
        for _ in 0..4 {
            let n = s.ng;
            let Some((ls, slot)) =
                sampler.sample_li(&scene.lights, &scene.prims, s.p, n, rng.next_f32(), rng.next_2d())
            else {
                continue;
            };
            if ls.pdf <= 0.0 {
                continue;
            }
            queries += 1;
            let ray = ls.shadow_ray(&s);
            let occluded = scene.occluded(&ray);
            blocked += occluded as usize;
            // A key is proved once it has been asked often enough to be worth it: ask until it has.
            let proven_now = (0..=200).any(|_| sampler.proven_clear(&s, slot));
            if proven_now {
                proven += 1;
                assert!(
                    !occluded,
                    "a shadow ray proven clear is blocked: from {:?} (primitive {}) to {:?} (light {slot})",
                    s.p, s.prim, ls.p
                );
            }
        }
    }
    (queries, proven, blocked)
}

#[test]
fn proven_shadow_rays_are_never_blocked_in_the_box_scenes() {
    for (name, min_share) in [("cornell_box.ron", 0.4), ("cornell_rough.ron", 0.3), ("cornell_caustic.ron", 0.3)] {
        let app = setup_file(&scene_path(name), AccelKind::Bvh);
        let (queries, proven, blocked) = check_proofs(scene(&app), 60_000, 11);
        eprintln!("{name}: {queries} shadow rays, {proven} proven clear, {blocked} blocked");
        assert!(blocked > queries / 50, "{name}: the scene should have shadows ({blocked} of {queries} blocked)");
        let share = proven as f64 / queries as f64;
        assert!(share >= min_share, "{name}: only {share:.2} of the shadow rays proven clear");
    }
}

/// A room with a quad light, a point light and 150 small random triangles, two spheres and a plane between them:
/// occluders beside and across the proofs' hulls everywhere.
#[test]
fn proven_shadow_rays_are_never_blocked_among_clutter() {
    let mut rng = Rng::new(5, 9);
    let mut clutter = String::new();
    for _ in 0..150 {
        let c = Vec3A::new(rng.next_f32() * 1.8 - 0.9, rng.next_f32() * 1.6 - 0.95, rng.next_f32() * 1.8 - 0.9);
        let v: Vec<Vec3A> = (0..3)
            .map(|_| c + Vec3A::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5) * 0.25)
            .collect();
        clutter += &format!(
            "(shape: Triangle(vertices: (({}, {}, {}), ({}, {}, {}), ({}, {}, {})))),\n",
            v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z
        );
    }
    let text = format!(
        r#"(camera: (eye: (0, 0, 3.9)), materials: {{ "w": Lambert(albedo: (0.7, 0.7, 0.7)) }},
        entities: [
            (shape: Quad(), light: Area(radiance: (5, 5, 5)),
             transform: [Translate((0.1, 0.98, 0)), Rotate(axis: (1, 0, 0), degrees: 90), Scale((0.3, 0.2, 1))]),
            (light: Point(intensity: (2, 2, 2)), transform: [Translate((-0.5, 0.5, 0.4))]),
            (shape: Quad(), material: "w", transform: [Translate((0, -1, 0)), Rotate(axis: (1, 0, 0), degrees: -90)]),
            (shape: Quad(), material: "w", transform: [Translate((0, 0, -1))]),
            (shape: Quad(), material: "w", transform: [Translate((-1, 0, 0)), Rotate(axis: (0, 1, 0), degrees: 90)]),
            (shape: Sphere(radius: 0.15), material: "w", transform: [Translate((0.3, -0.2, 0.1))]),
            (shape: Sphere(radius: 0.1), material: "w", transform: [Translate((-0.4, 0.3, -0.3))]),
            {clutter}
        ])"#
    );
    let app = setup_ron(&text, AccelKind::Bvh);
    let (queries, proven, blocked) = check_proofs(scene(&app), 60_000, 12);
    eprintln!("clutter: {queries} shadow rays, {proven} proven clear, {blocked} blocked");
    assert!(proven > queries / 20 && blocked > queries / 20, "both outcomes should be common");
}

fn cube(c: DVec3, h: f64) -> Vec<DVec3> {
    (0..8)
        .map(|i| {
            let pick = |bit: u32| if i & bit == 0 { -h } else { h };
            c + DVec3::new(pick(1), pick(2), pick(4))
        })
        .collect()
}

#[test]
fn separated_hulls_are_apart_by_their_distance_and_no_more() {
    let a = cube(DVec3::ZERO, 1.0);
    // Two cubes a unit apart along x: apart by any gap below 1, not by one above.
    let b = cube(DVec3::new(3.0, 0.5, 0.0), 1.0);
    assert!(hulls_apart(&a, &b, 0.99) && hulls_apart(&b, &a, 0.99));
    assert!(!hulls_apart(&a, &b, 1.01));
    // A segment and a triangle whose nearest edge passes 0.5 from it.
    let seg = [DVec3::ZERO, DVec3::new(0.0, 2.0, 0.0)];
    let tri = [DVec3::new(0.5, 1.0, -1.0), DVec3::new(0.5, 1.0, 1.0), DVec3::new(2.0, 1.0, 0.0)];
    assert!(hulls_apart(&seg, &tri, 0.49));
    assert!(!hulls_apart(&seg, &tri, 0.51));
    // Diagonal closest features (edge against edge): distance sqrt(2) / 2 between the skew segments.
    let e1 = [DVec3::new(-1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0)];
    let e2 = [DVec3::new(0.0, -1.0, 0.5_f64.sqrt()), DVec3::new(0.0, 1.0, 0.5_f64.sqrt())];
    assert!(hulls_apart(&e1, &e2, 0.7) && !hulls_apart(&e1, &e2, 0.71));
}

#[test]
fn touching_or_overlapping_hulls_are_not_apart() {
    let a = cube(DVec3::ZERO, 1.0);
    assert!(!hulls_apart(&a, &cube(DVec3::new(1.5, 0.2, 0.1), 1.0), 0.0), "overlapping cubes");
    assert!(!hulls_apart(&a, &cube(DVec3::new(2.0, 0.0, 0.0), 1.0), 0.0), "cubes sharing a face");
    let through = [DVec3::new(-5.0, 0.0, -5.0), DVec3::new(5.0, 0.0, -5.0), DVec3::new(0.0, 0.0, 5.0)];
    assert!(!hulls_apart(&a, &through, 0.0), "a triangle through the cube");
    // A triangle piercing a thin tetrahedron-like hull without containing any of its points.
    let hull = [DVec3::new(0.0, -1.0, 0.0), DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.1, 0.0, 1.0)];
    let pierce = [DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 3.0)];
    assert!(!hulls_apart(&hull, &pierce, 0.0));
    // Random pairs: whenever the answer is "apart", no two points of the hulls (random convex combinations of
    // their corners) come within the gap.
    let mut rng = Rng::new(2, 2);
    let mut r = || rng.next_f32() as f64;
    for _ in 0..2000 {
        let p: Vec<DVec3> = (0..5).map(|_| DVec3::new(r(), r(), r())).collect();
        let off = DVec3::new(r() * 1.5, r() * 1.5, r() * 1.5);
        let q: Vec<DVec3> = (0..3).map(|_| DVec3::new(r(), r(), r()) * 0.6 + off).collect();
        let gap = 0.02;
        if hulls_apart(&p, &q, gap) {
            for _ in 0..200 {
                let comb = |pts: &[DVec3], w: &mut dyn FnMut() -> f64| {
                    let ws: Vec<f64> = pts.iter().map(|_| w()).collect();
                    let sum: f64 = ws.iter().sum();
                    pts.iter().zip(&ws).map(|(p, w)| *p * (w / sum)).sum::<DVec3>()
                };
                let (x, y) = (comb(&p, &mut r), comb(&q, &mut r));
                assert!((x - y).length() > gap, "points {x} and {y} of hulls called apart");
            }
        }
    }
}
