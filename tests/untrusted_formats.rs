//! Hostile inputs of the formats and outputs added last: glTF, PLY, pbrt, textures, films, reports. Each class is
//! bounded before the work or memory is spent (a one-line error naming the limit), loses no file the user did not
//! ask to write, refuses wrong data instead of rendering it, names the file, line or entity in its message, and
//! never echoes a file it was pointed at. Every case would have hung, aborted, overwritten or misled before.

use crate::common::{data, prism_args, scratch};
use crate::reliability::{assert_error, file, s};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn render_err(scene: &Path, dir: &Path, needles: &[&str]) -> String {
    assert_error(&["render", s(scene), "-o", s(&dir.join("o.png")), "-q", "--size", "8x8", "--spp", "1"], needles)
}

fn mkfifo(p: &Path) {
    let _ = std::fs::remove_file(p);
    assert!(Command::new("mkfifo").arg(p).status().unwrap().success());
}

/// A glTF document of `nodes` (JSON text of the array) and one triangle mesh, all in one file.
fn gltf_doc(nodes: &str, extra: &str) -> String {
    // One triangle: three float positions, base64 in a data URI.
    let positions: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|v| v.to_le_bytes()).collect();
    use base64::Engine;
    let b64 = base64::engine::general_purpose::STANDARD.encode(&positions);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": {nodes},
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{b64}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 0]}}]{extra}}}"#
    )
}

// ---- Work and memory bounded before they are spent ----------------------------------------------------------

