//! glTF files composed into RON scenes: a `Gltf(path)` entity nests the file's nodes under its transform, its
//! materials can be replaced by name (or all by the entity's material), several files share one scene (a file
//! placed twice stores its meshes and materials once), a RON
//! scene without a camera takes the first file's, `Mesh(path: "x.gltf")` is the same entity, and `prism convert
//! model.gltf -o scene.ron` writes a scene that renders the same bytes as the file.

use crate::common::{app_from_ron, prism_args, render_file, render_ron, scratch};
use crate::gltf_doc::{Doc, QUAD, QUAD_IDX, diffuse, node};
use prism::settings::Overrides;
use std::path::PathBuf;

/// One double-sided grey (0.5) Lambert quad at the origin facing +z, its material named "paint"; no camera, no
/// light.
fn quad_gltf(name: &str) -> PathBuf {
    let mut d = Doc::default();
    let m = diffuse([0.5; 3], true, None);
    d.materials.push(format!("{{\"name\": \"paint\", {}", &m[1..]));
    let q = d.mesh(&QUAD, &QUAD_IDX, 0);
    d.nodes.push(node(q, [0.0; 3], None, [1.0; 3]));
    d.write(name)
}

/// A RON scene: a camera looking at the origin from +z, a white sky, a red Lambert material, and `entities`.
fn scene(entities: &str, camera: bool) -> String {
    let cam = if camera { "camera: (eye: (0, 0, 4), target: (0, 0, 0), fov: 20, size: (16, 16))," } else { "" };
    format!(
        r#"(
    {cam}
    render: (integrator: envlight(max_depth: 2)),
    materials: {{ "red": Lambert(albedo: (0.8, 0, 0)) }},
    entities: [
        {entities}
        (light: Environment(radiance: (1, 1, 1))),
    ],
)"#
    )
}

fn o() -> Overrides {
    Overrides { spp: Some(64), ..Default::default() }
}

/// The mean of the centre 4 x 4 pixels.
fn centre(img: &prism::io::Image) -> glam::Vec3 {
    let mut s = glam::Vec3::ZERO;
    for y in 6..10 {
        for x in 6..10 {
            s += img.get(x, y);
        }
    }
    s / 16.0
}

fn near(a: glam::Vec3, b: glam::Vec3, what: &str) {
    assert!((a - b).abs().max_element() < 0.02, "{what}: {a}, expected {b}");
}

#[test]
fn a_gltf_entity_nests_the_files_nodes_under_its_transform() {
    let q = quad_gltf("compose_quad.gltf");
    // The quad fills the view's centre; a Lambert 0.5 under a sky of 1 reflects 0.5.
    let here = render_ron(&scene(&format!("(shape: Gltf(path: {q:?})),"), true), o());
    near(centre(&here), glam::Vec3::splat(0.5), "the placed quad");
    // Moved 5 to the side by the entity's transform: the sky behind it.
    let moved =
        render_ron(&scene(&format!("(shape: Gltf(path: {q:?}), transform: [Translate((5, 0, 0))]),"), true), o());
    near(centre(&moved), glam::Vec3::ONE, "the quad moved out of view");
}

#[test]
fn gltf_materials_are_replaced_by_name_or_all_by_the_entitys_material() {
    let q = quad_gltf("compose_paint.gltf");
    let red = glam::Vec3::new(0.8, 0.0, 0.0);
    let by_name =
        render_ron(&scene(&format!("(shape: Gltf(path: {q:?}, materials: {{\"paint\": \"red\"}})),"), true), o());
    near(centre(&by_name), red, "\"paint\" replaced by \"red\"");
    let all = render_ron(&scene(&format!("(shape: Gltf(path: {q:?}), material: \"red\"),"), true), o());
    near(centre(&all), red, "every material replaced by the entity's");
    let e = app_from_ron(&scene(&format!("(shape: Gltf(path: {q:?}, materials: {{\"pant\": \"red\"}})),"), true), o())
        .run()
        .unwrap_err()
        .to_string();
    assert!(e.contains("no material named 'pant' to override (materials: paint)"), "{e}");
    let e =
        app_from_ron(&scene(&format!("(shape: Gltf(path: {q:?}, materials: {{\"paint\": \"blue\"}})),"), true), o())
            .run()
            .unwrap_err()
            .to_string();
    assert!(e.contains("unknown material 'blue'"), "{e}");
    let e = app_from_ron(&scene(&format!("(shape: Gltf(path: {q:?}), light: Area(radiance: (1, 1, 1))),"), true), o())
        .run()
        .unwrap_err()
        .to_string();
    assert!(e.contains("glTF entity carries no light"), "{e}");
}

#[test]
fn several_gltf_files_share_a_scene_and_a_scene_without_camera_takes_the_first_files() {
    let q = quad_gltf("compose_two.gltf");
    let two = format!(
        "(shape: Gltf(path: {q:?}), transform: [Translate((-1, 0, 0))]), (shape: Mesh(path: {q:?}), transform: [Translate((1, 0, 0))]),"
    );
    let mut app = app_from_ron(&scene(&two, false), Overrides { spp: Some(1), ..Default::default() });
    app.setup().unwrap();
    assert_eq!(app.resources.meshes.len(), 1, "a file placed twice stores its mesh once");
    assert_eq!(app.resources.materials.len(), 3, "and its material once (beside the default and \"red\")");
    let cams = app.world.query_mut::<&prism::camera::Camera>().into_iter().count();
    assert_eq!(cams, 1, "the first glTF brings the (framing) camera, the second none");
    // `Mesh(path: "x.gltf")` is `Gltf(path: "x.gltf")`.
    let a = render_ron(&scene(&format!("(shape: Gltf(path: {q:?})),"), true), o());
    let b = render_ron(&scene(&format!("(shape: Mesh(path: {q:?})),"), true), o());
    assert!(a.pixels == b.pixels, "Mesh(path: glTF) and Gltf(path) render the same");
}

#[test]
fn prism_convert_writes_a_ron_scene_that_renders_the_files_bytes() {
    let q = quad_gltf("compose_convert.gltf");
    let out = scratch("gltf_compose").join("quad.ron");
    let _ = std::fs::remove_file(&out);
    let r = prism_args(&["convert", q.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("Gltf(path:") && text.contains("Environment(radiance: (1, 1, 1))"), "{text}");
    let small = || Overrides { size: Some((12, 12)), spp: Some(4), ..Default::default() };
    let from_ron = render_file(&out, small());
    let from_gltf = render_file(&q, small());
    assert!(from_ron.pixels == from_gltf.pixels, "the converted scene renders as the file does");
}
