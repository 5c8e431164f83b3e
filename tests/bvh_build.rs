//! The wide BVH's build: two candidate trees (PLOC's and a top-down binned-SAH tree with spatial splits), each
//! answering every ray as brute force does, and the one of lower surface-area cost kept.

use crate::accel::{assert_matches_brute, bunny_scene_text, rays, scene, setup_file, setup_ron};
use prism::accel::{Accel, BvhCandidate, SPLIT_SAMPLES_PER_PRIMITIVE, SpatialSplits, WideBvh};
use prism::ray_sets::secondary_rays;
use prism::settings::AccelKind;

/// The bunny with spheres, ellipsoids and planes, as every accelerator is tested: both candidate trees agree with
/// brute force on random, camera, bounce and shadow rays, and the built BVH is the cheaper of the two by the
/// surface-area cost — on this mesh of uniform triangles, the SAH tree (measured: it traces the Stanford bunny's
/// bounce rays about 12% faster than PLOC's).
#[test]
fn both_candidate_bvh_trees_match_brute_force_and_the_cheaper_is_kept() {
    let text = bunny_scene_text();
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    let mut all = rays(truth, 3000, 41);
    let (bounce, shadow) = secondary_rays(truth, &all[..1000], 43);
    all.extend(bounce);
    all.extend(shadow);
    let mut app = setup_ron(&text, AccelKind::Bvh);
    let built = scene(&app).accel.stats().detail;
    let mut costs = vec![];
    for candidate in [BvhCandidate::Ploc, BvhCandidate::Sah] {
        let s = app.resources.scene.as_mut().expect("a scene");
        let bvh = WideBvh::build_candidate(&s.prims, candidate);
        costs.push(bvh.sah_cost());
        s.accel = Accel::Bvh(bvh);
        let hits = assert_matches_brute(&format!("{candidate:?} tree"), scene(&app), truth, &all);
        assert!(hits > all.len() / 3, "{candidate:?}: only {hits} of {} rays hit: the test would be weak", all.len());
    }
    let kept = WideBvh::build(&scene(&app).prims);
    eprintln!("surface-area cost: PLOC {:.3}, SAH {:.3}, kept {:.3} ({built})", costs[0], costs[1], kept.sah_cost());
    assert!(costs.iter().all(|c| c.is_finite() && *c > 1.0), "costs {costs:?}");
    assert_eq!(kept.sah_cost(), costs[0].min(costs[1]), "the build keeps the cheaper tree");
    assert!(costs[1] < costs[0], "on the bunny the SAH tree is the cheaper: {costs:?}");
}

/// On the Cornell box the walls are axis-aligned quads: PLOC keeps each in a leaf of its own (which the leaf slabs
/// skip), the top-down tree merges walls into shared leaves, and the cost says so — the box keeps PLOC's tree
/// (measured: the top-down tree traces its bounce rays about 20% slower).
#[test]
fn the_cornell_box_keeps_the_tree_with_a_leaf_per_wall() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.ron");
    let app = setup_file(&path, AccelKind::Bvh);
    let prims = &scene(&app).prims;
    let [ploc, sah] = [BvhCandidate::Ploc, BvhCandidate::Sah].map(|c| WideBvh::build_candidate(prims, c).sah_cost());
    assert!(ploc < sah, "PLOC {ploc}, SAH {sah}");
    assert_eq!(WideBvh::build(prims).sah_cost(), ploc);
}

/// Spatial splits (SBVH): a pile of long, thin, slanted triangles (sticks crossing each other in every direction, a
/// case whose boxes overlap badly) beside the bunny. The SAH candidate splits the sticks — some are referenced in
/// more than one leaf, each reference's box clipped to its part — and it still answers every ray as brute force
/// does: the shared random rays, and rays aimed at exact points of the sticks (barycentric), whose hits fall on and
/// around the faces of the clipped boxes. A clipped box that lost a sliver of its triangle would miss those hits.
#[test]
fn spatial_splits_reference_long_triangles_in_several_leaves_and_match_brute_force() {
    use glam::Vec3A;
    use prism::geometry::Ray;
    use prism::sampling::Rng;
    let mut rng = Rng::new(7, 0);
    let mut sticks = String::new();
    for _ in 0..400 {
        let p = |rng: &mut Rng| Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - 2.0;
        let (a, b) = (p(&mut rng), p(&mut rng));
        let c = a + (Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 0.08;
        sticks += &format!(
            "(shape: Triangle(vertices: (({}, {}, {}), ({}, {}, {}), ({}, {}, {})))),\n",
            a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z
        );
    }
    let text = bunny_scene_text().replacen("entities: [", &format!("entities: [\n{sticks}"), 1);
    let truth_app = setup_ron(&text, AccelKind::Brute);
    let truth = scene(&truth_app);
    let mut all = rays(truth, 3000, 47);
    let tris = &truth.prims.tris;
    for i in 0..3000u32 {
        let t = tris[(i as usize * 7919) % tris.len()];
        let (u, v) = (rng.next_f32(), rng.next_f32());
        let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
        let target = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
        let o = target + prism::sampling::warp::uniform_sphere(rng.next_2d()) * 5.0;
        all.push(Ray::new(o, (target - o).normalize()));
    }
    let mut app = setup_ron(&text, AccelKind::Bvh);
    let s = app.resources.scene.as_mut().expect("a scene");
    let n = s.prims.num_bounded() as usize;
    let bvh = WideBvh::build_candidate(&s.prims, BvhCandidate::Sah);
    let references = bvh.references();
    eprintln!("{n} primitives, {references} references in the SAH tree with spatial splits");
    assert!(references > n + 50, "spatial splits should duplicate some triangles: {references} references for {n}");
    assert!(references <= n + n / 2, "the reference budget is half the primitive count: {references}");
    // Subtrees are built in parallel with budgets fixed by their sizes: the same tree on one thread.
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool");
    let alone = one.install(|| WideBvh::build_candidate(&s.prims, BvhCandidate::Sah));
    assert_eq!((alone.references(), alone.sah_cost().to_bits()), (references, bvh.sah_cost().to_bits()));
    // Without spatial splits (a render with fewer than SPLIT_SAMPLES_PER_PRIMITIVE camera samples per primitive), every
    // primitive is referenced once.
    let plain = WideBvh::build_with(&s.prims, SpatialSplits::No);
    assert_eq!(plain.references(), n, "no spatial splits, no duplicates");
    let per = SPLIT_SAMPLES_PER_PRIMITIVE;
    assert_eq!(SpatialSplits::for_samples(Some(per * n as u64 - 1), n as u64), SpatialSplits::No);
    assert_eq!(SpatialSplits::for_samples(Some(per * n as u64), n as u64), SpatialSplits::Yes);
    assert_eq!(SpatialSplits::for_samples(None, n as u64), SpatialSplits::Yes, "a time budget may trace any number");
    s.accel = Accel::Bvh(plain);
    assert_matches_brute("the SAH tree without spatial splits", scene(&app), truth, &all);
    let s = app.resources.scene.as_mut().expect("a scene");
    s.accel = Accel::Bvh(bvh);
    let hits = assert_matches_brute("SBVH", scene(&app), truth, &all);
    assert!(hits > all.len() / 2, "only {hits} of {} rays hit: the test would be weak", all.len());
}
