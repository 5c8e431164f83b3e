//! Every accelerator returns the same closest hit (t within 1e-5 relative; the same primitive unless both
//! primitives are hit at the same distance) and the same occlusion answer as brute force, on real scenes (the
//! Stanford bunny with spheres, ellipsoids and planes; the 6.837 bunnies; teapot in a stadium) and hostile ones
//! (coplanar triangles, rays along grid cell borders and kd-tree planes, through shared vertices and edges,
//! axis-parallel rays, rays starting inside). Degenerate input keeps the kd-tree and the grid small.

use crate::common::{app_from_file, app_from_ron, data};
use glam::Vec3A;
use prism::accel::{Accel, KdTree, TraversalWork, UniformGrid};
use prism::geometry::{Ray, WatertightRay};
use prism::primitives::Hit;
use prism::ray_sets::{camera_rays, secondary_rays};
use prism::sampling::{Rng, warp};
use prism::scene::Scene;
use prism::settings::{AccelKind, GridResolution, Overrides};
use rayon::prelude::*;

/// The accelerators compared with brute force: BVH, kd-tree, grid with automatic resolution and a coarse
/// fixed-resolution grid (primitives spanning many cells exercise the mailboxes).
pub fn accelerators() -> Vec<AccelKind> {
    vec![
        AccelKind::Bvh,
        AccelKind::CwBvh,
        AccelKind::KdTree,
        AccelKind::Grid(GridResolution::Auto),
        AccelKind::Grid(GridResolution::Fixed([7, 5, 3])),
    ]
}

/// The Stanford bunny (69k triangles) with analytic spheres (one an ellipsoid, one nested under a transformed
/// parent), a triangle, and two unbounded planes.
pub fn bunny_scene_text() -> String {
    format!(
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
        data("meshes/stanford-bunny.obj").display()
    )
}

pub fn setup_ron(text: &str, kind: AccelKind) -> prism::App {
    let mut app = app_from_ron(text, Overrides { accel: Some(kind), ..Default::default() });
    app.setup().unwrap_or_else(|e| panic!("setup failed: {e}"));
    app
}

pub fn setup_file(path: &std::path::Path, kind: AccelKind) -> prism::App {
    let mut app = app_from_file(path, Overrides { accel: Some(kind), ..Default::default() });
    app.setup().unwrap_or_else(|e| panic!("setup of {} failed: {e}", path.display()));
    app
}

pub fn scene(app: &prism::App) -> &Scene {
    app.resources.scene.as_ref().unwrap()
}

/// Random rays: half aimed at random points of random primitives (so they hit), half random; origins around and
/// inside the bounds; every 7th ray axis-parallel, every 5th with a finite `tmax`.
pub fn rays(scene: &Scene, n: usize, seed: u64) -> Vec<Ray> {
    let b = scene.prims.bounds;
    // Origins around the bounds, at least 0.3 of the largest extent away along flat axes too.
    let ext = (b.diagonal() * 0.6).max(Vec3A::splat(b.diagonal().max_element() * 0.3));
    let mut rng = Rng::new(seed, 0);
    (0..n)
        .map(|i| {
            let o =
                b.min - ext + (b.diagonal() + 2.0 * ext) * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let mut d = if i % 2 == 0 && scene.prims.num_bounded() > 0 {
                let id = rng.below(scene.prims.num_bounded());
                let pb = scene.prims.prim_bounds(id);
                let target = pb.min + pb.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                (target - o).normalize_or(Vec3A::X)
            } else {
                warp::uniform_sphere(rng.next_2d())
            };
            if i % 7 == 3 {
                let a = rng.below(3) as usize;
                let s = if d[a] < 0.0 { -1.0 } else { 1.0 };
                d = Vec3A::ZERO;
                d[a] = s;
            }
            let tmax = if i % 5 == 0 { rng.next_f32() * b.diagonal().length() } else { f32::INFINITY };
            Ray::with_tmax(o, d, tmax)
        })
        .collect()
}

