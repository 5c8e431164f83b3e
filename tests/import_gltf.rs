//! glTF import: every sample file renders; a Cornell box written here as glTF renders like
//! `scenes/cornell_box.ron` within noise (and stores its shared cube once); supplied tangents agree with
//! generated MikkTSpace ones; photometric lights convert at 683 lm/W; alpha cut-outs let camera and shadow rays
//! through exactly as much as alpha says; malformed files are one-line errors; `--camera` by name or index; a
//! model with only emissive surfaces gets the default sky; the automatic camera ignores a huge ground plane.

use crate::common::{app_from_file, data, render_file, render_ron, scratch};
use crate::gltf_doc::{Doc, QUAD, QUAD_IDX, diffuse, node};
use prism::compare::compare;
use prism::settings::Overrides;
use std::path::PathBuf;

/// `scenes/cornell_box.ron` written as glTF: quads and one cube mesh (used by both boxes), Lambert materials
/// through KHR_materials_specular 0, the light as an emissive one-sided quad, the camera as a node.
fn cornell_gltf() -> PathBuf {
    let mut d = Doc::default();
    let white = [0.885809, 0.698859, 0.666422];
    d.materials.push(diffuse(white, false, None));
    d.materials.push(diffuse([0.105421, 0.37798, 0.076425], true, None));
    d.materials.push(diffuse([0.570068, 0.0430135, 0.0443706], true, None));
    d.materials.push(diffuse(white, false, Some([18.387, 13.9873, 6.75357])));
    let quad_w = d.mesh(&QUAD, &QUAD_IDX, 0);
    let quad_g = d.mesh(&QUAD, &QUAD_IDX, 1);
    let quad_r = d.mesh(&QUAD, &QUAD_IDX, 2);
    let quad_l = d.mesh(&QUAD, &QUAD_IDX, 3);
    let cube = prism::mesh::MeshData::unit_cube();
    let pos: Vec<f32> = cube.positions.iter().flat_map(|p| p.to_array()).collect();
    let idx: Vec<u32> = cube.indices.iter().flatten().copied().collect();
    let cube = d.mesh(&pos, &idx, 0);
    let x = [1.0, 0.0, 0.0];
    let y = [0.0, 1.0, 0.0];
    d.nodes.push(node(quad_l, [0.0, 0.99, 0.01], Some((x, 90.0)), [0.23, 0.19, 0.19]));
    d.nodes.push(node(quad_w, [0.0, -1.0, 0.0], Some((x, -90.0)), [1.0; 3]));
    d.nodes.push(node(quad_w, [0.0, 1.0, 0.0], Some((x, 90.0)), [1.0; 3]));
    d.nodes.push(node(quad_w, [0.0, 0.0, -1.0], None, [1.0; 3]));
    d.nodes.push(node(quad_g, [1.0, 0.0, 0.0], Some((y, -90.0)), [1.0; 3]));
    d.nodes.push(node(quad_r, [-1.0, 0.0, 0.0], Some((y, 90.0)), [1.0; 3]));
    d.nodes.push(node(cube, [0.335, -0.7, 0.38], Some((y, -17.0)), [0.3; 3]));
    d.nodes.push(node(cube, [-0.33, -0.4, -0.28], Some((y, 18.25)), [0.3, 0.61, 0.3]));
    d.cameras.push(format!(
        "{{\"type\": \"perspective\", \"perspective\": {{\"yfov\": {}, \"aspectRatio\": 1, \"znear\": 0.01}}}}",
        39.3077f32.to_radians()
    ));
    d.nodes.push("{\"camera\": 0, \"translation\": [0, 0, 3.9]}".into());
    d.write("cornell.gltf")
}

