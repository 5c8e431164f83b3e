//! The wide BVH's traversal shortcuts change the work, never the answer: the AVX and SSE box tests, a query that
//! outgrows its first stack, spheres given leaves of their own, the triangle a ray leaves, and leaves a ray moves
//! away from (their slabs) — each checked bit for bit against the traversal without it, and against brute force.

use crate::accel::{
    accelerators, assert_matches_brute, bunny_scene_text, rays, same_hit, scene, setup_file, setup_ron,
};
use glam::Vec3A;
use prism::accel::{Accel, TraversalWork, WideBvh};
use prism::geometry::{NO_PRIM, Ray};
use prism::primitives::Hit;
use prism::ray_sets::secondary_rays;
use prism::sampling::{Rng, warp};
use prism::scene::Scene;
use prism::settings::AccelKind;
use rayon::prelude::*;

/// One ray's traversal answers bit for bit: the closest hit counted and uncounted (primitive, `t`, barycentrics),
/// occlusion, and the work counted.
type Answer = (Option<(u32, u32, u32, u32)>, Option<(u32, u32, u32, u32)>, bool, TraversalWork);

fn traversal_answers(s: &Scene, all: &[Ray]) -> Vec<Answer> {
    let bits = |h: Hit| (h.prim, h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits());
    all.iter()
        .map(|r| {
            let mut work = TraversalWork::default();
            let counted = s.accel.intersect_counted(&s.prims, r, &mut work).map(bits);
            (counted, s.intersect(r).map(bits), s.occluded(r), work)
        })
        .collect()
}

/// The answers of `app`'s BVH for `all` rays as built, then after `change` (a switch of how it traverses).
fn answers_before_and_after(
    app: &mut prism::App,
    all: &[Ray],
    change: impl FnOnce(&mut WideBvh),
) -> (Vec<Answer>, Vec<Answer>) {
    let before = traversal_answers(scene(app), all);
    let s = app.resources.scene.as_mut().expect("a scene");
    let Accel::Bvh(bvh) = &mut s.accel else { panic!("the BVH was asked for") };
    change(bvh);
    (before, traversal_answers(scene(app), all))
}

/// The answers of the bunny scene's BVH for its camera, bounce and shadow rays as built, then after `change` (an
/// implementation switch that must not change any of them): the answers before, and how many rays answer
/// differently after.
fn bvh_answers_before_and_after(change: impl FnOnce(&mut WideBvh)) -> (Vec<Answer>, usize) {
    let mut app = setup_ron(&bunny_scene_text(), AccelKind::Bvh);
    let rays_camera = rays(scene(&app), 4000, 3);
    let (bounce, shadow) = secondary_rays(scene(&app), &rays_camera, 5);
    let all: Vec<Ray> = rays_camera.iter().chain(&bounce).chain(&shadow).copied().collect();
    let (before, after) = answers_before_and_after(&mut app, &all, change);
    let differ = before.iter().zip(&after).filter(|(a, b)| a != b).count();
    (before, differ)
}

/// The wide BVH tests a node's eight child boxes with one AVX operation per step where the CPU has AVX2, with
/// two SSE operations elsewhere; both compute every lane with the same operations in the same order, so the
/// traversal visits the same nodes and primitives in the same order and every answer is the same bit for bit.
/// (On a CPU without AVX2 both sides are the SSE test.)
#[test]
fn the_bvhs_avx_and_sse_box_tests_give_the_same_traversal_bit_for_bit() {
    let (wide, differ) = bvh_answers_before_and_after(|bvh| {
        eprintln!("AVX box test available: {}", bvh.uses_avx_boxes());
        bvh.use_baseline_boxes();
    });
    assert_eq!(differ, 0, "{differ} of {} rays traverse differently (hit, occlusion or nodes visited)", wide.len());
    assert!(wide.iter().filter(|a| a.0.is_some()).count() > wide.len() / 4, "too few hits: the test would be weak");
}

