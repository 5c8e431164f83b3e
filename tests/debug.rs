//! The `debug` integrator's views against known geometry: normals and depth of a plane facing the camera, the
//! grid's occupied cells (coloured where the grid has primitives, black elsewhere; an error without a grid),
//! heat maps for every accelerator (more work where there is geometry), and the teapot-in-a-stadium failure mode
//! of a plain uniform grid made visible in traversal counts, with the nested-grid fix.

use crate::common::{app_from_ron, render_ron};
use glam::{Vec2, Vec3};
use prism::accel::grid::auto_resolution;
use prism::accel::{TraversalWork, UniformGrid};
use prism::io::srgb_to_linear;
use prism::settings::{AccelKind, GridResolution, Overrides};

fn with(integrator: &str, accel: AccelKind, size: u32) -> Overrides {
    Overrides {
        integrator: Some(integrator.into()),
        accel: Some(accel),
        size: Some((size, size)),
        spp: Some(1),
        ..Default::default()
    }
}

/// A square facing the camera 5 units away (z = 0, camera at z = 5), plus a small cube off to the side.
const SQUARE: &str = "(camera: (eye: (0, 0, 5), target: (0, 0, 0), fov: 30),
    entities: [(shape: Quad(), transform: [UniformScale(0.8)]),
               (shape: Cube, transform: [Translate((1.2, 0.8, 0.5)), UniformScale(0.2)])])";

#[test]
fn normals_and_depth_views_show_the_known_geometry() {
    let img = render_ron(SQUARE, with("debug(mode: normals)", AccelKind::Bvh, 9));
    let c = img.get(4, 4);
    assert!((c - Vec3::new(0.0, 0.0, 1.0)).abs().max_element() < 1e-5, "|n| of a +z face: {c}");
    let img = render_ron(SQUARE, with("debug(mode: normals, signed: true)", AccelKind::Bvh, 9));
    let want = Vec3::new(srgb_to_linear(0.5), srgb_to_linear(0.5), 1.0);
    assert!((img.get(4, 4) - want).abs().max_element() < 1e-3, "(n+1)/2: {}", img.get(4, 4));
    // Depth 5 between near 0 and far 10: grey 0.5 (as an sRGB value).
    let img = render_ron(SQUARE, with("debug(mode: depth, near: 0, far: 10)", AccelKind::Bvh, 9));
    let v = img.get(4, 4);
    assert!((v.x - srgb_to_linear(0.5)).abs() < 2e-3, "depth: {v}");
}

#[test]
fn grid_cells_view_colours_occupied_cells_and_needs_a_grid() {
    let img =
        render_ron(SQUARE, with("debug(mode: grid_cells)", AccelKind::Grid(GridResolution::Fixed([4, 4, 2])), 32));
    // The square fills the middle of the view: occupied cells there; the corners of the image see no cell.
    assert!(img.get(16, 16).max_element() > 0.01, "centre: {}", img.get(16, 16));
    assert_eq!(img.get(0, 0), Vec3::ZERO);
    let mut app = app_from_ron(SQUARE, with("debug(mode: grid_cells)", AccelKind::Bvh, 8));
    let err = app.run().expect_err("grid_cells without a grid").to_string();
    assert!(err.contains("--accel grid"), "{err}");
}

#[test]
fn heat_maps_show_more_work_on_geometry_for_every_accelerator() {
    for accel in [AccelKind::Bvh, AccelKind::KdTree, AccelKind::Grid(GridResolution::Auto)] {
        let img = render_ron(SQUARE, with("debug(mode: heat, heat: total, max: 40)", accel, 32));
        // Rays that miss the scene's bounds do (almost) no work; rays onto the square do more.
        let (corner, centre) = (img.get(0, 0).element_sum(), img.get(16, 16).element_sum());
        assert!(centre > corner && centre > 0.0, "{accel:?}: corner {corner}, centre {centre}");
    }
    // Brute force tests every primitive for every ray: a flat heat map.
    let img = render_ron(SQUARE, with("debug(mode: heat, heat: prims, max: 40)", AccelKind::Brute, 8));
    assert!(img.pixels.iter().all(|p| *p == img.get(0, 0) && p.max_element() > 0.0));
}

#[test]
fn a_plain_grid_fails_on_the_teapot_in_a_stadium_and_nested_grids_fix_it() {
    let mut app = app_from_ron(&crate::accel::teapot_in_stadium_text(), Overrides::default());
    app.setup().unwrap();
    let scene = app.resources.scene.as_ref().unwrap();
    let prims = &scene.prims;
    let flat_res = auto_resolution(prims.num_bounded() as usize, prims.bounds.diagonal(), 2.0);
    let flat = UniformGrid::build(prims, GridResolution::Fixed(flat_res)).unwrap();
    let nested = UniformGrid::build(prims, GridResolution::Auto).unwrap();
    assert!(nested.nested_grids() > 0);
    let (mut wf, mut wn) = (TraversalWork::default(), TraversalWork::default());
    let mut hits = 0;
    for y in 0..16 {
        for x in 0..16 {
            let ray = scene.camera.generate_ray(Vec2::new(x as f32 * 16.0 + 8.0, y as f32 * 16.0 + 8.0));
            let a = prism::accel::Accelerator::intersect_counted(&flat, prims, &ray, &mut wf);
            let b = prism::accel::Accelerator::intersect_counted(&nested, prims, &ray, &mut wn);
            assert_eq!(a.map(|h| h.prim), b.map(|h| h.prim));
            hits += a.is_some_and(|h| h.prim < 6320) as u32;
        }
    }
    assert!(hits > 20, "the view must see the teapot ({hits} rays)");
    let per_ray = |w: TraversalWork| w.prims as f64 / 256.0;
    // The plain grid tests (nearly) every teapot triangle for a ray through the teapot's cell(s).
    assert!(per_ray(wf) > 500.0, "plain grid: {} tests per ray", per_ray(wf));
    assert!(per_ray(wn) < 50.0, "nested grids: {} tests per ray", per_ray(wn));
}