#[test]
fn a_gltf_cornell_box_renders_like_the_ron_cornell_box_within_noise_and_stores_its_cube_once() {
    let over = |seed| Overrides {
        size: Some((64, 64)),
        spp: Some(64),
        seed: Some(seed),
        integrator: Some("envlight(max_depth: 8)".into()),
        ..Default::default()
    };
    let ron = crate::common::scene_path("cornell_box.ron");
    let r0 = render_file(&ron, over(0));
    let r1 = render_file(&ron, over(1));
    let path = cornell_gltf();
    // Its only light is the emissive quad: without --no-default-light the white sky would shine in through the
    // open front.
    let mut app = app_from_file(&path, Overrides { no_default_light: true, ..over(0) });
    app.run().unwrap();
    let g = prism::stages::film_image(&app.resources).unwrap();
    // Four quad meshes and one cube mesh, though the cube is used twice.
    assert_eq!(app.resources.meshes.len(), 5, "a mesh used by two nodes is stored once");
    let noise = compare(&r1, &r0).unwrap();
    let m = compare(&g, &r0).unwrap();
    let mean = |img: &prism::io::Image| {
        img.pixels.iter().map(|p| (p.x + p.y + p.z) as f64).sum::<f64>() / img.pixels.len() as f64
    };
    let (mg, mr) = (mean(&g), mean(&r0));
    assert!((mg - mr).abs() / mr < 0.01, "image means {mg} vs {mr}");
    assert!(
        m.rmse <= 1.2 * noise.rmse + 1e-4,
        "glTF vs RON RMSE {} exceeds the noise between two RON seeds {}",
        m.rmse,
        noise.rmse
    );
}

#[test]
fn every_sample_gltf_file_renders_and_the_gltf_and_glb_box_agree() {
    let files = [
        "BoxTextured/BoxTextured.gltf",
        "BoxTextured-glb/BoxTextured.glb",
        "Box-embedded/Box.gltf",
        "NormalTangentTest.glb",
        "NormalTangentMirrorTest.glb",
    ];
    let mut means = Vec::new();
    for f in files {
        let img = render_file(
            &data(&format!("gltf/{f}")),
            Overrides { size: Some((32, 32)), spp: Some(2), ..Default::default() },
        );
        assert!(img.pixels.iter().all(|p| p.is_finite()), "{f}");
        let m = img.pixels.iter().map(|p| p.x + p.y + p.z).sum::<f32>() / img.pixels.len() as f32;
        assert!(m > 0.1, "{f}: image mean {m}");
        means.push(m);
    }
    assert!((means[0] - means[1]).abs() / means[0] < 0.02, "BoxTextured .gltf and .glb: {} vs {}", means[0], means[1]);
}

#[test]
fn supplied_tangents_agree_with_generated_mikktspace_tangents() {
    let mut app = app_from_file(
        &data("gltf/NormalTangentMirrorTest.glb"),
        Overrides { size: Some((4, 4)), spp: Some(1), ..Default::default() },
    );
    app.run().unwrap();
    let meshes = &app.resources.meshes;
    let (mut agree, mut total) = (0, 0);
    for h in 0..meshes.len() as u32 {
        let m = meshes.get(prism::components::MeshHandle(h));
        if m.tangents.is_empty() {
            continue;
        }
        let supplied = prism::mesh_tangents::corner_tangents(m);
        let generated = prism::mesh_tangents::mikktspace_tangents(m);
        for (s, g) in supplied.iter().flatten().zip(generated.iter().flatten()) {
            total += 1;
            let (a, b) = (s.truncate().normalize_or_zero(), g.truncate().normalize_or_zero());
            if a.dot(b) > 0.95 && s.w.signum() == g.w.signum() {
                agree += 1;
            }
        }
    }
    assert!(total > 1000, "the file supplies tangents: {total} corners");
    assert!(agree as f64 > 0.95 * total as f64, "only {agree} of {total} corners agree in direction and sign");
}