/// Same closest hit: both none, or t within 1e-5 relative and the same primitive unless it is a tie (the other
/// primitive, tested alone, is hit at the same distance within 1e-6 relative).
pub fn same_hit(scene: &Scene, ray: &Ray, a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            if (a.t - b.t).abs() > 1e-5 * b.t.abs().max(1e-6) {
                return false;
            }
            if a.prim == b.prim || a.t == b.t {
                return true;
            }
            a.prim < scene.prims.num_bounded()
                && scene
                    .prims
                    .intersect_bounded(a.prim, ray, &WatertightRay::new(ray))
                    .is_some_and(|h| (h.t - b.t).abs() <= 1e-6 * b.t.abs())
        }
        _ => false,
    }
}

/// Compare `scene` (some accelerator) with `truth` (brute force) on `rays`; panics listing the first mismatches.
/// Rays whose origin lies on a surface (brute force hits it at t < 1e-6 of the scene size: a self-intersection,
/// which Prism's spawned rays avoid by construction and whose answer is decided by rounding) are left out; they
/// must stay few. Returns the number of rays that hit something.
pub fn assert_matches_brute(label: &str, scene: &Scene, truth: &Scene, rays: &[Ray]) -> usize {
    let expected: Vec<(Option<Hit>, bool)> = rays.par_iter().map(|r| (truth.intersect(r), truth.occluded(r))).collect();
    let eps = 1e-6 * truth.prims.bounds.diagonal().length();
    let on_surface = |h: &Option<Hit>| h.is_some_and(|h| h.t < eps);
    let skipped = expected.iter().filter(|(h, _)| on_surface(h)).count();
    assert!(skipped * 20 <= rays.len(), "{label}: {skipped} of {} rays start on a surface", rays.len());
    let mismatches: Vec<String> = rays
        .par_iter()
        .zip(expected.par_iter())
        .enumerate()
        .filter(|(_, (_, (b, _)))| !on_surface(b))
        .filter_map(|(i, (r, &(b, ob)))| {
            let a = scene.intersect(r);
            let oa = scene.occluded(r);
            let mut work = TraversalWork::default();
            let c = scene.accel.intersect_counted(&scene.prims, r, &mut work);
            let counted_ok = c.map(|h| (h.prim, h.t.to_bits()))
                == scene.accel.intersect(&scene.prims, r).map(|h| (h.prim, h.t.to_bits()));
            (!same_hit(truth, r, a, b) || oa != ob || !counted_ok)
                .then(|| format!("ray {i} {r:?}: {a:?}/{oa} brute {b:?}/{ob} counted {c:?}"))
        })
        .collect();
    assert!(
        mismatches.is_empty(),
        "{label}, {}: {} of {} rays differ from brute force, first: {:#?}",
        scene.accel.stats().kind,
        mismatches.len(),
        rays.len(),
        &mismatches[..mismatches.len().min(4)]
    );
    expected.iter().filter(|(h, _)| h.is_some()).count()
}

/// Every accelerator against brute force on one scene built by `make`.
fn check_all(label: &str, make: impl Fn(AccelKind) -> prism::App, n_rays: usize, min_hits: usize) {
    let truth_app = make(AccelKind::Brute);
    let truth = scene(&truth_app);
    let rays = rays(truth, n_rays, 7);
    for kind in accelerators() {
        let app = make(kind);
        let hits = assert_matches_brute(label, scene(&app), truth, &rays);
        assert!(hits >= min_hits, "{label}: only {hits} of {n_rays} rays hit: the test would be weak");
    }
}

#[test]
fn every_accelerator_matches_brute_force_on_the_stanford_bunny_with_spheres_ellipsoids_and_planes() {
    let text = bunny_scene_text();
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    assert!(truth.prims.num_tris() > 69_000, "bunny loaded: {} triangles", truth.prims.num_tris());
    assert_eq!(truth.prims.spheres.len(), 3);
    assert_eq!(truth.prims.planes.len(), 2);
    assert_eq!(truth.prims.spheres.iter().filter(|s| s.transform.is_some()).count(), 2, "two ellipsoids");
    let rays = rays(truth, 20_000, 1);
    for kind in accelerators() {
        let app = setup_ron(&text, kind);
        let hits = assert_matches_brute("bunny", scene(&app), truth, &rays);
        assert!(hits > 8_000, "too few rays hit anything ({hits}): the test would be weak");
    }
}