#[test]
fn a_gltf_node_graph_of_shared_nodes_is_refused_by_its_instance_count() {
    let dir = scratch("uf-gltf-dag");
    // 40 levels of a node listed twice under the one above it: 2^40 instances from a small file.
    let mut nodes: Vec<String> = (0..40).map(|i| format!(r#"{{"children": [{0}, {0}]}}"#, i + 1)).collect();
    nodes.push(r#"{"mesh": 0}"#.into());
    let g = file(&dir, "dag.gltf", gltf_doc(&format!("[{}]", nodes.join(",")), ""));
    let t0 = Instant::now();
    render_err(&g, &dir, &["dag.gltf", "node instances", "1048576"]);
    assert!(t0.elapsed() < Duration::from_secs(10));
}

#[test]
fn gltf_sparse_accessors_without_a_buffer_view_are_bounded_before_they_are_read() {
    let dir = scratch("uf-gltf-sparse");
    // A billion zero positions with one sparse value: 12 GB from a few hundred bytes.
    let extra = r#", "extensionsUsed": []"#;
    let doc = gltf_doc(r#"[{"mesh": 0}]"#, extra).replace(
        r#""accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3""#,
        r#""accessors": [{"componentType": 5126, "count": 1000000000, "type": "VEC3",
            "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125},
                       "values": {"bufferView": 0}}"#,
    );
    let g = file(&dir, "sparse.gltf", doc);
    render_err(&g, &dir, &["sparse.gltf", "without a buffer view", "bytes"]);
}

#[test]
fn pbrt_include_fan_out_is_bounded() {
    let dir = scratch("uf-pbrt-fan");
    // Nine files, each including the next eight times: 16.7 M spheres from 72 lines.
    for k in 0..9 {
        let body = if k == 8 {
            "Shape \"sphere\" \"float radius\" 0.1\n".to_string()
        } else {
            format!("Include \"f{}.pbrt\"\n", k + 1).repeat(8)
        };
        file(&dir, &format!("f{k}.pbrt"), body);
    }
    let main =
        file(&dir, "main.pbrt", "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\nInclude \"f0.pbrt\"\n");
    let t0 = Instant::now();
    render_err(&main, &dir, &["more than 10000 files included"]);
    assert!(t0.elapsed() < Duration::from_secs(20));
}

#[test]
fn pbrt_objects_that_instance_each_other_are_bounded() {
    let dir = scratch("uf-pbrt-objects");
    let mut text = String::from("LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n");
    text += "ObjectBegin \"o0\"\nShape \"sphere\" \"float radius\" 0.1\nObjectEnd\n";
    for k in 1..40 {
        text += &format!("ObjectBegin \"o{k}\"\nObjectInstance \"o{0}\"\nObjectInstance \"o{0}\"\nObjectEnd\n", k - 1);
    }
    text += "ObjectInstance \"o39\"\n";
    let p = file(&dir, "objects.pbrt", text);
    render_err(&p, &dir, &["objects.pbrt", "ObjectInstance", "MiB"]);
}

#[test]
fn a_ply_element_without_properties_cannot_claim_a_huge_count() {
    let dir = scratch("uf-ply-empty");
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement junk 9223372036854775807\nelement face 1\nproperty list uchar int vertex_indices\n\
        end_header\n"
        .to_vec();
    for v in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        ply.extend_from_slice(&v.to_le_bytes());
    }
    ply.push(3);
    for i in [0i32, 1, 2] {
        ply.extend_from_slice(&i.to_le_bytes());
    }
    let p = file(&dir, "empty.ply", ply);
    let t0 = Instant::now();
    render_err(&p, &dir, &["empty.ply", "`junk`", "no properties"]);
    assert!(t0.elapsed() < Duration::from_secs(10));
}

#[test]
fn png_textures_are_held_to_the_decoded_pixel_cap() {
    let dir = scratch("uf-png-cap");
    // 16384 x 16384 grey is within the side limit and four times the 2^26-pixel cap.
    let png = file(&dir, "huge.png", crate::common::png_header_only(16384, 16384, 8, 0));
    let scene = file(
        &dir,
        "tex.ron",
        format!(
            "(camera: (size: (8, 8)), textures: {{\"t\": Image(path: {:?})}}, materials: {{\"m\": \
             Lambert(albedo: Texture(\"t\"))}}, entities: [(shape: Sphere(), material: \"m\")])",
            s(&png)
        ),
    );
    render_err(&scene, &dir, &["huge.png", "larger than Prism reads"]);
    assert_error(&["compare", s(&png), s(&png)], &["huge.png", "larger than Prism reads"]);
}

#[test]
fn a_report_suite_that_is_a_pipe_is_an_error_not_a_hang() {
    let dir = scratch("uf-report-fifo");
    let fifo = dir.join("suite.ron");
    mkfifo(&fifo);
    assert_error(&["report", s(&fifo), "-o", s(&dir.join("out"))], &["suite.ron", "named pipe"]);
}

#[test]
fn a_phong_light_sample_count_beyond_its_cap_is_an_error() {
    let dir = scratch("uf-phong-cap");
    let scene = file(&dir, "s.ron", crate::reliability::SPHERE);
    assert_error(
        &["render", s(&scene), "--integrator", "phong(light_samples: 100000000)", "-o", s(&dir.join("o.png"))],
        &["light_samples", "4096"],
    );
}

#[test]
fn ctrl_c_while_a_scene_loads_exits_at_once() {
    let dir = scratch("uf-ctrl-c-load");
    // 600,000 spheres: seconds of parsing and spawning before the first pass.
    let mut text = String::from("(camera: (size: (8, 8)), entities: [");
    for i in 0..600_000 {
        text += &format!("(shape: Sphere(center: ({}, 0, -20), radius: 0.001)),", i % 1000);
    }
    text += "])";
    let scene = file(&dir, "many.ron", text);
    let out = dir.join("o.png");
    let mut child = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["render", s(&scene), "-o", s(&out), "-q"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(400));
    let t0 = Instant::now();
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let status = child.wait().unwrap();
    let took = t0.elapsed();
    if status.success() {
        return; // loaded and rendered within 0.4 s: nothing to interrupt
    }
    assert!(took < Duration::from_secs(2), "exit {took:?} after Ctrl-C while loading");
    assert_eq!(status.code(), Some(130));
    assert!(!out.exists(), "nothing was rendered, so nothing is written");
}

// ---- No file the user did not ask for is touched ---------------------------------------------------------------

#[test]
fn a_render_cannot_overwrite_a_gltf_texture_or_buffer() {
    let dir = scratch("uf-gltf-inputs");
    for f in ["BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"] {
        std::fs::copy(data("gltf/BoxTextured").join(f), dir.join(f)).unwrap();
    }
    let before = std::fs::read(dir.join("CesiumLogoFlat.png")).unwrap();
    for target in ["CesiumLogoFlat.png", "BoxTextured0.bin"] {
        let out = dir.join(target);
        assert_error(&["render", s(&dir.join("BoxTextured.gltf")), "-o", s(&out), "-q"], &[target, "input"]);
    }
    assert_eq!(std::fs::read(dir.join("CesiumLogoFlat.png")).unwrap(), before);
}

#[test]
fn a_report_removes_only_what_its_own_earlier_run_wrote() {
    let dir = scratch("uf-report-files");
    let suite = crate::common::root().join("scenes/report/small.ron");
    // A folder it did not write: refused before anything is rendered or removed.
    let foreign = dir.join("foreign");
    std::fs::create_dir_all(foreign.join("img")).unwrap();
    let mine = file(&foreign.join("img"), "mine.png", "not a report picture");
    assert_error(&["report", s(&suite), "-o", s(&foreign), "--threads", "2"], &["foreign", "manifest"]);
    assert!(mine.is_file());
    // Its own folder, twice: the second run removes the first run's files (and only those).
    let own = dir.join("own");
    let _ = std::fs::remove_dir_all(&own);
    let run = || {
        let r = prism_args(&["report", s(&suite), "-o", s(&own), "--threads", "2"]);
        assert!(r.code == Some(0), "{r:?}");
    };
    run();
    let stale = file(&own, "stale.csv", "written by an earlier run");
    let manifest = std::fs::read_to_string(own.join(".prism-report")).unwrap();
    std::fs::write(own.join(".prism-report"), format!("{manifest}stale.csv\n")).unwrap();
    let kept = file(&own.join("img"), "kept.png", "the user's file");
    run();
    assert!(!stale.exists(), "a file the earlier run wrote is removed");
    assert!(kept.is_file(), "a file no run wrote survives");
    assert!(own.join("index.html").is_file());
}

#[test]
fn a_failed_image_write_leaves_no_partial_file() {
    let dir = scratch("uf-partial");
    // The output's name is taken by a folder with something in it: the temporary file is written, the rename onto
    // the folder fails, and the temporary file must go.
    let out = dir.join("busy.exr");
    std::fs::create_dir_all(out.join("inside")).unwrap();
    let img = prism::io::Image::new(2, 2, vec![glam::Vec3::ONE; 4]);
    for path in [out.clone(), dir.join("busy.png")] {
        if path.extension().is_some_and(|e| e == "png") {
            std::fs::create_dir_all(path.join("inside")).unwrap();
        }
        assert!(prism::io::write_image(&path, &img, 0.0).is_err());
    }
    let partial: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().contains(".partial"))
        .collect();
    assert!(partial.is_empty(), "left behind: {partial:?}");
}

