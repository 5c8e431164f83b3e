//! Resumable renders and exact shards: a render resumed from its `.prism-film` (after a checkpoint or a real Ctrl-C)
//! and a render merged from `--shard K/N` parts are bit-identical to the uninterrupted one-process render, for the
//! path tracer (shards split passes) and the photon mapper (shards split pixel rows); broken, foreign or mismatched
//! film files are one-line errors.

use crate::common::{prism, scene_path, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

fn render(args: &[&str]) {
    let out = prism(args);
    assert!(out.status.success(), "prism {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The one-process render and the merge of `n` shards of the same render: equal EXR bytes.
fn shards_merge_exactly(name: &str, scene: &Path, extra: &[&str], n: u32) {
    let dir = scratch(name);
    let whole = dir.join("whole.exr");
    let mut args = vec!["render", s(scene), "-o", s(&whole), "-q"];
    args.extend_from_slice(extra);
    render(&args);
    let parts: Vec<PathBuf> = (0..n).map(|k| dir.join(format!("part{k}.prism-film"))).collect();
    for (k, part) in parts.iter().enumerate() {
        let shard = format!("{k}/{n}");
        let mut args = vec!["render", s(scene), "--shard", &shard, "-o", s(part), "-q"];
        args.extend_from_slice(extra);
        render(&args);
    }
    let merged = dir.join("merged.exr");
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend_from_slice(&["-o", s(&merged)]);
    render(&args);
    assert!(bytes(&whole) == bytes(&merged), "{name}: merged shards differ from the one-process render");
}

#[test]
fn path_traced_shards_merge_bit_identically() {
    let scene = scene_path("cornell_box.ron");
    let extra = ["--size", "48x48", "--spp", "12", "--passes", "6"];
    shards_merge_exactly("shards-envlight-2", &scene, &extra, 2);
    shards_merge_exactly("shards-envlight-4", &scene, &extra, 4);
    // Adaptive: every shard after the first re-renders the pilot pass for the rates, and adds only its own passes.
    let adaptive = ["--size", "48x48", "--spp", "12", "--passes", "6", "--adaptive"];
    shards_merge_exactly("shards-envlight-adaptive-3", &scene, &adaptive, 3);
    // With an explicit pattern, stratified over the pilot and then over each pixel's samples after it.
    let pattern = ["--size", "48x48", "--spp", "12", "--passes", "6", "--adaptive", "--pattern", "stratified"];
    shards_merge_exactly("shards-envlight-adaptive-pattern-2", &scene, &pattern, 2);
}

#[test]
fn photon_mapping_row_shards_merge_bit_identically() {
    let scene = scene_path("cornell_caustic.ron");
    let extra = ["--size", "40x40", "--spp", "4", "--integrator", "ppm"];
    shards_merge_exactly("shards-ppm-3", &scene, &extra, 3);
}

#[test]
fn bidirectional_shards_merge_bit_identically() {
    // Light tracing splats anywhere on the film: the fixed-point sums of each shard's passes still add up exactly.
    let scene = scene_path("cornell_caustic.ron");
    let extra = ["--size", "40x40", "--spp", "6", "--passes", "3", "--integrator", "vcm"];
    shards_merge_exactly("shards-vcm-3", &scene, &extra, 3);
}

/// Render 2 of 4 passes into a film (a checkpoint's state), resume it, compare with the uninterrupted render.
fn resume_is_exact(name: &str, integrator: &str, adaptive: &str) {
    let dir = scratch(name);
    let scene = scene_path("cornell_caustic.ron");
    let base = ["--size", "40x40", "--integrator", integrator, "--passes", "4", "--adaptive", adaptive, "-q"];
    let whole = dir.join("whole.exr");
    let mut args = vec!["render", s(&scene), "--spp", "8", "-o", s(&whole)];
    args.extend_from_slice(&base);
    render(&args);
    // Half the render: the same plan (spp 8 in 4 passes) stopped after 2 passes by a time budget of 1 ns.
    let film = dir.join("half.prism-film");
    let out = prism(&[
        "render",
        s(&scene),
        "--spp",
        "8",
        "--size",
        "40x40",
        "--integrator",
        integrator,
        "--passes",
        "4",
        "--adaptive",
        adaptive,
        "-q",
        "--time",
        "0.000000001",
        "-o",
        s(&film),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let resumed = dir.join("resumed.exr");
    let mut args = vec!["render", s(&scene), "--spp", "8", "--resume", s(&film), "-o", s(&resumed)];
    args.extend_from_slice(&base);
    render(&args);
    assert!(bytes(&whole) == bytes(&resumed), "{name}: resumed render differs from the uninterrupted one");
}

#[test]
fn resumed_renders_equal_uninterrupted_ones() {
    resume_is_exact("resume-envlight", "envlight(max_depth: 12)", "false");
    // Adaptive: the resumed process re-renders the pilot pass for the rates (the film already holds it).
    resume_is_exact("resume-envlight-adaptive", "envlight(max_depth: 12)", "true");
    resume_is_exact("resume-ppm", "ppm(max_depth: 12)", "false");
    resume_is_exact("resume-vcm", "vcm(max_depth: 12)", "false");
}

#[test]
fn ctrl_c_saves_a_film_that_resumes_exactly() {
    // A real SIGINT in the middle of a long render: the process writes the image and the film of its complete
    // passes and exits non-zero; resuming finishes the same image as an uninterrupted render.
    let dir = scratch("ctrl-c");
    let scene = scene_path("cornell_box.ron");
    let common = ["--size", "64x64", "--spp", "800", "--passes", "100", "--threads", "1"];
    let img = dir.join("out.exr");
    let mut child = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["render", s(&scene), "-o", s(&img), "--checkpoint", "0"])
        .args(common)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let status = child.wait().unwrap();
    let film = dir.join("out.prism-film");
    if status.success() {
        // The render finished before the signal (a very fast machine): nothing to resume.
        return;
    }
    assert!(film.is_file(), "no film saved on Ctrl-C");
    assert!(img.is_file(), "no image saved on Ctrl-C");
    let resumed = dir.join("resumed.exr");
    let mut args = vec!["render", s(&scene), "--resume", s(&film), "-o", s(&resumed), "-q"];
    args.extend_from_slice(&common);
    render(&args);
    let whole = dir.join("whole.exr");
    let mut args = vec!["render", s(&scene), "-o", s(&whole), "-q"];
    args.extend_from_slice(&common);
    render(&args);
    assert!(bytes(&whole) == bytes(&resumed), "resumed after Ctrl-C differs from the uninterrupted render");
}

#[test]
fn broken_foreign_and_mismatched_films_are_one_line_errors() {
    let dir = scratch("bad-films");
    let scene = scene_path("cornell_box.ron");
    let film = dir.join("a.prism-film");
    render(&["render", s(&scene), "--size", "16x16", "--spp", "2", "-o", s(&film), "-q"]);
    let good = bytes(&film);
    let check = |name: &str, content: &[u8], args: &[&str], needle: &str| {
        let p = dir.join(name);
        std::fs::write(&p, content).unwrap();
        let mut a = vec!["render", s(&scene), "--size", "16x16", "--spp", "2", "--resume", s(&p), "-q"];
        a.extend_from_slice(args);
        let out = prism(&a);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(needle) && err.trim().lines().count() == 1, "{name}: {err}");
    };
    check("truncated.prism-film", &good[..good.len() / 2], &[], "truncated");
    let mut flipped = good.clone();
    flipped[100] ^= 0x40;
    check("flipped.prism-film", &flipped, &[], "checksum");
    check("foreign.prism-film", b"PK\x03\x04 not a film at all", &[], "not a Prism film");
    check("seed.prism-film", &good, &["--seed", "7"], "different scene file or settings");
    check("integrator.prism-film", &good, &["--integrator", "phong"], "rendered with");
    // Merging: a missing shard, a shard given twice, parts of different renders.
    let p0 = dir.join("p0.prism-film");
    let p1 = dir.join("p1.prism-film");
    render(&["render", s(&scene), "--size", "16x16", "--spp", "4", "--shard", "0/2", "-o", s(&p0), "-q"]);
    render(&[
        "render",
        s(&scene),
        "--size",
        "16x16",
        "--spp",
        "4",
        "--shard",
        "1/2",
        "--seed",
        "3",
        "-o",
        s(&p1),
        "-q",
    ]);
    let out = dir.join("m.exr");
    for (args, needle) in [
        (vec!["merge", s(&p0), "-o", s(&out)], "missing"),
        (vec!["merge", s(&p0), s(&p0), "-o", s(&out)], "twice"),
        (vec!["merge", s(&p0), s(&p1), "-o", s(&out)], "fingerprint"),
        (vec!["merge", s(&p0), "-o", s(&p0)], "overwrite"),
    ] {
        let o = prism(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(needle), "{args:?}: {err}");
    }
}

/// Checkpoints come every `--checkpoint` seconds: the first one interval into the render, not after its first pass
/// (writing images and the film is one thread's work; after every first pass it stalled the other threads of every
/// short render, 20 ms of a 0.6 s `ppm` render), then one interval after the last.
#[test]
fn the_first_checkpoint_comes_one_interval_into_the_render() {
    use prism::stages::checkpoint_due;
    use std::time::Duration;
    let every = Duration::from_secs(10);
    let s = Duration::from_secs_f64;
    assert!(!checkpoint_due(None, s(0.05), every), "not after a first pass of 50 ms");
    assert!(!checkpoint_due(None, s(9.9), every));
    assert!(checkpoint_due(None, s(10.0), every), "one interval into the render");
    assert!(!checkpoint_due(Some(s(3.0)), s(25.0), every), "the last checkpoint was 3 s ago");
    assert!(checkpoint_due(Some(s(10.5)), s(25.0), every));
}