#[test]
fn every_accelerator_matches_brute_force_on_every_6837_scene_of_assignments_2_to_5() {
    for path in crate::mit6837::scenes(2, 5) {
        let truth_app = setup_file(&path, AccelKind::Brute);
        let truth = scene(&truth_app);
        // Camera rays, their diffuse bounces and shadow rays, and random rays.
        let camera = camera_rays(truth, 40, 40);
        let (bounce, shadow) = secondary_rays(truth, &camera, 3);
        let mut all = camera;
        all.extend(bounce);
        all.extend(shadow);
        all.extend(rays(truth, 1_500, 5));
        for kind in accelerators() {
            let app = setup_file(&path, kind);
            assert_matches_brute(&path.display().to_string(), scene(&app), truth, &all);
        }
    }
}

#[test]
fn every_accelerator_matches_brute_force_on_the_6837_bunnies() {
    for n in ["200", "1k", "5k", "40k"] {
        let path = data(&format!("mit6837/assignment5/bunny_{n}.obj"));
        check_all(&format!("bunny_{n}"), |k| setup_file(&path, k), 10_000, 3_000);
    }
}

/// The teapot (6320 triangles, about 6 units wide) inside a closed box 10^4 times larger.
pub fn teapot_in_stadium_text() -> String {
    format!(
        r#"(camera: (eye: (0, 3, 12), target: (0, 1, 0)),
        entities: [
            (shape: Mesh(path: "{}")),
            (shape: Cube, transform: [UniformScale(30000)]),
        ])"#,
        data("meshes/teapot.obj").display()
    )
}

#[test]
fn every_accelerator_matches_brute_force_on_the_teapot_in_a_stadium() {
    let text = teapot_in_stadium_text();
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    assert_eq!(truth.prims.num_tris(), 6320 + 12);
    // Rays from around the teapot: random directions (most hit the stadium), and aimed at teapot triangles.
    let mut rng = Rng::new(3, 3);
    let rays: Vec<Ray> = (0..10_000)
        .map(|i| {
            let o = Vec3A::new(rng.next_f32() * 20.0 - 10.0, rng.next_f32() * 10.0 - 2.0, rng.next_f32() * 20.0 - 10.0);
            let d = if i % 2 == 0 {
                let t = truth.prims.tris[rng.below(6320) as usize];
                ((t[0] + t[1] + t[2]) / 3.0 - o).normalize()
            } else {
                warp::uniform_sphere(rng.next_2d())
            };
            Ray::new(o, d)
        })
        .collect();
    for kind in accelerators() {
        let app = setup_ron(&text, kind);
        assert_matches_brute("teapot in a stadium", scene(&app), truth, &rays);
    }
}

/// A 40 x 40 tessellated square in the plane z = 0 (3200 coplanar triangles sharing vertices and edges).
fn coplanar_text() -> String {
    let mut tris = String::new();
    let n = 40;
    let v = |i: i32, j: i32| format!("({}, {}, 0)", i as f32 * 0.25 - 5.0, j as f32 * 0.25 - 5.0);
    for i in 0..n {
        for j in 0..n {
            tris += &format!(
                "(shape: Triangle(vertices: ({}, {}, {}))), (shape: Triangle(vertices: ({}, {}, {}))),\n",
                v(i, j),
                v(i + 1, j),
                v(i + 1, j + 1),
                v(i, j),
                v(i + 1, j + 1),
                v(i, j + 1)
            );
        }
    }
    format!("(camera: (), entities: [{tris}])")
}

