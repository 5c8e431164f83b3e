//! The shipped scenes: the Cornell box reproduces the Mitsuba reference's geometry exactly, direct lighting
//! converges to Mitsuba's direct-only reference, every scene renders, nested transforms compose.

use crate::common::{app_from_file, render_file, scene_path};
use glam::Vec3A;
use prism::settings::Overrides;

#[test]
fn cornell_direct_matches_mitsubas_direct_lighting_reference_and_converges() {
    let rmse = crate::common::rmse_against_reference("cornell_direct.ron", "direct_only.exr", &[4, 16, 64], 0.02);
    // Unbiased Monte Carlo: 4x the samples should halve the RMSE; require at least a 1.5x drop each time.
    assert!(rmse[1] < rmse[0] / 1.5 && rmse[2] < rmse[1] / 1.5, "RMSE does not fall with samples: {rmse:?}");
}

#[test]
fn cornell_box_geometry_is_exactly_the_reference_scene() {
    let mut app = app_from_file(&scene_path("cornell_box.ron"), Overrides::default());
    app.setup().unwrap();
    let s = app.resources.scene.as_ref().unwrap();
    assert_eq!((s.camera.width, s.camera.height), (256, 256));
    assert_eq!(s.prims.num_tris(), 2 * 6 + 12 * 2, "6 quads and 2 cubes");
    let has_vertex = |v: [f32; 3]| {
        let v = Vec3A::from(v);
        s.prims.tris.iter().flatten().any(|p| (*p - v).abs().max_element() < 2e-6)
    };
    // Corners listed in ../shared/refs/cornell.md.
    for v in [
        [-0.23, 0.99, -0.18],
        [0.23, 0.99, 0.2],
        [0.1358201, -1.0, 0.005397062],
        [0.5341799, -0.4, 0.7546029],
        [-0.7088589, -1.01, -0.4709606],
        [0.04885888, 0.21, -0.0890394],
        [-1.0, -1.0, 1.0],
        [1.0, 1.0, -1.0],
    ] {
        assert!(has_vertex(v), "vertex {v:?} of the reference scene is missing");
    }
    // One-sided emitter facing down, radiance as specified.
    assert_eq!(s.lights.len(), 1);
    let light_tri = s.prims.tri_shading.iter().position(|t| t.light == 0).unwrap();
    let t = s.prims.tris[light_tri];
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
    assert!((n - Vec3A::new(0.0, -1.0, 0.0)).length() < 1e-6);
    let text = std::fs::read_to_string(scene_path("cornell_box.ron")).unwrap();
    assert!(text.lines().count() <= 45, "a Cornell box should take about 40 lines of RON");
}

#[test]
fn every_shipped_scene_renders_small() {
    let mut count = 0;
    for entry in std::fs::read_dir(crate::common::root().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let img = render_file(&path, Overrides { size: Some((32, 32)), spp: Some(1), ..Default::default() });
            assert!(img.pixels.iter().all(|p| p.is_finite()), "{}", path.display());
            assert!(img.mean().max_element() > 0.0, "{} is black", path.display());
            count += 1;
        }
    }
    assert!(count >= 3, "expected at least cornell_box, cornell_direct and a nested/OBJ scene");
}

#[test]
fn nested_children_inherit_their_parents_transforms() {
    // nested.ron: a sphere under three levels of groups; its world centre is known by hand.
    let mut app = app_from_file(&scene_path("nested.ron"), Overrides::default());
    app.setup().unwrap();
    let s = app.resources.scene.as_ref().unwrap();
    let moon = s.prims.spheres.iter().find(|sp| (sp.radius - 0.05).abs() < 1e-6).expect("the moon sphere");
    // table at (0, 1, -0.2); orbit rotates 30 degrees about y; moon translated (0.3, 0.1, 0) inside it:
    // (0.3, 0.1, 0) rotated by 30 degrees about y is (0.3 cos 30, 0.1, -0.3 sin 30); plus the table offset.
    let expect = Vec3A::new(0.3 * 30f32.to_radians().cos(), 1.1, -0.2 - 0.3 * 30f32.to_radians().sin());
    assert!((moon.center - expect).length() < 1e-5, "moon at {:?}, expected {expect:?}", moon.center);
    assert!(s.prims.num_tris() > 1000, "the OBJ mesh is loaded");
}