/// `Ray::coherent` is a hint (camera rays): the wide BVH then reads a leaf's surviving triangle through a branch on
/// its lane, otherwise through a permute. Both must give every answer, and the work counted, bit for bit; on the
/// bunny's camera, bounce and shadow rays, each traced with the hint and without.
#[test]
fn the_coherent_ray_hint_never_changes_an_answer() {
    let app = setup_ron(&bunny_scene_text(), AccelKind::Bvh);
    let s = scene(&app);
    let camera = rays(s, 4000, 7);
    let (bounce, shadow) = secondary_rays(s, &camera, 9);
    let all: Vec<Ray> = camera.iter().chain(&bounce).chain(&shadow).copied().collect();
    let plain: Vec<Ray> = all.iter().map(|r| Ray { coherent: false, ..*r }).collect();
    let hinted: Vec<Ray> = all.iter().map(|r| r.coherent()).collect();
    let (a, b) = (traversal_answers(s, &plain), traversal_answers(s, &hinted));
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(differ, 0, "{differ} of {} rays answer differently with the hint", a.len());
    assert!(a.iter().filter(|x| x.0.is_some()).count() > a.len() / 4, "too few hits: the test would be weak");
}

/// A BVH query starts with a 32-entry traversal stack (zeroing one sized for the tree's depth costs a `memset` on
/// deep trees) and starts again with a full one when a node's children would overflow it: the answer, and the
/// work counted, must not change. Forced here by a first stack of 8 entries, which every ray outgrows at the
/// first node it meets with a non-empty stack (so every ray that visits three nodes or more starts again).
#[test]
fn a_bvh_query_that_outgrows_its_first_stack_starts_again_with_the_same_answer() {
    let (normal, differ) = bvh_answers_before_and_after(|bvh| bvh.set_first_stack(8));
    assert_eq!(differ, 0, "{differ} of {} rays answer differently after a restart", normal.len());
    let deep = normal.iter().filter(|a| a.3.nodes >= 3).count();
    assert!(deep > normal.len() / 5, "only {deep} of {} rays visit 3 nodes or more: too few restarts", normal.len());
}

/// An analytic primitive (a sphere here; also revolutions and patches) costs several triangle tests — divisions,
/// square roots, Newton steps — while a node tests all eight child boxes in one operation. So where a node has
/// room the wide BVH gives each analytic primitive a leaf of its own, and rays that do not come near it never test
/// it. On the sphere Cornell box the BVH2 puts each sphere in a leaf with a wall (whose box every ray to that wall
/// enters); after the collapse no leaf mixes a sphere with anything, and every answer still equals brute force.
#[test]
fn the_wide_bvh_gives_spheres_leaves_of_their_own_where_a_node_has_room() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_rough.ron");
    let app = setup_file(&path, AccelKind::Bvh);
    let s = scene(&app);
    let Accel::Bvh(bvh) = &s.accel else { panic!("the BVH was asked for") };
    let nt = s.prims.num_tris();
    let leaves = bvh.leaf_primitives();
    let mut seen: Vec<u32> = leaves.iter().flatten().copied().collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..s.prims.num_bounded()).collect::<Vec<_>>(), "every primitive in exactly one leaf");
    let spheres = (nt..s.prims.num_bounded()).count();
    assert_eq!(spheres, 2, "the scene has two spheres");
    for leaf in &leaves {
        if leaf.iter().any(|&id| id >= nt) {
            assert_eq!(leaf.len(), 1, "a sphere shares a leaf: {leaf:?} (leaves {leaves:?})");
        }
    }
    let truth_app = setup_file(&path, AccelKind::Brute);
    let all = rays(s, 4000, 11);
    let hits = assert_matches_brute("cornell_rough bvh", s, scene(&truth_app), &all);
    assert!(hits > 1000, "too few hits ({hits}): the test would be weak");
}