#[test]
fn coplanar_triangles_rays_through_shared_vertices_and_edges_and_in_the_plane_match_brute_force() {
    let text = coplanar_text();
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    let mut rng = Rng::new(5, 5);
    let mut rays = Vec::new();
    for i in 0..=40 {
        for j in 0..=40 {
            let vertex = Vec3A::new(i as f32 * 0.25 - 5.0, j as f32 * 0.25 - 5.0, 0.0);
            let edge_mid = vertex + Vec3A::new(0.125, 0.0, 0.0);
            let diag_mid = vertex + Vec3A::new(0.125, 0.125, 0.0);
            for target in [vertex, edge_mid, diag_mid] {
                // From above, from below, tilted, and exactly perpendicular.
                let o = target + Vec3A::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 2.0 * rng.next_f32() + 0.5);
                rays.push(Ray::new(o, (target - o).normalize()));
                rays.push(Ray::new(target + Vec3A::Z * 3.0, -Vec3A::Z));
                rays.push(Ray::new(target - Vec3A::Z * 3.0, Vec3A::Z));
            }
            // In the plane itself (grazing: only the watertight edge rules decide).
            rays.push(Ray::new(vertex - Vec3A::X * 7.0, Vec3A::X));
        }
    }
    rays.extend(self::rays(truth, 5_000, 11));
    for kind in accelerators() {
        let app = setup_ron(&text, kind);
        let hits = assert_matches_brute("coplanar", scene(&app), truth, &rays);
        assert!(hits > rays.len() / 2, "{hits} hits");
    }
}

/// Cubes on a lattice, a grid whose cell faces fall between and on them; rays exactly along cell borders (in a
/// face plane, on cell edges, through cell corners), starting inside the grid, axis-parallel, and rays in
/// kd-tree split planes.
#[test]
fn rays_along_grid_cell_borders_and_kd_tree_planes_match_brute_force() {
    let mut entities = String::new();
    for x in 0..5 {
        for y in 0..4 {
            for z in 0..3 {
                entities += &format!(
                    "(shape: Cube, transform: [Translate(({}, {}, {})), UniformScale(0.3)]),",
                    x as f32 * 1.1,
                    y as f32 * 0.9,
                    z as f32 * 1.3
                );
            }
        }
    }
    entities += "(shape: Sphere(center: (2, 1.5, 1.3), radius: 0.4)),";
    let text = format!("(camera: (), entities: [{entities}])");
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    for res in [[5, 4, 3], [10, 8, 6], [1, 1, 1], [17, 3, 2]] {
        let app = setup_ron(&text, AccelKind::Grid(GridResolution::Fixed(res)));
        let s = scene(&app);
        let Accel::Grid(grid) = &s.accel else { panic!("not a grid") };
        assert_eq!(grid.resolution(), res);
        let b = grid.bounds();
        let mut rng = Rng::new(9, 9);
        let mut rays = Vec::new();
        let faces = |a: usize| (0..=res[a]).map(|k| grid.face_position(a, k)).collect::<Vec<f32>>();
        let (fx, fy, fz) = (faces(0), faces(1), faces(2));
        for &x in &fx {
            for &y in &fy {
                // Along a cell edge (two border planes at once), both ways, from outside and from inside.
                rays.push(Ray::new(Vec3A::new(x, y, b.min.z - 1.0), Vec3A::Z));
                rays.push(Ray::new(Vec3A::new(x, y, b.max.z + 1.0), -Vec3A::Z));
                rays.push(Ray::new(Vec3A::new(x, y, b.center().z), Vec3A::Z));
                for &z in &fz {
                    // Through a cell corner, diagonally, starting inside the grid at the corner.
                    let c = Vec3A::new(x, y, z);
                    let d = warp::uniform_sphere(rng.next_2d());
                    rays.push(Ray::new(c, d));
                    rays.push(Ray::new(c - d * 20.0, d));
                }
            }
            // In a face plane x = const, directions within the plane.
            for _ in 0..8 {
                let o = Vec3A::new(x, b.min.y + rng.next_f32() * b.diagonal().y, b.min.z + rng.next_f32() * 4.0);
                let phi = rng.next_f32() * std::f32::consts::TAU;
                rays.push(Ray::new(o, Vec3A::new(0.0, phi.cos(), phi.sin())));
            }
        }
        for &y in &fy {
            for _ in 0..8 {
                let o = Vec3A::new(b.min.x + rng.next_f32() * b.diagonal().x, y, b.min.z + rng.next_f32() * 4.0);
                let phi = rng.next_f32() * std::f32::consts::TAU;
                rays.push(Ray::new(o, Vec3A::new(phi.cos(), 0.0, phi.sin())));
            }
        }
        rays.extend(self::rays(truth, 3_000, 13));
        assert_matches_brute(&format!("cell borders {res:?}"), s, truth, &rays);
    }
    // Rays in and onto the kd-tree's split planes.
    let app = setup_ron(&text, AccelKind::KdTree);
    let s = scene(&app);
    let Accel::KdTree(kd) = &s.accel else { panic!("not a kd-tree") };
    let b = s.prims.bounds;
    let mut rng = Rng::new(10, 10);
    let mut rays = Vec::new();
    for n in kd.nodes().iter().filter(|n| !n.is_leaf()).take(300) {
        let (axis, split) = (n.axis(), n.split());
        for _ in 0..6 {
            let mut o = b.min + b.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            o[axis] = split;
            let mut d = warp::uniform_sphere(rng.next_2d());
            rays.push(Ray::new(o, d));
            d[axis] = 0.0;
            rays.push(Ray::new(o, d.normalize()));
            rays.push(Ray::new(o - d.normalize() * 10.0, d.normalize()));
        }
    }
    assert_matches_brute("kd-tree planes", s, truth, &rays);
}

