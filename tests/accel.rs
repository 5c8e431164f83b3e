//! Every accelerator returns the same closest hit (t and primitive, up to exact ties) and the same occlusion
//! answer as brute force.

use crate::common::{app_from_ron, data};
use glam::Vec3A;
use prism::geometry::Ray;
use prism::primitives::Hit;
use prism::sampling::{Rng, warp};
use prism::scene::Scene;
use prism::settings::{AccelKind, Overrides};
use rayon::prelude::*;

/// The Stanford bunny (69k triangles) with analytic spheres (one an ellipsoid, one nested under a transformed
/// parent), a triangle, and two unbounded planes.
fn bunny_scene(kind: AccelKind) -> prism::App {
    let bunny = data("meshes/stanford-bunny.obj");
    let text = format!(
        r#"(camera: (),
        entities: [
            (shape: Mesh(path: "{}"), transform: [UniformScale(10)]),
            (shape: Sphere(center: (0.3, 1.0, 0.2), radius: 0.25)),
            (shape: Sphere(radius: 0.3), transform: [Translate((-0.8, 0.8, 0)), Scale((1, 2, 0.5))]),
            (transform: [Translate((0, 0.5, 0.8)), Rotate(axis: (0, 1, 0), degrees: 30)], children: [
                (shape: Sphere(radius: 0.2), transform: [Scale((0.5, 1, 1))]),
                (shape: Triangle(vertices: ((0, 0, 0), (0.5, 0, 0), (0, 0.5, 0.1)))),
            ]),
            (shape: Plane(normal: (0, 1, 0), offset: 0.33)),
            (shape: Plane(normal: (1, 0, 1), offset: -1.2)),
        ])"#,
        bunny.display()
    );
    let mut app = app_from_ron(&text, Overrides { accel: Some(kind), ..Default::default() });
    app.setup().unwrap();
    app
}

/// Random rays: half aimed at random points of random primitives (so they hit), half random.
fn rays(scene: &Scene, n: usize, seed: u64) -> Vec<Ray> {
    let b = scene.prims.bounds;
    let ext = b.diagonal() * 0.6;
    let mut rng = Rng::new(seed, 0);
    (0..n)
        .map(|i| {
            let o =
                b.min - ext + (b.diagonal() + 2.0 * ext) * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let d = if i % 2 == 0 {
                let id = rng.below(scene.prims.num_bounded());
                let pb = scene.prims.prim_bounds(id);
                let target = pb.min + pb.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                (target - o).normalize()
            } else {
                warp::uniform_sphere(rng.next_2d())
            };
            let tmax = if i % 5 == 0 { rng.next_f32() * b.diagonal().length() } else { f32::INFINITY };
            Ray::with_tmax(o, d, tmax)
        })
        .collect()
}

fn same_hit(a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => (a.t - b.t).abs() <= 1e-5 * a.t.abs().max(1e-6) && (a.prim == b.prim || a.t == b.t),
        _ => false,
    }
}

#[test]
fn bvh_matches_brute_force_on_1e5_rays_over_the_stanford_bunny_spheres_and_planes() {
    let bvh = bunny_scene(AccelKind::Bvh);
    let brute = bunny_scene(AccelKind::Brute);
    let (sb, sf) = (bvh.resources.scene.as_ref().unwrap(), brute.resources.scene.as_ref().unwrap());
    assert!(sb.prims.num_tris() > 69_000, "bunny loaded: {} triangles", sb.prims.num_tris());
    assert_eq!(sb.prims.spheres.len(), 3);
    assert_eq!(sb.prims.planes.len(), 2);
    assert!(sb.prims.spheres.iter().filter(|s| s.transform.is_some()).count() == 2, "two ellipsoids");
    let rays = rays(sb, 100_000, 1);
    let mismatches: Vec<String> = rays
        .par_iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let (a, b) = (sb.intersect(r), sf.intersect(r));
            let (oa, ob) = (sb.occluded(r), sf.occluded(r));
            (!same_hit(a, b) || oa != ob).then(|| format!("ray {i}: bvh {a:?}/{oa} brute {b:?}/{ob}"))
        })
        .collect();
    let hits = rays.iter().filter(|r| sb.intersect(r).is_some()).count();
    assert!(hits > 40_000, "too few rays hit anything ({hits}): the test would be weak");
    assert!(
        mismatches.is_empty(),
        "{} mismatches, first: {:?}",
        mismatches.len(),
        &mismatches[..mismatches.len().min(5)]
    );
}
