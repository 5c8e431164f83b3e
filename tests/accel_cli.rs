//! The accelerators through the command line: `--grid` and scene settings give one-line errors, `prism bench`
//! prints its table and chart, and `prism bench --export-rays` writes the rays it times with brute force's answers
//! (the file the Embree comparison reads).

use crate::accel::{scene, setup_file};
use crate::common::data;
use prism::geometry::Ray;
use prism::ray_sets::{camera_rays, secondary_rays};
use prism::settings::AccelKind;

#[test]
fn bad_grid_options_and_scene_settings_give_one_line_errors() {
    let dir = crate::common::scratch("grid-cli");
    let scene = dir.join("s.ron");
    std::fs::write(&scene, "(camera: (size: (8, 8)), entities: [(shape: Sphere())])").unwrap();
    let out = dir.join("s.png");
    let run = |extra: &[&str]| {
        let mut args = vec!["render", scene.to_str().unwrap(), "-q", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = crate::common::prism(&args);
        (o.status.success(), String::from_utf8_lossy(&o.stderr).to_string())
    };
    for (extra, needle) in [
        (vec!["--grid", "0", "4", "4"], "0 cells"),
        (vec!["--grid", "10000", "1", "1"], "at most 4096"),
        (vec!["--grid", "4096", "4096", "4"], "cells (at most"),
        (vec!["--accel", "bvh", "--grid", "2", "2", "2"], "--accel is bvh"),
        (vec!["--grid", "2", "x", "2"], "invalid"),
        (vec!["--accel", "octree"], "bvh, kdtree, grid or brute"),
    ] {
        // The first line is the error (clap adds a usage hint below its own parse errors).
        let (ok, err) = run(&extra);
        let first = err.lines().next().unwrap_or("");
        assert!(!ok && !err.contains("panicked") && first.starts_with("error:"), "{err}");
        assert!(first.contains(needle), "{extra:?}: {err}");
    }
    for (text, needle) in [
        ("(camera: (), render: (grid: (0, 1, 1)), entities: [])", "0 cells"),
        ("(camera: (), render: (accel: kdtree, grid: (2, 2, 2)), entities: [])", "needs accel: grid"),
    ] {
        std::fs::write(&scene, text).unwrap();
        let (ok, err) = run(&[]);
        assert!(!ok && err.contains("s.ron") && err.contains(needle) && err.lines().count() == 1, "{err}");
    }
    // Valid: every accelerator renders the scene, and a grid resolution from the scene file is used.
    std::fs::write(&scene, "(camera: (size: (8, 8)), render: (grid: (3, 2, 1)), entities: [(shape: Sphere())])")
        .unwrap();
    for accel in ["bvh", "kdtree", "grid", "brute"] {
        let (ok, err) = run(&["--accel", accel]);
        assert!(ok, "{accel}: {err}");
    }
}

#[test]
fn prism_bench_prints_the_table_and_writes_the_chart() {
    let dir = crate::common::scratch("bench");
    let chart = dir.join("accel.svg");
    let scene = data("mit6837/assignment5/bunny_200.obj");
    let o = crate::common::prism(&[
        "bench",
        scene.to_str().unwrap(),
        "--accel",
        "all",
        "--seconds",
        "0.02",
        "--size",
        "32",
        "--chart",
        chart.to_str().unwrap(),
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for accel in ["| bvh |", "| kdtree |", "| grid |", "| brute |"] {
        assert!(out.contains(accel), "{accel} missing:\n{out}");
    }
    let svg = std::fs::read_to_string(&chart).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("kdtree camera"), "{svg}");
}

/// `prism bench --export-rays` writes exactly the rays `prism bench` traces (regenerated here from the scene) with
/// the same triangles and, for every ray, the closest hit and occlusion answer of brute force: what another engine
/// timed on the file (`benches/embree/`) is checked against. Scenes with spheres are refused with one line, and a
/// truncated file is refused on reading.
#[test]
fn prism_bench_exports_its_rays_and_brute_force_answers() {
    use prism::ray_file::{MISS, RaySetFile};
    let dir = crate::common::scratch("export-rays");
    let scene_path = data("mit6837/assignment5/bunny_200.obj");
    let args = ["bench", scene_path.to_str().unwrap(), "--accel", "bvh", "--seconds", "0.01", "--size", "24"];
    let o = crate::common::prism(&[&args[..], &["--export-rays", dir.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = RaySetFile::read(&dir.join("bunny_200.prism-rays")).unwrap();
    assert!(!dir.join("bunny_200.prism-rays.partial").exists());
    let app = setup_file(&scene_path, AccelKind::Brute);
    let truth = scene(&app);
    assert_eq!(file.tris, truth.prims.tris);
    let camera = camera_rays(truth, 24, 24);
    let (bounce, shadow) = secondary_rays(truth, &camera, 1);
    let same = |a: &[Ray], b: &[Ray]| {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.origin == y.origin && x.dir == y.dir && x.tmax == y.tmax)
    };
    assert!(same(&file.sets[0], &camera) && same(&file.sets[1], &bounce) && same(&file.sets[2], &shadow));
    assert!(file.sets.iter().all(|s| !s.is_empty()), "every set has rays");
    let mut hits = 0;
    for (set, answers) in file.sets[..2].iter().zip(&file.hits) {
        for (r, &(prim, t)) in set.iter().zip(answers) {
            match truth.accel.intersect(&truth.prims, r) {
                Some(h) => {
                    assert!((h.t - t).abs() <= 1e-5 * h.t && (h.prim == prim || h.t == t), "{h:?} vs {prim} {t}");
                    hits += 1;
                }
                None => assert!(prim == MISS && t == f32::INFINITY),
            }
        }
    }
    let total = file.sets[0].len() + file.sets[1].len();
    assert!(hits > 50 && hits < total, "both hits and misses are checked: {hits} of {total}");
    for (r, &o) in file.sets[2].iter().zip(&file.occluded) {
        assert_eq!(truth.accel.occluded(&truth.prims, r), o);
    }
    // Refusals.
    let sphere = dir.join("sphere.ron");
    std::fs::write(&sphere, "(camera: (), entities: [(shape: Sphere())])").unwrap();
    let o = crate::common::prism(&["bench", sphere.to_str().unwrap(), "--export-rays", dir.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("only triangle scenes") && err.trim().lines().count() == 1, "{err}");
    let bytes = std::fs::read(dir.join("bunny_200.prism-rays")).unwrap();
    std::fs::write(dir.join("short.prism-rays"), &bytes[..bytes.len() - 4]).unwrap();
    let e = RaySetFile::read(&dir.join("short.prism-rays")).unwrap_err().to_string();
    assert!(e.contains("short.prism-rays") && e.contains("does not match its header"), "{e}");
}