fn tri_entity(v: [[f32; 3]; 3]) -> String {
    format!(
        "(shape: Triangle(vertices: (({}, {}, {}), ({}, {}, {}), ({}, {}, {})))),",
        v[0][0], v[0][1], v[0][2], v[1][0], v[1][1], v[1][2], v[2][0], v[2][1], v[2][2]
    )
}

#[test]
fn degenerate_input_keeps_the_kd_tree_and_grid_small_and_correct() {
    // 2000 identical triangles; 500 huge overlapping triangles through one region; 3000 triangles in one plane.
    let mut rng = Rng::new(4, 4);
    let identical: String =
        (0..2000).map(|_| tri_entity([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])).collect();
    let huge: String = (0..500)
        .map(|_| {
            let mut v = [[0.0; 3]; 3];
            for p in v.iter_mut() {
                for c in p.iter_mut() {
                    *c = (rng.next_f32() - 0.5) * 1000.0;
                }
            }
            tri_entity(v)
        })
        .collect();
    let planar: String = (0..3000)
        .map(|_| {
            let (x, y) = (rng.next_f32() * 10.0, rng.next_f32() * 10.0);
            tri_entity([[x, y, 2.0], [x + rng.next_f32(), y, 2.0], [x, y + rng.next_f32() + 0.01, 2.0]])
        })
        .collect();
    for (label, entities, n) in
        [("identical", &identical, 2000), ("huge overlapping", &huge, 500), ("coplanar", &planar, 3000)]
    {
        let text = format!("(camera: (), entities: [{entities}])");
        let truth_app = setup_ron(&text, AccelKind::Brute);
        let truth = scene(&truth_app);
        let rays = rays(truth, 3_000, 21);
        for kind in accelerators() {
            let app = setup_ron(&text, kind);
            assert_matches_brute(label, scene(&app), truth, &rays);
        }
        let kd = KdTree::build(&truth.prims);
        assert!(kd.depth() <= 40, "{label}: kd-tree depth {}", kd.depth());
        assert!(kd.references() <= 64 * n, "{label}: {} kd-tree references for {n} triangles", kd.references());
        let grid = UniformGrid::build(&truth.prims, GridResolution::Auto).unwrap();
        assert!(grid.references() <= 64 * n, "{label}: {} grid references for {n} triangles", grid.references());
    }
}

