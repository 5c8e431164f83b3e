//! `prism watch` from the outside (the browser test, `tests/browser/watch_in_chromium.sh`, follows edits in a real
//! page): a render left alone writes the same bytes as `prism render` with the same flags; the server answers on
//! 127.0.0.1 with the page, the frame (linear RGB and counts of the right size) and the event stream; `--shard` and
//! `--resume` are one-line errors.

use crate::common::{prism, scene_path, scratch};
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Command, Stdio};

/// GET `path` from `addr` (HTTP/1.0, so the server closes the connection after the body): status line and body.
fn get(addr: &str, path: &str) -> (String, Vec<u8>) {
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    write!(s, "GET {path} HTTP/1.0\r\nHost: {addr}\r\n\r\n").unwrap();
    let mut bytes = vec![];
    s.read_to_end(&mut bytes).unwrap();
    let split = bytes.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&bytes[..split]).to_string();
    (head.lines().next().unwrap_or("").to_string(), bytes[split + 4..].to_vec())
}

#[test]
fn a_watch_render_left_alone_writes_what_prism_render_writes_and_serves_its_frame() {
    let dir = scratch("watch_bytes");
    let (watched, rendered) = (dir.join("watch.png"), dir.join("render.png"));
    let scene = scene_path("cornell_box.ron");
    // Without --passes: watch splits the samples into passes of 4, prism render into one pass; the bytes agree.
    let flags = ["--size", "48x48", "--spp", "32"];
    let mut child = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["watch", scene.to_str().unwrap(), "--port", "0", "-o", watched.to_str().unwrap()])
        .args(flags)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let mut addr = None;
    let mut done = false;
    for line in lines.by_ref() {
        let line = line.unwrap();
        if let Some(rest) = line.split(" at http://").nth(1) {
            addr = Some(rest.split('/').next().unwrap().to_string());
        }
        if line.starts_with("prism watch: done") {
            done = true;
            break;
        }
    }
    assert!(done, "the watch render did not finish");
    let addr = addr.expect("an address");
    let (status, page) = get(&addr, "/");
    assert!(status.contains("200") && String::from_utf8_lossy(&page).contains("EventSource"), "{status}");
    let (status, frame) = get(&addr, "/frame.bin");
    assert!(status.contains("200"), "{status}");
    assert_eq!(frame.len(), 48 * 48 * 16, "f32 RGB and a u32 count per pixel");
    let counts: Vec<u32> =
        frame[48 * 48 * 12..].chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect();
    assert!(counts.iter().all(|&c| c == 32), "every pixel has its 32 samples");
    let (status, png) = get(&addr, "/image.png");
    assert!(status.contains("200") && png.starts_with(b"\x89PNG"), "{status}");
    assert_eq!(get(&addr, "/nothing").0.split(' ').nth(1), Some("404"));
    child.kill().unwrap();
    let _ = child.wait();
    let out = prism(&[
        "render",
        scene.to_str().unwrap(),
        "-q",
        "-o",
        rendered.to_str().unwrap(),
        "--size",
        "48x48",
        "--spp",
        "32",
        "--passes",
        "4",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read(&watched).unwrap() == std::fs::read(&rendered).unwrap(), "watch and render PNGs differ");
    // The viewer's download is the same image at the same exposure.
    assert!(png == std::fs::read(&rendered).unwrap(), "the page's PNG download differs from prism render's");
}

#[test]
fn shards_and_resumes_are_not_for_watch() {
    let scene = scene_path("cornell_box.ron");
    for extra in [["--shard", "0/2"], ["--resume", "x.prism-film"]] {
        let out = prism(&["watch", scene.to_str().unwrap(), "--port", "0", extra[0], extra[1]]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.lines().count() == 1 && err.contains("prism render"), "{err}");
    }
}

#[test]
fn reloads_reuse_unchanged_meshes_and_the_accelerator_and_render_the_same_image() {
    use prism::app::reload_cache::{CacheHits, ReloadCache};
    let dir = scratch("reload_cache");
    let mesh = crate::common::data("meshes/cow.obj");
    let scene = dir.join("scene.ron");
    let write = |albedo: &str, eye: &str, scale: &str| {
        let text = format!(
            "(camera: (eye: {eye}, target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (32, 32)), render: (integrator: envlight, spp: 4),
              materials: {{\"m\": Lambert(albedo: {albedo})}},
              entities: [(shape: Mesh(path: \"{}\"), material: \"m\", transform: [UniformScale({scale})]), (light: Environment(radiance: (1, 1, 1)))])",
            mesh.display()
        );
        std::fs::write(&scene, text).unwrap();
    };
    // One load with the cache carried from the previous one: its image and the cache's hits so far.
    let load = |cache: ReloadCache| {
        let mut app = crate::common::app_from_file(&scene, prism::settings::Overrides::default());
        app.resources.insert(cache);
        app.run().unwrap();
        let img = prism::stages::film_image(&app.resources).unwrap();
        let accel = app.resources.scene.take().map(|s| s.accel);
        let mut cache = app.resources.remove::<ReloadCache>().unwrap();
        cache.finish(accel, true);
        (img, cache)
    };
    let fresh = || crate::common::render_file(&scene, prism::settings::Overrides::default());
    write("(0.8, 0.2, 0.2)", "(0, 0, 3)", "1");
    let (a, cache) = load(ReloadCache::default());
    assert_eq!(cache.hits, CacheHits { mesh_files: 0, accels: 0 });
    assert!(a.pixels == fresh().pixels);
    // A material and a camera edit: the mesh is not read again, the accelerator not built again.
    write("(0.2, 0.8, 0.2)", "(0.5, 0, 3)", "1");
    let (b, cache) = load(cache);
    assert_eq!(cache.hits, CacheHits { mesh_files: 1, accels: 1 });
    assert!(b.pixels == fresh().pixels, "a reused accelerator renders what a fresh build renders");
    // A transform edit changes the world-space triangles: the mesh is reused, the accelerator built again.
    write("(0.2, 0.8, 0.2)", "(0.5, 0, 3)", "1.1");
    let (c, cache) = load(cache);
    assert_eq!(cache.hits, CacheHits { mesh_files: 2, accels: 1 });
    assert!(c.pixels == fresh().pixels);
}

#[test]
fn a_pbrt_scenes_included_files_are_among_its_inputs_so_watch_follows_them() {
    let dir = scratch("pbrt_inputs");
    std::fs::write(dir.join("geometry.pbrt"), "Shape \"sphere\" \"float radius\" [1]\n").unwrap();
    let main = dir.join("main.pbrt");
    std::fs::write(
        &main,
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\nFilm \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\nWorldBegin\nLightSource \"infinite\"\nInclude \"geometry.pbrt\"\n",
    )
    .unwrap();
    let mut app = crate::common::app_from_file(&main, prism::settings::Overrides::default());
    app.setup().unwrap();
    let inputs: Vec<String> = app.resources.inputs.iter().map(|p| p.display().to_string()).collect();
    assert!(inputs.iter().any(|p| p.ends_with("geometry.pbrt")), "inputs: {inputs:?}");
}