#[test]
fn punctual_lights_convert_candela_and_lux_at_683_lumens_per_watt() {
    // A white Lambert floor, the camera looking straight down at it.
    let build = |light: &str, t: [f32; 3], r: Option<([f32; 3], f32)>| {
        let mut d = Doc::default();
        d.materials.push(diffuse([1.0; 3], true, None));
        let q = d.mesh(&QUAD, &QUAD_IDX, 0);
        d.nodes.push(node(q, [0.0; 3], Some(([1.0, 0.0, 0.0], -90.0)), [10.0; 3]));
        d.cameras.push(
            "{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.01, \"aspectRatio\": 1, \"znear\": 0.01}}"
                .into(),
        );
        d.nodes.push(format!(
            "{{\"camera\": 0, \"translation\": [0, 3, 0], \"rotation\": {:?}}}",
            [-(45f32.to_radians()).sin(), 0.0, 0.0, 45f32.to_radians().cos()]
        ));
        d.lights.push(light.to_string());
        let mut n = node(0, t, r, [1.0; 3]);
        n = n.replace("\"mesh\": 0, ", "\"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}, ");
        d.nodes.push(n);
        d.write("light.gltf")
    };
    let centre = |p: PathBuf| {
        let img = render_file(
            &p,
            Overrides {
                size: Some((4, 4)),
                spp: Some(4),
                integrator: Some("envlight(max_depth: 2)".into()),
                ..Default::default()
            },
        );
        img.pixels.iter().map(|p| p.x as f64).sum::<f64>() / img.pixels.len() as f64
    };
    let pi = std::f64::consts::PI;
    // 683 cd at 1 m: 1 W/m^2, radiance 1/pi from albedo 1.
    let point = centre(build("{\"type\": \"point\", \"intensity\": 683}", [0.0, 1.0, 0.0], None));
    assert!((point - 1.0 / pi).abs() < 0.01 / pi, "point: {point}");
    // 683 lux straight down: 1 W/m^2.
    let sun =
        centre(build("{\"type\": \"directional\", \"intensity\": 683}", [0.0; 3], Some(([1.0, 0.0, 0.0], -90.0))));
    assert!((sun - 1.0 / pi).abs() < 0.01 / pi, "directional: {sun}");
    // A spot pointing down: full intensity inside its inner cone.
    let spot = centre(build(
        "{\"type\": \"spot\", \"intensity\": 683, \"spot\": {\"innerConeAngle\": 0.3, \"outerConeAngle\": 0.6}}",
        [0.0, 1.0, 0.0],
        Some(([1.0, 0.0, 0.0], -90.0)),
    ));
    assert!((spot - 1.0 / pi).abs() < 0.01 / pi, "spot: {spot}");
}

