//! The examples do what their headers say: the scene built in code is the white furnace (the sphere exactly its
//! albedo, the sky exactly 1, the same bytes as the RON file that describes it), and the custom `ao` plugin
//! registers, parses its parameters and measures occlusion (1 on an open plane, less beside a ball).

#[path = "../examples/custom_integrator.rs"]
mod custom_integrator;
#[path = "../examples/render_from_code.rs"]
mod render_from_code;

use crate::common::{render_file, scene_path};
use prism::app::SceneSource;
use prism::settings::Overrides;
use std::path::PathBuf;

#[test]
fn a_scene_built_in_code_renders_the_furnace_exactly_and_like_its_ron_file() {
    let mut app = render_from_code::furnace_app(0.8, 128, 16);
    app.run().unwrap();
    let img = prism::stages::film_image(&app.resources).unwrap();
    assert_eq!(img.get(0, 0), glam::Vec3::ONE, "the sky is exactly 1");
    let centre = img.get(64, 64).x;
    assert!((centre - 0.8).abs() < 0.05, "a pixel on the sphere estimates its albedo 0.8: {centre}");
    let from_file = render_file(&scene_path("furnace.ron"), Overrides { spp: Some(16), ..Default::default() });
    assert_eq!(img.pixels, from_file.pixels, "the same entities and settings give the same image");
}

#[test]
fn the_custom_ao_integrator_sees_an_open_plane_unoccluded_and_the_contact_of_a_ball_darker() {
    let text = "(camera: (eye: (0, 5, 0), target: (0, 0, 0), up: (0, 0, -1), orthographic: 4, size: (32, 32)),
        render: (spp: 16),
        entities: [(shape: Plane()), (shape: Sphere(center: (0, 1, 0)))])";
    let source =
        SceneSource::RonText { text: text.into(), name: PathBuf::from("ao.ron"), base_dir: PathBuf::from(".") };
    let mut app = custom_integrator::ao_app(source);
    app.resources.overrides.integrator = Some("ao(distance: 1)".into());
    app.run().unwrap();
    let img = prism::stages::film_image(&app.resources).unwrap();
    // A corner sees the plane 2.75 units from the ball's axis, 1.93 from its surface: nothing within 1, so every
    // sample is 1.
    assert_eq!(img.get(0, 0), glam::Vec3::ONE, "open plane");
    // The ball's top is convex: its hemisphere is open too.
    assert_eq!(img.get(16, 16), glam::Vec3::ONE, "the ball's top");
    // Just outside the silhouette (1.06 from the axis, 0.46 from the ball) the ball fills a cone of half-angle 43
    // degrees towards the horizon, most of it within 1.
    let ring = img.get(16 + 8, 16).x;
    assert!(ring < 0.9, "the plane beside the ball is occluded: {ring}");
    let mut bad = custom_integrator::ao_app(SceneSource::RonText {
        text: text.replace("render: (spp: 16)", "render: (integrator: ao(distanse: 1))"),
        name: PathBuf::from("ao.ron"),
        base_dir: PathBuf::from("."),
    });
    bad.resources.overrides.integrator = None;
    let e = bad.run().unwrap_err().to_string();
    assert!(e.contains("ao.ron:2:") && e.contains("distanse"), "{e}");
}