#[test]
fn bad_grid_resolutions_are_errors_not_panics() {
    let text = "(camera: (), entities: [(shape: Sphere())])";
    for res in [[0, 4, 4], [10_000, 1, 1], [4096, 4096, 4]] {
        let mut app = app_from_ron(
            text,
            Overrides { accel: Some(AccelKind::Grid(GridResolution::Fixed(res))), ..Default::default() },
        );
        let err = app.setup().err().unwrap_or_else(|| panic!("{res:?} accepted")).to_string();
        assert!(err.contains("grid resolution"), "{res:?}: {err}");
    }
}

#[test]
fn counted_traversal_reports_work_for_every_accelerator() {
    let text = bunny_scene_text();
    for kind in [AccelKind::Bvh, AccelKind::KdTree, AccelKind::Grid(GridResolution::Auto), AccelKind::Brute] {
        let app = setup_ron(&text, kind);
        let s = scene(&app);
        let ray = Ray::new(Vec3A::new(0.0, 1.0, 5.0), Vec3A::new(0.0, 0.0, -1.0));
        let mut work = TraversalWork::default();
        s.accel.intersect_counted(&s.prims, &ray, &mut work);
        assert!(work.prims > 0, "{kind:?}: {work:?}");
        if kind != AccelKind::Brute {
            assert!(work.nodes > 0 && (work.prims as u64) < s.prims.num_bounded() as u64 / 10, "{kind:?}: {work:?}");
        }
    }
}

/// Surfaces of revolution (the vase under a non-uniform scale and a rotation, the torus tilted) and Bézier
/// patches (the teapot's, and the 6.837 patch scaled), with spheres, an ellipsoid, a quad and a plane.
fn curved_scene_text() -> String {
    format!(
        r#"(camera: (eye: (0, 4, 14), target: (0, 0, 0)),
        entities: [
            (transform: [Translate((-4, 0, 0)), Rotate(axis: (0, 0, 1), degrees: 20), Scale((0.6, 0.5, 0.8))],
             shape: Revolution(profile: BSpline([(0, -3, 0), (0, -3, 0), (0, -3, 0), (1.5, -3, 0), (2.5, 4, 0),
                 (3, 4, 0), (2, -4, 0), (0, -4, 0), (0, -4, 0), (0, -4, 0)]))),
            (transform: [Translate((3, 2, 0)), Rotate(axis: (1, 0, 0), degrees: 60), UniformScale(0.5)],
             shape: Splines(path: "{}")),
            (transform: [Translate((1, -2, 1))], shape: Splines(path: "{}")),
            (transform: [Translate((-2, 2.5, -2)), Scale((1, 0.5, 1))], shape: Splines(path: "{}")),
            (shape: Sphere(center: (0, 3, 0), radius: 0.7)),
            (shape: Sphere(radius: 0.5), transform: [Translate((4, -1, 2)), Scale((2, 0.5, 1))]),
            (shape: Quad(), transform: [Translate((0, 0, -3)), UniformScale(2)]),
            (shape: Plane(normal: (0, 1, 0), offset: -5)),
        ])"#,
        data("mit6837/assignment8/spline8_06_torus.txt").display(),
        data("mit6837/assignment8/spline8_09_teapot.txt").display(),
        data("mit6837/assignment8/spline8_08_bezier_patch.txt").display(),
    )
}

#[test]
fn every_accelerator_matches_brute_force_on_surfaces_of_revolution_and_bezier_patches() {
    let text = curved_scene_text();
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    assert_eq!(truth.prims.revolutions.len(), 1 + 1 + 2, "vase, torus, the teapot's body and lid");
    assert_eq!(truth.prims.patches.len(), 8 + 1);
    let camera = camera_rays(truth, 48, 48);
    let (bounce, shadow) = secondary_rays(truth, &camera, 3);
    let mut all = rays(truth, 6_000, 21);
    all.extend(camera);
    all.extend(bounce);
    all.extend(shadow);
    for kind in accelerators() {
        let app = setup_ron(&text, kind);
        let hits = assert_matches_brute("curved surfaces", scene(&app), truth, &all);
        assert!(hits > 3_000, "only {hits} rays hit: the test would be weak");
    }
}
