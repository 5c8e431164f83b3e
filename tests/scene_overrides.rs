//! The command line's light and view for any scene (`--sky`, `--env`, `--look-from`, `--look-at`, `--up`,
//! `--fov`, `--no-default-light`): each override renders the same bytes as the scene written with it, the view is
//! taken in world space whatever the camera's parents, bad values are one-line errors, and the overrides are part
//! of the film's fingerprint.

use crate::common::{app_from_file, app_from_ron, data, render_file, render_ron, scene_path};
use glam::Vec3;
use prism::settings::{EnvOverride, Overrides, ViewOverride};

/// Two spheres and a point light, no environment; `{env}` and `{camera}` are filled in by the tests.
fn scene(camera: &str, env: &str) -> String {
    format!(
        r#"(
    camera: {camera},
    render: (integrator: envlight(max_depth: 2)),
    materials: {{ "clay": Lambert(albedo: (0.7, 0.6, 0.5)), "mirror": Mirror() }},
    entities: [
        (shape: Sphere(center: (-0.7, 0, 0), radius: 0.6), material: "clay"),
        (shape: Sphere(center: (0.7, 0, 0), radius: 0.6), material: "mirror"),
        (light: Point(intensity: (2, 2, 2), position: (0, 3, 2))),
        {env}
    ],
)"#
    )
}

const CAMERA: &str = "(eye: (0, 0.5, 4), target: (0, 0, 0), fov: 40, size: (24, 16))";
const SKY_MAP: &str = "../../shared/data/envmaps/equirect/probulator_pisa_256x128.hdr";

fn small() -> Overrides {
    Overrides { spp: Some(8), ..Default::default() }
}

fn bytes(img: &prism::io::Image) -> Vec<u32> {
    img.pixels.iter().flat_map(|p| p.to_array()).map(f32::to_bits).collect()
}

/// The two images are bit for bit the same (the message counts the values that differ, not lists them).
fn assert_same(a: &prism::io::Image, b: &prism::io::Image, what: &str) {
    let (a, b) = (bytes(a), bytes(b));
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(a.len() == b.len() && differ == 0, "{what}: {differ} of {} values differ", a.len());
}

#[test]
fn sky_replaces_the_scenes_environment_and_renders_as_the_scene_written_with_it() {
    let with_map = scene(CAMERA, &format!("(light: Environment(map: \"{SKY_MAP}\"))"));
    let sky = Vec3::new(0.25, 0.5, 1.0);
    let overridden = render_ron(&with_map, Overrides { environment: Some(EnvOverride::Sky(sky)), ..small() });
    let written = render_ron(&scene(CAMERA, "(light: Environment(radiance: (0.25, 0.5, 1)))"), small());
    assert_same(&overridden, &written, "--sky 0.25,0.5,1 is the uniform environment 0.25,0.5,1");
}

#[test]
fn env_adds_a_scaled_map_turned_about_y_and_renders_as_the_scene_written_with_it() {
    let path = scene_path(SKY_MAP).canonicalize().unwrap();
    let env = EnvOverride::Map { path, scale: 2.0, rotate_deg: 90.0, layout: None };
    let overridden = render_ron(&scene(CAMERA, ""), Overrides { environment: Some(env), ..small() });
    let written = render_ron(
        &scene(
            CAMERA,
            &format!(
                "(light: Environment(map: \"{SKY_MAP}\", scale: 2), transform: [Rotate(axis: (0, 1, 0), degrees: 90)])"
            ),
        ),
        small(),
    );
    assert_same(&overridden, &written, "--env MAP --env-scale 2 --env-rotate 90");
}

#[test]
fn the_view_flags_render_as_the_camera_written_with_them() {
    let view = ViewOverride {
        from: Some(Vec3::new(1.0, 2.0, 3.0)),
        at: Some(Vec3::new(0.5, 0.0, 0.0)),
        up: Some(Vec3::new(0.0, 1.0, 0.2)),
        fov: Some(55.0),
    };
    let overridden = render_ron(&scene(CAMERA, ""), Overrides { view, ..small() });
    let written = render_ron(
        &scene("(eye: (1, 2, 3), target: (0.5, 0, 0), up: (0, 1, 0.2), fov: 55, size: (24, 16))", ""),
        small(),
    );
    assert_same(&overridden, &written, "the view flags");
}