/// A ray spawned from a triangle cannot meet that triangle again (a plane), so `Ray::leaves` lets the BVH skip
/// its test: with the hint or without, every accelerator's answer is the same, and equals brute force, for
/// bounce and shadow rays spawned from hits on the bunny (triangles), spheres and an ellipsoid.
#[test]
fn skipping_the_triangle_a_ray_leaves_never_changes_the_answer() {
    let truth_app = setup_ron(&bunny_scene_text(), AccelKind::Brute);
    let truth = scene(&truth_app);
    let spawned = spawned_rays(truth, 3000, 23);
    assert!(spawned.iter().filter(|r| r.leaves != NO_PRIM).count() > 3000, "too few spawned rays");
    let brute: Vec<Option<Hit>> = spawned.par_iter().map(|r| truth.intersect(&r.leaving(NO_PRIM))).collect();
    for kind in accelerators() {
        let app = setup_ron(&bunny_scene_text(), kind);
        let sc = scene(&app);
        spawned.par_iter().zip(&brute).enumerate().for_each(|(i, (r, &expected))| {
            let plain = r.leaving(NO_PRIM);
            let (a, b) = (sc.intersect(r), sc.intersect(&plain));
            assert_eq!(
                a.map(|h| (h.prim, h.t.to_bits())),
                b.map(|h| (h.prim, h.t.to_bits())),
                "{kind:?}: ray {i} {r:?}: the hint changed the closest hit"
            );
            assert_eq!(sc.occluded(r), sc.occluded(&plain), "{kind:?}: ray {i}: the hint changed occlusion");
            assert!(same_hit(truth, r, a, expected), "{kind:?}: ray {i}: differs from brute force");
        });
    }
}

/// Rays spawned from where `n` random rays first hit `truth`'s surfaces (so they carry [`Ray::leaves`]): a bounce
/// away from the surface, one into it (refraction-like), and a shadow ray to a random point of the scene's bounds.
fn spawned_rays(truth: &Scene, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 0);
    let mut spawned = vec![];
    for r in rays(truth, n, 11) {
        let Some(s) = truth.trace(&r) else { continue };
        let normal = if s.ng.dot(r.dir) < 0.0 { s.ng } else { -s.ng };
        let mut d = warp::uniform_sphere(rng.next_2d());
        if d.dot(normal) < 0.0 {
            d = -d;
        }
        spawned.push(s.spawn(d));
        spawned.push(s.spawn(-d));
        let b = truth.prims.bounds;
        let q = b.min + b.diagonal() * Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let mut sh = s.spawn((q - s.p).normalize_or(Vec3A::X));
        sh.tmax = (q - s.p).length();
        spawned.push(sh);
    }
    spawned
}

/// A leaf whose triangles lie in a face of its box (a wall, the floor, the top of a block) keeps that slab, and a
/// ray whose origin is beyond the slab and that does not move back towards it skips the leaf's primitives (rays
/// leaving a wall never test the wall again). Exact comparisons make it a shortcut, not an approximation: on both
/// Cornell boxes, for rays spawned from every kind of surface (with the `leaves` hint and without it) and random
/// rays, every closest hit (primitive, distance, barycentrics) and occlusion answer is the same bit for bit with
/// the slab tests as without them, and agrees with brute force — while the primitives tested fall by a quarter.
#[test]
fn rays_moving_away_from_a_leafs_slab_skip_it_without_changing_any_answer() {
    for name in ["cornell_box", "cornell_rough"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.ron"));
        let truth_app = setup_file(&path, AccelKind::Brute);
        let truth = scene(&truth_app);
        let spawned = spawned_rays(truth, 3000, 29);
        let mut all: Vec<Ray> = spawned.iter().flat_map(|r| [*r, r.leaving(NO_PRIM)]).collect();
        all.extend(rays(truth, 2000, 5));
        let mut app = setup_file(&path, AccelKind::Bvh);
        let (with_slabs, without) = answers_before_and_after(&mut app, &all, WideBvh::disable_leaf_slabs);
        for (i, (a, b)) in with_slabs.iter().zip(&without).enumerate() {
            assert_eq!(
                (a.0, a.1, a.2),
                (b.0, b.1, b.2),
                "{name}: ray {i} {:?}: the slab test changed the answer",
                all[i]
            );
        }
        let prims = |v: &[Answer]| v.iter().map(|a| a.3.prims as u64).sum::<u64>();
        let (tested, before) = (prims(&with_slabs), prims(&without));
        eprintln!("{name}: {tested} primitive tests with slabs, {before} without");
        assert!(4 * tested <= 3 * before, "{name}: {tested} primitive tests with slabs, {before} without");
        let sc = scene(&app);
        all.par_iter().enumerate().for_each(|(i, r)| {
            assert!(same_hit(truth, r, sc.intersect(r), truth.intersect(&r.leaving(NO_PRIM))), "{name}: ray {i}");
            assert_eq!(sc.occluded(r), truth.occluded(&r.leaving(NO_PRIM)), "{name}: ray {i}: occlusion");
        });
        let hits = with_slabs.iter().filter(|a| a.0.is_some()).count();
        assert!(hits > all.len() / 3, "{name}: only {hits} of {} rays hit: the test would be weak", all.len());
    }
}