// ---- Wrong results refused ------------------------------------------------------------------------------------

/// FNV-1a 64, the film file's checksum.
fn fnv1a(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

#[test]
fn a_film_with_a_negative_radiance_sum_is_refused() {
    let dir = scratch("uf-film-negative");
    let scene = file(&dir, "s.ron", crate::reliability::SPHERE);
    let film = dir.join("f.prism-film");
    let r = prism_args(&["render", s(&scene), "--spp", "2", "-o", s(&film), "-q"]);
    assert!(r.code == Some(0), "{r:?}");
    let mut bytes = std::fs::read(&film).unwrap();
    // The first pixel's red sum follows the header; make it negative and re-seal the checksum.
    let header = 8 + 4 + 8 + 16 + 9 + 16 + 4 + {
        let at = 8 + 4 + 8 + 16 + 9 + 16;
        u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize
    };
    bytes[header..header + 16].copy_from_slice(&(-5i128).to_le_bytes());
    let n = bytes.len() - 8;
    let sum = fnv1a(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
    std::fs::write(&film, &bytes).unwrap();
    assert_error(&["merge", s(&film), "-o", s(&dir.join("m.exr"))], &["f.prism-film", "negative radiance sum"]);
}

#[test]
fn wrong_values_in_pbrt_and_gltf_files_are_errors_not_images() {
    let dir = scratch("uf-wrong-values");
    let pbrt = file(
        &dir,
        "cold.pbrt",
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\nLightSource \"point\" \"blackbody I\" [0]\n",
    );
    render_err(&pbrt, &dir, &["cold.pbrt:4:", "not above 0"]);
    let skew = gltf_doc(r#"[{"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,1, 0,0,0,1]}]"#, "");
    render_err(&file(&dir, "skew.gltf", skew), &dir, &["skew.gltf", "bottom row", "affine"]);
    let mut glb = std::fs::read(data("gltf/BoxTextured-glb/BoxTextured.glb")).unwrap();
    glb.extend_from_slice(&[0; 64]);
    render_err(&file(&dir, "long.glb", glb), &dir, &["long.glb", "GLB header", "file length"]);
}

#[test]
fn radiance_beyond_the_films_range_is_reported_not_clipped_silently() {
    let dir = scratch("uf-saturation");
    let scene = file(
        &dir,
        "bright.ron",
        "(camera: (eye: (0, 0, 3), size: (8, 8)), render: (integrator: envlight, spp: 1),
          entities: [(shape: Sphere(), light: Area(radiance: (1e30, 1e30, 1e30)))])",
    );
    let r = prism_args(&["render", s(&scene), "-o", s(&dir.join("o.exr")), "-q"]);
    assert!(r.code == Some(0), "{r:?}");
    assert!(r.stderr.contains("reached the film's range"), "{}", r.stderr);
}

// ---- Messages name the place and the cause -------------------------------------------------------------------

#[test]
fn render_settings_of_a_scene_are_reported_at_their_line() {
    let dir = scratch("uf-settings-pos");
    for (text, needle) in [
        ("(camera: (size: (8, 8)),\n render: (spp: 0), entities: [])", "s.ron:2:11: render: spp must be at least 1"),
        ("(camera: (size: (8, 8)),\n render: (exposure: 1000), entities: [])", "s.ron:2:11: render: exposure"),
        ("(camera: (size: (8, 8)),\n render: (time: -1), entities: [])", "s.ron:2:11: render: time budget"),
        ("(camera: (size: (0, 8)), entities: [])", "s.ron:1:11: camera: image size 0x8 is empty"),
        (
            "(camera: (size: (8, 8)),\n render: (integrator: nope), entities: [])",
            "s.ron:2:11: render: unknown integrator",
        ),
        ("(entities: [])", "s.ron: the scene has no camera"),
    ] {
        let p = file(&dir, "s.ron", text);
        assert_error(&["render", s(&p), "-o", s(&dir.join("o.png")), "-q"], &[needle]);
    }
}

#[test]
fn messages_name_the_real_cause() {
    let dir = scratch("uf-messages");
    let far = file(&dir, "far.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n");
    render_err(&far, &dir, &["far.obj", "coordinate limit"]);
    let fifo = dir.join("pipe.pbrt");
    mkfifo(&fifo);
    render_err(&fifo, &dir, &["pipe.pbrt", "named pipe"]);
    let inc_dir = dir.join("a-folder.pbrt");
    std::fs::create_dir_all(&inc_dir).unwrap();
    let inc = file(&dir, "inc.pbrt", "WorldBegin\nInclude \"a-folder.pbrt\"\n");
    render_err(&inc, &dir, &["inc.pbrt:2:1", "a directory"]);
    let ply = file(&dir, "bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n0\n");
    let e = render_err(&ply, &dir, &["bad.ply", "PLY header"]);
    assert!(!e.contains("{") && !e.contains("Err("), "no Debug structures: {e}");
    let colour =
        file(&dir, "c.ron", "(camera: (size: (8, 8)), materials: {\"m\": Lambert(albedo: (0.5, 0.5))}, entities: [])");
    render_err(&colour, &dir, &["c.ron:1:", "`(r, g, b)`", "Texture("]);
    let quoted = file(&dir, "q.ron", "(camera: (size: (8, 8)), render: (integrator: \"envlight(max_depth: 2)\"))");
    render_err(&quoted, &dir, &["q.ron:1:", "without quotes", "integrator: envlight(max_depth: 2)"]);
    let r = prism_args(&[]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.lines().any(|l| l.starts_with("error:")), "{}", r.stderr);
}

#[test]
fn a_basis_ktx2_texture_falls_back_to_the_factor_with_a_warning_and_a_malformed_one_is_an_error() {
    let dir = scratch("uf-ktx2");
    use base64::Engine;
    let render = |ktx2: &[u8], name: &str| {
        let ktx2 = base64::engine::general_purpose::STANDARD.encode(ktx2);
        let extra = format!(
            r#", "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "data:image/ktx2;base64,{ktx2}"}}]"#
        );
        let doc = gltf_doc(r#"[{"mesh": 0}]"#, &extra)
            .replace(r#""attributes": {"POSITION": 0}"#, r#""attributes": {"POSITION": 0}, "material": 0"#);
        let g = file(&dir, name, doc);
        prism_args(&["render", s(&g), "-o", s(&dir.join("o.png")), "--size", "8x8", "--spp", "1"])
    };
    // VK_FORMAT_UNDEFINED with BasisLZ: a valid file Prism does not transcode.
    let r = render(&crate::common::forged_ktx2(0, 4, 4, 1, &[0; 16]), "basis.gltf");
    assert!(r.code == Some(0), "{r:?}");
    assert!(r.stderr.contains("KTX2 texture Basis Universal"), "{}", r.stderr);
    // A KTX2 magic and a zero header: malformed, named.
    let zeros = [&[0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n'][..], &[0; 68]].concat();
    let r = render(&zeros, "zeros.gltf");
    assert!(r.is_clean_error() && r.error_line().contains("image 0: cannot decode KTX2 texture"), "{r:?}");
}

// ---- Untrusted scenes -----------------------------------------------------------------------------------------

#[test]
fn an_included_file_that_is_no_scene_is_never_echoed() {
    let dir = scratch("uf-no-echo");
    let secret = file(&dir, "secret.txt", "root:x:0:0:hunter2:/root:/bin/bash\nsecond line\n");
    let main = file(&dir, "main.pbrt", format!("WorldBegin\nInclude {:?}\n", s(&secret)));
    let e = render_err(&main, &dir, &["secret.txt:1:1"]);
    assert!(!e.contains("hunter2") && !e.contains("root:x"), "{e}");
}

#[test]
fn allow_read_refuses_paths_outside_its_folders_symlinks_included() {
    let dir = scratch("uf-allow-read");
    let jail = dir.join("jail");
    std::fs::create_dir_all(&jail).unwrap();
    let outside = file(&dir, "outside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let link = jail.join("link.obj");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&outside, &link).unwrap();
    let inside = file(&jail, "inside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let out = dir.join("o.png");
    let ok = |mesh: &Path| {
        file(&jail, "s.ron", format!("(camera: (size: (8, 8)), entities: [(shape: Mesh(path: {:?}))])", s(mesh)))
    };
    let args = |scene: &Path| -> Vec<String> {
        ["render", s(scene), "-o", s(&out), "-q", "--allow-read", s(&jail)].iter().map(|a| a.to_string()).collect()
    };
    let scene = ok(&inside);
    let r = prism_args(&args(&scene).iter().map(String::as_str).collect::<Vec<_>>());
    assert!(r.code == Some(0), "a mesh inside the folder renders: {r:?}");
    for mesh in [&outside, &link] {
        let scene = ok(mesh);
        let a = args(&scene);
        assert_error(&a.iter().map(String::as_str).collect::<Vec<_>>(), &["--allow-read"]);
    }
}

#[test]
fn a_fan_triangulated_polygon_builds_every_accelerator_in_near_linear_time() {
    let dir = scratch("uf-fan");
    // One polygon of 80,000 vertices on a circle: 79,998 slivers meeting at vertex 1. The BVH's PLOC build and the
    // kd-tree's splits turned quadratic on it (23.5 s and 70 s, 3.7 GB); now seconds at most.
    let n = 80_000;
    let mut obj = String::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        obj += &format!("v {:.7} {:.7} 0\n", a.cos(), a.sin());
    }
    obj += "f";
    for i in 1..=n {
        obj += &format!(" {i}");
    }
    obj.push('\n');
    let p = file(&dir, "fan.obj", obj);
    for accel in ["bvh", "cwbvh", "kdtree"] {
        let t0 = Instant::now();
        let r = prism_args(&[
            "render",
            s(&p),
            "--accel",
            accel,
            "--size",
            "16x16",
            "--spp",
            "1",
            "-q",
            "-o",
            s(&dir.join("o.png")),
        ]);
        assert!(r.code == Some(0), "{accel}: {r:?}");
        assert!(t0.elapsed() < Duration::from_secs(20), "{accel}: {:?}", t0.elapsed());
    }
}
