//! Regression tests for two hostile-input classes of issue 11 (the others are in `reliability.rs`): hangs (an
//! interrupt stops any render or measurement promptly) and lost work (what was measured is written, outputs that
//! cannot be written or would overwrite an input fail before rendering).

use crate::common::{prism_args, root, scratch};
use crate::reliability::{SPHERE, assert_error, file, s};
use std::time::{Duration, Instant};

// ---- Hangs ---------------------------------------------------------------------------------------------------

#[test]
fn bench_on_a_scene_where_no_camera_ray_hits_anything_finishes() {
    let dir = scratch("rel-bench-miss");
    let scene = file(
        &dir,
        "miss.ron",
        "(camera: (eye: (0, 0, 0), target: (0, 0, -1), size: (8, 8)), entities: [(shape: Sphere(center: (0, 0, 10)))])",
    );
    let r = prism_args(&["bench", s(&scene), "--seconds", "0.05", "--size", "16"]);
    assert!(r.code == Some(0) && !r.timed_out, "{r:?}");
}

/// Start `prism` with `args`, send SIGINT after `after`, and return (exit code, seconds from the signal to exit).
fn interrupt(args: &[&str], after: Duration) -> (Option<i32>, f64, String) {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let t0 = Instant::now();
    let _ = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let deadline = Instant::now() + Duration::from_secs(30);
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break Some(st);
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    let _ = std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err);
    (status.and_then(|s| s.code()), t0.elapsed().as_secs_f64(), err)
}

#[test]
fn ctrl_c_stops_a_pixel_of_exponential_phong_work_or_huge_spp() {
    let dir = scratch("rel-ctrl-c");
    // A glass sphere inside a mirror box: phong splits every glass hit into reflection and refraction and no ray
    // leaves, so one camera sample at max_depth 64 is about 2^64 rays (depth 20 already takes 20 s).
    let scene = file(
        &dir,
        "hall.ron",
        "(camera: (eye: (0, 0, 1.5), target: (0, 0, 0), fov: 10, size: (1, 1)),
          materials: {\"mirror\": Phong(reflective: 1), \"glass\": Phong(transparent: 1, reflective: 0.5, ior: 1.5)},
          entities: [
            (shape: Sphere(radius: 0.5), material: \"glass\"),
            (shape: Cube, material: \"mirror\", transform: [UniformScale(2)]),
            (light: Point(intensity: (1, 1, 1), position: (0, 1.5, 0))),
          ])",
    );
    let out = dir.join("o.png");
    let (code, secs, err) = interrupt(
        &["render", s(&scene), "-o", s(&out), "--integrator", "phong(max_depth: 64)", "--threads", "1", "-q"],
        Duration::from_millis(1500),
    );
    assert!(code.is_some(), "phong did not stop within 30 s of Ctrl-C");
    assert!(code != Some(0) && !err.contains("panicked"), "{err}");
    assert!(secs < 10.0, "took {secs} s to stop");
    let (code, secs, err) = interrupt(
        &["render", s(&scene), "-o", s(&out), "--spp", "4000000000", "--passes", "1", "--threads", "1", "-q"],
        Duration::from_millis(1500),
    );
    assert!(code.is_some() && code != Some(0) && !err.contains("panicked"), "{err}");
    assert!(secs < 10.0, "took {secs} s to stop");
}

#[test]
fn converge_interrupted_writes_the_points_measured_so_far() {
    let dir = scratch("rel-converge-int");
    let reference = root().join("../shared/refs/cornell.exr");
    let out = dir.join("conv");
    let scene = root().join("scenes/cornell_box.ron");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["converge", s(&scene), "--reference", s(&reference), "--integrator", "envlight", "--spp"])
        .arg("1,2,100000")
        .args(["--threads", "1", "-o", s(&out)])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the first points are written, then interrupt the long third render.
    let csv = out.join("convergence.csv");
    let deadline = Instant::now() + Duration::from_secs(120);
    while Instant::now() < deadline && std::fs::read_to_string(&csv).map_or(true, |t| t.lines().count() < 3) {
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(300));
    let _ = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let status = child.wait().unwrap();
    let mut err = String::new();
    let _ = std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err);
    assert!(!status.success() && !err.contains("panicked"), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 3, "header and the two finished points: {text}");
    assert!(out.join("rmse_vs_time.svg").is_file());
}

// ---- Data loss -----------------------------------------------------------------------------------------------

#[test]
fn unwritable_outputs_fail_before_rendering() {
    let dir = scratch("rel-outputs");
    let scene = file(&dir, "s.ron", SPHERE);
    // A render of 10^6 samples per pixel would take minutes: the error must come first.
    let heavy = ["--spp", "1000000", "-q"];
    let t0 = Instant::now();
    let missing = dir.join("no/such/dir/o.png");
    assert_error(&[&["render", s(&scene), "-o", s(&missing)][..], &heavy].concat(), &["does not exist"]);
    let is_dir = dir.join("adir.png");
    std::fs::create_dir_all(&is_dir).unwrap();
    assert_error(&[&["render", s(&scene), "-o", s(&is_dir)][..], &heavy].concat(), &["is a directory"]);
    // converge -o naming a file, merge -o into a missing directory.
    let reference = root().join("../shared/refs/cornell.exr");
    assert_error(
        &["converge", s(&scene), "--reference", s(&reference), "--integrator", "phong", "--spp", "1", "-o", s(&scene)],
        &[s(&scene)],
    );
    assert!(t0.elapsed() < Duration::from_secs(30), "the errors came after rendering");
}

#[test]
fn outputs_that_would_overwrite_a_scene_input_are_refused() {
    let dir = scratch("rel-overwrite");
    let tex = dir.join("tex.png");
    std::fs::copy(root().join("scenes/assets/checker_f.png"), &tex).unwrap();
    let env = dir.join("sky.exr");
    std::fs::write(&env, std::fs::read(root().join("../shared/refs/furnace.exr")).unwrap_or_default()).unwrap();
    let scene = file(
        &dir,
        "s.ron",
        "(camera: (size: (8, 8)), textures: {\"t\": Image(path: \"tex.png\")}, materials: {\"m\": Lambert(albedo: \
         Texture(\"t\"))}, entities: [(shape: Sphere(), material: \"m\")])",
    );
    let before = std::fs::read(&tex).unwrap();
    assert_error(&["render", s(&scene), "-o", s(&tex), "-q"], &["would overwrite", "tex.png"]);
    // The same file through another name (a hard link).
    let link = dir.join("link.png");
    let _ = std::fs::remove_file(&link);
    std::fs::hard_link(&tex, &link).unwrap();
    assert_error(&["render", s(&scene), "-o", s(&link), "-q"], &["would overwrite"]);
    assert_eq!(std::fs::read(&tex).unwrap(), before, "the input was modified");
    if std::fs::metadata(&env).map(|m| m.len() > 0).unwrap_or(false) {
        let sky = file(
            &dir,
            "sky.ron",
            "(camera: (size: (8, 8)), entities: [(light: Environment(map: \"sky.exr\", layout: Equirect))])",
        );
        assert_error(&["render", s(&sky), "-o", s(&env), "-q"], &["would overwrite", "sky.exr"]);
    }
    // A merge output naming one of its parts, by another path.
    let part = dir.join("p.prism-film");
    std::fs::write(&part, b"x").unwrap();
    let alias = format!("{}/./p.prism-film", s(&dir));
    assert_error(&["merge", s(&part), "-o", &alias], &["overwrite"]);
}