/// Rays traced sixteen at a time (`Accelerator::intersect_packet`, the wide BVH's packet traversal) get the closest
/// hit each would get alone: the same distance bit for bit and, but for two primitives at exactly the same distance,
/// the same primitive and barycentrics. Checked on coherent packets (a pixel's camera rays, which the packet
/// traversal is for) and incoherent ones (random rays with finite and infinite `tmax`, rays spawned from surfaces
/// with the `leaves` hint, directions whose components tie in magnitude or are signed zeros, a last packet of fewer
/// than sixteen), on triangle-only and sphere scenes and the bunny.
#[test]
fn packets_of_rays_get_the_closest_hit_each_ray_gets_alone() {
    let paths = ["scenes/cornell_box.ron", "scenes/cornell_rough.ron"]
        .map(|p| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(p));
    let mut apps: Vec<prism::App> = paths.iter().map(|p| setup_file(p, AccelKind::Bvh)).collect();
    apps.push(setup_ron(&bunny_scene_text(), AccelKind::Bvh));
    for app in &apps {
        let s = scene(app);
        let mut rng = Rng::new(7, 1);
        // A pixel's camera rays, every 7th pixel of every 7th row.
        let mut all: Vec<Ray> = vec![];
        for y in (0..s.camera.height).step_by(7) {
            for x in (0..s.camera.width).step_by(7) {
                for _ in 0..16 {
                    let film = glam::Vec2::new(x as f32 + rng.next_f32(), y as f32 + rng.next_f32());
                    all.push(s.camera.generate_ray(film));
                }
            }
        }
        let coherent = all.len();
        all.extend(rays(s, 3000, 13));
        all.extend(spawned_rays(s, 2000, 17));
        // Directions whose largest components tie in magnitude, or with signed zeros: where the choice of the
        // shear's axes (the packet computes it lane by lane, the lone query per ray) could differ.
        let b = s.prims.bounds;
        let values = [-1.0f32, -0.5, -0.0, 0.0, 0.5, 1.0];
        let mut k = 0;
        for x in values {
            for y in values {
                for z in values {
                    if x == 0.0 && y == 0.0 && z == 0.0 {
                        continue;
                    }
                    let f = [0.3, 0.5, 0.7][k % 3];
                    k += 1;
                    all.push(Ray::new(b.min + b.diagonal() * Vec3A::new(f, 0.5, 1.0 - f), Vec3A::new(x, y, z)));
                }
            }
        }
        all.truncate(all.len() / 16 * 16 - 3);
        let mut packed = vec![None; all.len()];
        s.accel.intersect_packet(&s.prims, &all, &mut packed);
        let (mut hits, mut ties) = (0, 0);
        for (i, (r, p)) in all.iter().zip(&packed).enumerate() {
            let alone = s.accel.intersect(&s.prims, r);
            match (alone, p) {
                (None, None) => {}
                (Some(a), Some(p)) => {
                    hits += 1;
                    assert_eq!(a.t.to_bits(), p.t.to_bits(), "ray {i} ({}): distance", i < coherent);
                    if a.prim == p.prim {
                        let bits = |h: Hit| (h.b1.to_bits(), h.b2.to_bits());
                        assert_eq!(bits(a), bits(*p), "ray {i}: barycentrics {a:?} vs {p:?}");
                    } else {
                        // A tie: the packet's primitive is hit at exactly that distance too.
                        let wt = prism::geometry::WatertightRay::new(r);
                        let again = s.prims.intersect_bounded(p.prim, r, &wt).map(|h| h.t.to_bits());
                        assert_eq!(again, Some(p.t.to_bits()), "ray {i}: {a:?} vs {p:?} is not a tie");
                        ties += 1;
                    }
                }
                _ => panic!("ray {i} ({:?}): alone {alone:?}, in a packet {p:?}", r),
            }
        }
        assert!(hits > 2000, "too few hits ({hits}) for a test");
        assert!(ties * 100 <= hits, "{ties} ties in {hits} hits");
    }
}