#[test]
fn look_at_alone_keeps_a_parented_cameras_world_position() {
    // Cameras.gltf: the perspective camera is a node at (0.5, 0.5, 3) looking down -z.
    let path = data("gltf_samples/cameras/Cameras.gltf");
    let view = ViewOverride { at: Some(Vec3::ZERO), ..Default::default() };
    let mut app = app_from_file(&path, Overrides { view, ..small() });
    app.setup().unwrap();
    let cam = *app.world.query_mut::<&prism::camera::Camera>().into_iter().next().unwrap();
    assert!((cam.eye - Vec3::new(0.5, 0.5, 3.0)).length() < 1e-5, "eye {} (world)", cam.eye);
    assert_eq!(cam.target, Vec3::ZERO);
}

#[test]
fn bad_view_and_environment_values_are_one_line_errors() {
    let err = |o: Overrides| app_from_ron(&scene(CAMERA, ""), o).run().unwrap_err().to_string();
    let view = |v: ViewOverride| Overrides { view: v, ..small() };
    let e = err(view(ViewOverride { from: Some(Vec3::ZERO), at: Some(Vec3::ZERO), ..Default::default() }));
    assert!(e.contains("--look-from and --look-at are the same point"), "{e}");
    let e = err(view(ViewOverride { up: Some(Vec3::new(0.0, -0.5, -4.0)), ..Default::default() }));
    assert!(e.contains("--up") && e.contains("parallel"), "{e}");
    let e = err(view(ViewOverride { fov: Some(180.0), ..Default::default() }));
    assert!(e.contains("--fov must be in (0, 180)"), "{e}");
    let e = err(view(ViewOverride { from: Some(Vec3::new(1e30, 0.0, 0.0)), ..Default::default() }));
    assert!(e.contains("--look-from") && e.contains("coordinate limit"), "{e}");
    let ortho = scene("(eye: (0, 0, 4), target: (0, 0, 0), orthographic: Some(3), size: (8, 8))", "");
    let e = app_from_ron(&ortho, view(ViewOverride { fov: Some(30.0), ..Default::default() })).run().unwrap_err();
    assert!(e.to_string().contains("orthographic"), "{e}");
    let env = |e: EnvOverride| Overrides { environment: Some(e), ..small() };
    let e = err(env(EnvOverride::Sky(Vec3::new(-1.0, 0.0, 0.0))));
    assert!(e.contains("--sky"), "{e}");
    let missing = EnvOverride::Map { path: "no/such/sky.hdr".into(), scale: 1.0, rotate_deg: 0.0, layout: None };
    let e = err(env(missing));
    assert!(e.starts_with("--env: ") && e.contains("no/such/sky.hdr") && e.contains("not found"), "{e}");
    let wide = data("bitterli/classroom/classroom.exr");
    let e = err(env(EnvOverride::Map { path: wide, scale: 1.0, rotate_deg: 0.0, layout: None }));
    assert!(e.contains("--env-layout equirect"), "the hint names the flag, not the RON field: {e}");
}

#[test]
fn no_default_light_leaves_a_bare_mesh_dark_and_an_environment_replaces_its_headlight() {
    let obj = scene_path("assets/CornellBox-Sphere.obj");
    let o = |no_default_light, environment| Overrides {
        size: Some((16, 16)),
        spp: Some(2),
        no_default_light,
        environment,
        ..Default::default()
    };
    let lit = render_file(&obj, o(false, None));
    assert!(lit.pixels.iter().any(|p| p.max_element() > 0.0), "the headlight lights the bare mesh");
    // The OBJ's own light quad emits; without the headlight only it and what it lights are non-black.
    let dark = render_file(&obj, o(true, None));
    let sum = |i: &prism::io::Image| i.pixels.iter().map(|p| p.element_sum() as f64).sum::<f64>();
    assert!(sum(&dark) < sum(&lit), "no headlight: darker ({} vs {})", sum(&dark), sum(&lit));
    let black_sky = render_file(&obj, o(false, Some(EnvOverride::Sky(Vec3::ZERO))));
    assert_same(&black_sky, &dark, "--sky 0,0,0 replaces the headlight (and adds nothing)");
}

#[test]
fn the_overrides_are_part_of_the_films_fingerprint() {
    let hash = |o: Overrides| {
        let mut app = app_from_ron(&scene(CAMERA, ""), o);
        app.setup().unwrap();
        app.resources.settings.fingerprint(app.resources.scene_hash)
    };
    let plain = hash(small());
    let sky = hash(Overrides { environment: Some(EnvOverride::Sky(Vec3::ONE)), ..small() });
    let moved = hash(Overrides { view: ViewOverride { fov: Some(30.0), ..Default::default() }, ..small() });
    let unlit = hash(Overrides { no_default_light: true, ..small() });
    assert_eq!(plain, hash(small()));
    for (name, h) in [("--sky", sky), ("--fov", moved), ("--no-default-light", unlit)] {
        assert_ne!(h, plain, "{name} changes the fingerprint, so --resume refuses a film made without it");
    }
}