#[test]
fn alpha_cutouts_let_shadow_rays_through_as_much_as_alpha_says() {
    // A floor lit by a point light 2 above it, a small occluder just under the light (outside the camera's view).
    let scene = |alpha: Option<&str>| {
        let occluder = match alpha {
            None => String::new(),
            Some(a) => format!(
                "(shape: Quad(), material: \"w\", transform: [Translate((0, 1.9, 0)), Rotate(axis: (1, 0, 0), degrees: 90), UniformScale(0.2)] {a}),"
            ),
        };
        format!(
            "(camera: (eye: (0, 1, 3), target: (0, 0, 0), fov: 10, size: (8, 8)), render: (integrator: envlight(max_depth: 2), sampler: independent),
              materials: {{\"w\": Lambert(albedo: 1)}},
              entities: [(shape: Quad(), material: \"w\", transform: [Rotate(axis: (1, 0, 0), degrees: -90), UniformScale(4)]),
                         {occluder}
                         (light: Point(intensity: (4, 4, 4), position: (0, 2, 0)))])"
        )
    };
    let mean = |alpha: Option<&str>| {
        let img = render_ron(&scene(alpha), Overrides { spp: Some(256), ..Default::default() });
        img.pixels.iter().map(|p| p.x as f64).sum::<f64>() / img.pixels.len() as f64
    };
    let lit = mean(None);
    let open = mean(Some(", alpha: (factor: 0)"));
    assert!((open - lit).abs() < 0.02 * lit, "an alpha-0 occluder casts no shadow: {open} vs {lit}");
    assert!(mean(Some("")) < 0.01 * lit, "an opaque occluder casts a full shadow");
    let mask_hole = mean(Some(", alpha: (factor: 0.3, mode: Mask(cutoff: 0.5))"));
    assert!((mask_hole - lit).abs() < 0.02 * lit, "alpha below the cutoff is a hole: {mask_hole}");
    assert!(
        mean(Some(", alpha: (factor: 0.8, mode: Mask(cutoff: 0.5))")) < 0.01 * lit,
        "alpha above the cutoff is opaque"
    );
    let blend = mean(Some(", alpha: (factor: 0.3, mode: Blend)"));
    assert!(
        (blend - 0.7 * lit).abs() < 0.03 * lit,
        "stochastic transparency passes 1 - alpha of the light: {blend} vs {}",
        0.7 * lit
    );
}

/// A valid one-triangle document as JSON, with the parts the malformed cases replace.
fn triangle(positions: &[f32], indices: &[u32]) -> String {
    let mut d = Doc::default();
    d.materials.push(diffuse([0.5; 3], true, None));
    d.mesh(positions, indices, 0);
    d.nodes.push("{\"mesh\": 0}".into());
    d.json()
}

fn gltf_error(name: &str, bytes: &[u8], needle: &str) {
    let p = scratch("gltf-bad").join(name);
    std::fs::write(&p, bytes).unwrap();
    let mut app = app_from_file(&p, Overrides { size: Some((4, 4)), spp: Some(1), ..Default::default() });
    let e = app.run().expect_err("malformed glTF must fail").to_string();
    assert!(!e.contains('\n'), "one line: {e}");
    assert!(e.contains(name), "names the file: {e}");
    assert!(e.contains(needle), "{needle:?}: {e}");
}

#[test]
fn malformed_gltf_files_are_one_line_errors() {
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let ok = triangle(&tri, &[0, 1, 2]);
    let mut app = app_from_file(
        &{
            let p = scratch("gltf-bad").join("ok.gltf");
            std::fs::write(&p, &ok).unwrap();
            p
        },
        Overrides { size: Some((4, 4)), spp: Some(1), ..Default::default() },
    );
    app.run().expect("the unmodified document loads");
    let glb = std::fs::read(data("gltf/BoxTextured-glb/BoxTextured.glb")).unwrap();
    gltf_error("truncated.glb", &glb[..glb.len() / 2], "GLB");
    let mut short = glb.clone();
    short[8..12].copy_from_slice(&1u32.to_le_bytes());
    gltf_error("short-length.glb", &short, "below the header");
    gltf_error("syntax.gltf", &ok.as_bytes()[..ok.len() - 30], "syntax.gltf:");
    gltf_error(
        "range.gltf",
        ok.replacen("\"count\": 3, \"type\": \"VEC3\"", "\"count\": 300, \"type\": \"VEC3\"", 1).as_bytes(),
        "overrun",
    );
    gltf_error(
        "type.gltf",
        ok.replacen(
            "\"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"",
            "\"componentType\": 5123, \"count\": 3, \"type\": \"VEC3\"",
            1,
        )
        .as_bytes(),
        "not allowed",
    );
    gltf_error(
        "buffer.gltf",
        ok.replacen("data:application/octet-stream;base64,", "missing.bin#", 1).as_bytes(),
        "buffer 0",
    );
    gltf_error("overflow.gltf", triangle(&tri, &[0, 1, 7]).as_bytes(), "index 2 is 7");
    gltf_error("nan.gltf", triangle(&[0.0, f32::NAN, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], &[0, 1, 2]).as_bytes(), "NaN");
    gltf_error(
        "required.gltf",
        ok.replacen("\"scene\": 0,", "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"], \"scene\": 0,", 1)
            .as_bytes(),
        "KHR_draco_mesh_compression",
    );
    gltf_error("reference.gltf", ok.replacen("{\"mesh\": 0}", "{\"mesh\": 5}", 1).as_bytes(), "invalid glTF");
    // gltf-json's own validation indexed this without a check and panicked (found by fuzzing).
    gltf_error(
        "position.gltf",
        ok.replacen("{\"POSITION\": 0}", "{\"POSITION\": 9}", 1).as_bytes(),
        "names accessor 9 but the file has 2 accessors",
    );
    // The gltf crate unwraps an image's uri (or its mimeType in a buffer view): found by fuzzing.
    gltf_error(
        "no-uri.gltf",
        ok.replacen("\"scene\": 0,", "\"scene\": 0, \"images\": [{\"name\": \"x\"}],", 1).as_bytes(),
        "image 0 has neither a uri nor a bufferView",
    );
    let with_image = ok
        .replacen("\"metallicFactor\": 0,", "\"metallicFactor\": 0, \"baseColorTexture\": {\"index\": 0},", 1)
        .replacen(
            "\"scene\": 0,",
            "\"scene\": 0, \"textures\": [{\"source\": 0}], \"images\": [{\"uri\": \"nope.png\"}],",
            1,
        );
    gltf_error("image.gltf", with_image.as_bytes(), "image 0 (nope.png)");
}

#[test]
fn the_camera_option_picks_a_gltf_camera_by_name_or_by_index_in_node_order() {
    let mut d = Doc::default();
    d.materials.push(diffuse([0.5; 3], true, None));
    let q = d.mesh(&QUAD, &QUAD_IDX, 0);
    d.nodes.push(node(q, [0.0; 3], None, [1.0; 3]));
    d.cameras.push("{\"name\": \"near\", \"type\": \"perspective\", \"perspective\": {\"yfov\": 0.5, \"aspectRatio\": 2, \"znear\": 0.01}}".into());
    // Unnamed, on an unnamed node (Cameras.gltf's orthographic camera): reachable by index only.
    d.cameras.push(
        "{\"type\": \"orthographic\", \"orthographic\": {\"xmag\": 1, \"ymag\": 1, \"znear\": 0.01, \"zfar\": 10}}"
            .into(),
    );
    d.cameras.push("{\"name\": \"ortho\", \"type\": \"orthographic\", \"orthographic\": {\"xmag\": 2, \"ymag\": 1, \"znear\": 0.01, \"zfar\": 10}}".into());
    d.nodes.push("{\"camera\": 0, \"translation\": [0, 0, 3]}".into());
    d.nodes.push("{\"camera\": 1, \"translation\": [0, 0, 4]}".into());
    d.nodes.push("{\"name\": \"side\", \"camera\": 2, \"translation\": [0, 0, 5]}".into());
    let path = d.write("cameras.gltf");
    let run = |camera: Option<&str>| {
        let mut app =
            app_from_file(&path, Overrides { spp: Some(1), camera: camera.map(str::to_string), ..Default::default() });
        app.run()?;
        let ortho = app
            .world
            .query_mut::<&prism::camera::Camera>()
            .into_iter()
            .any(|c| matches!(c.projection, prism::camera::Projection::Orthographic { .. }));
        Ok::<_, prism::error::PrismError>((app.resources.settings.width, app.resources.settings.height, ortho))
    };
    assert_eq!(run(None).unwrap(), (960, 480, false), "the first camera, aspect ratio 2");
    assert_eq!(run(Some("ortho")).unwrap(), (960, 480, true), "by camera name: xmag / ymag = 2");
    assert_eq!(run(Some("side")).unwrap(), (960, 480, true), "by node name");
    assert_eq!(run(Some("1")).unwrap(), (480, 480, true), "by index: the unnamed square orthographic camera");
    assert_eq!(run(Some("0")).unwrap(), (960, 480, false), "index 0 is the first camera");
    let e = run(Some("nope")).unwrap_err().to_string();
    assert!(e.contains("no camera named or numbered 'nope'") && e.contains("0 'near'"), "{e}");
    assert!(e.contains("1 (unnamed)") && e.contains("2 'ortho'"), "{e}");
    let e = run(Some("3")).unwrap_err().to_string();
    assert!(e.contains("'3'"), "{e}");
}

/// The mean of an image's pixels in the rows and columns of the fractions `[x0, x1) x [y0, y1)`.
fn region_mean(img: &prism::io::Image, x: (f32, f32), y: (f32, f32)) -> f32 {
    let (w, h) = (img.width as f32, img.height as f32);
    let (mut sum, mut n) = (0.0, 0);
    for py in (y.0 * h) as u32..(y.1 * h) as u32 {
        for px in (x.0 * w) as u32..(x.1 * w) as u32 {
            sum += img.get(px, py).element_sum() / 3.0;
            n += 1;
        }
    }
    sum / n as f32
}

#[test]
fn a_model_lit_only_by_its_emissive_decals_gets_the_default_sky_unless_told_not_to() {
    // An emissive quad (a decal) beside a grey one, no light: the sky must light the grey quad.
    let mut d = Doc::default();
    d.materials.push(diffuse([0.5; 3], true, None));
    d.materials.push(diffuse([0.5; 3], true, Some([2.0, 2.0, 2.0])));
    let grey = d.mesh(&QUAD, &QUAD_IDX, 0);
    let decal = d.mesh(&QUAD, &QUAD_IDX, 1);
    d.nodes.push(node(grey, [-1.0, 0.0, 0.0], None, [1.0; 3]));
    d.nodes.push(node(decal, [1.0, 0.0, 0.0], None, [1.0; 3]));
    d.cameras.push(format!(
        "{{\"type\": \"perspective\", \"perspective\": {{\"yfov\": {}, \"aspectRatio\": 2, \"znear\": 0.01}}}}",
        60f32.to_radians()
    ));
    d.nodes.push("{\"camera\": 0, \"translation\": [0, 0, 3]}".into());
    let path = d.write("decals.gltf");
    let o = |no_default_light| Overrides {
        size: Some((32, 16)),
        spp: Some(64),
        no_default_light,
        integrator: Some("envlight(max_depth: 2)".into()),
        ..Default::default()
    };
    // Direct light only (quads at x in [-2, 0] and [0, 2] fill the image's columns 0.21-0.5 and 0.5-0.79, rows
    // 0.21-0.79): a Lambert quad of albedo 0.5 under a uniform sky of 1 reflects 0.5 (half the sphere is
    // sky behind it, the front hemisphere is all sky: the decal quad is coplanar and does not shadow).
    let lit = render_file(&path, o(false));
    let grey_px = region_mean(&lit, (0.26, 0.45), (0.3, 0.7));
    assert!((grey_px - 0.5).abs() < 0.03, "grey quad under the default sky: {grey_px}, expected 0.5");
    let decal_px = region_mean(&lit, (0.55, 0.74), (0.3, 0.7));
    assert!((decal_px - 2.5).abs() < 0.1, "decal: emission 2 plus the sky's 0.5: {decal_px}");
    let dark = render_file(&path, o(true));
    assert_eq!(region_mean(&dark, (0.26, 0.45), (0.3, 0.7)), 0.0, "--no-default-light: nothing lights the grey quad");
    let decal_px = region_mean(&dark, (0.55, 0.74), (0.3, 0.7));
    assert!((decal_px - 2.0).abs() < 0.02, "the decal still emits 2: {decal_px}");
}

#[test]
fn the_automatic_camera_frames_the_model_not_a_ground_plane_a_hundred_times_its_size() {
    // TonemappingTest's layout: small objects on a huge ground quad, no camera.
    let mut d = Doc::default();
    d.materials.push(diffuse([0.8; 3], true, None));
    let cube = prism::mesh::MeshData::unit_cube();
    let pos: Vec<f32> = cube.positions.iter().flat_map(|p| p.to_array()).collect();
    let idx: Vec<u32> = cube.indices.iter().flatten().copied().collect();
    let cube = d.mesh(&pos, &idx, 0);
    let ground = d.mesh(&QUAD, &QUAD_IDX, 0);
    d.nodes.push(node(cube, [0.0, 0.5, 0.0], None, [1.0; 3]));
    d.nodes.push(node(ground, [0.0; 3], Some(([1.0, 0.0, 0.0], -90.0)), [100.0; 3]));
    let path = d.write("ground.gltf");
    let o = Overrides { size: Some((32, 32)), spp: Some(4), ..Default::default() };
    let mut app = app_from_file(&path, o);
    app.setup().unwrap();
    let cam = *app.world.query_mut::<&prism::camera::Camera>().into_iter().next().unwrap();
    // Framing the cube's bounding sphere (the cube spans [-1, 1]^3: radius sqrt(3)) at 40 degrees: 1.1 sqrt(3) /
    // sin(20 degrees) = 5.57 from its centre, not 300.
    let dist = (cam.eye - cam.target).length();
    assert!((dist - 5.57).abs() < 0.01, "camera {dist} from the cube's centre; the ground was framed");
    assert!((cam.target - glam::Vec3::new(0.0, 0.5, 0.0)).length() < 1e-4, "looks at the cube: {}", cam.target);
    assert!(cam.eye.z > cam.eye.x.abs(), "from the front (+z): {}", cam.eye);
}
