//! Hostile command lines (every numeric option with zero, negative, NaN, infinite, huge and malformed values;
//! malformed integrator specs), hostile file kinds (directories, FIFOs, devices, empty and missing files as every
//! kind of input), outputs that cannot or must not be written, and damaged `.prism-film` files for `--resume` and
//! `prism merge`.

use super::scenes::Rng;
use super::{Case, Expect, dir, path_str};
use crate::common::{data, refs};
use std::path::Path;

fn args_case(class: &'static str, name: String, args: Vec<String>, expect: Expect) -> Case {
    let refs: Vec<&dyn AsRef<std::ffi::OsStr>> = args.iter().map(|a| a as &dyn AsRef<std::ffi::OsStr>).collect();
    Case::new(class, name, &refs, expect)
}

fn option_cases(v: &mut Vec<Case>, scene: &Path, out: &Path) {
    let base = |extra: &[&str]| {
        let mut a = vec!["render".to_string(), path_str(scene), "-o".into(), path_str(out), "-q".into()];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let numeric: [(&str, &[&str]); 13] = [
        ("--spp", &["0", "-1", "4294967296", "1.5", "NaN", "x", ""]),
        ("--passes", &["0", "-1", "4294967296", "1e3"]),
        ("--size", &["0x0", "1x0", "8", "99999x1", "-1x5", "axb", "16385x1", "8x8x8", "4294967296x1"]),
        ("--seed", &["-1", "1e3", "18446744073709551616", "seed"]),
        ("--threads", &["0", "-1", "100000", "1025", "two"]),
        ("--time", &["0", "-1", "NaN", "inf", "1e300", "-inf"]),
        ("--checkpoint", &["-1", "NaN", "inf", "1e20", "1e300"]),
        ("--exposure", &["NaN", "inf", "-inf", "1e30", "x"]),
        ("--filter", &["box:NaN", "tent:-1", "gaussian:1e30", "tent:0", "box:inf", "cubic", "box:", ":1"]),
        ("--shard", &["0/0", "3/2", "a/b", "1/4294967296", "-1/2", "2", "1/2/3"]),
        ("--accel", &["octree", "", "BVH2"]),
        ("--sampler", &["halton", ""]),
        ("--pattern", &["hex", ""]),
    ];
    for (opt, values) in numeric {
        for val in values {
            v.push(args_case("command line", format!("render {opt} {val:?}"), base(&[opt, val]), Expect::Error));
        }
    }
    for grid in [["0", "1", "1"], ["5000", "5000", "5000"], ["-1", "1", "1"], ["4097", "1", "1"], ["nan", "1", "1"]] {
        let mut a = vec!["--grid"];
        a.extend(grid);
        v.push(args_case("command line", format!("render --grid {grid:?}"), base(&a), Expect::Error));
    }
    let specs = [
        "",
        "(",
        ")",
        "phong(",
        "phong)",
        "phong(max_depth: 1e9)",
        "phong(max_depth: 65)",
        "phong(light_samples: 0)",
        "phong(min_weight: NaN)",
        "phong(max_depth: -1)",
        "phong(nope: 1)",
        "phong(max_depth: 1, max_depth: 2)",
        "envlight(max_depth: -5)",
        "envlight(max_depth: 0)",
        "envlight(rr_depth: 0)",
        "envlight(rr_threshold: 0)",
        "envlight(rr_threshold: -0.5)",
        "envlight(rr_threshold: NaN)",
        "envlight(rr_threshold: inf)",
        "envlight(env_sampling: magic)",
        "ppm(alpha: 0)",
        "ppm(alpha: 1.5)",
        "ppm(alpha: NaN)",
        "ppm(photons: 0)",
        "ppm(photons: 99999999999)",
        "ppm(radius: -1)",
        "ppm(radius: inf)",
        "ppm(radius_pixels: 0)",
        "ppm(max_depth: 0)",
        "ppm(mode: fast)",
        "debug(mode: x)",
        "debug(max: 0)",
        "debug(max: NaN)",
        "debug(far: -1, near: 0, mode: depth)",
        "debug(mode: grid_cells)",
        "phong(max_depth: ((((((((((((((((((((((((((((((1))))))))))))))))))))))))))))))",
        "\u{1b}[31mphong",
        "magic",
    ];
    for spec in specs {
        v.push(args_case(
            "command line",
            format!("--integrator {spec:?}"),
            base(&["--integrator", spec]),
            Expect::Error,
        ));
    }
    for (name, extra, expect) in [
        (
            "a valid override set",
            vec!["--spp", "3", "--passes", "3", "--size", "9x7", "--seed", "5", "--filter", "tent:1.5"],
            Expect::Ok,
        ),
        ("a valid shard", vec!["--spp", "4", "--shard", "1/2"], Expect::Ok),
        ("1024 threads", vec!["--threads", "1024", "--spp", "1"], Expect::Ok),
        ("a newline between name and parameters", vec!["--integrator", "phong\n(max_depth: 1)"], Expect::Ok),
    ] {
        v.push(args_case("command line", name.into(), base(&extra), expect));
    }
    // Other commands.
    let s = path_str(scene);
    let cornell = path_str(&refs("cornell.exr"));
    let furnace = path_str(&refs("furnace.exr"));
    let conv_out = path_str(&out.with_extension("conv"));
    let others: Vec<(&str, Vec<String>, Expect)> = vec![
        ("bench --size 0", vec!["bench".into(), s.clone(), "--size".into(), "0".into()], Expect::Error),
        ("bench --size 4097", vec!["bench".into(), s.clone(), "--size".into(), "4097".into()], Expect::Error),
        ("bench --seconds NaN", vec!["bench".into(), s.clone(), "--seconds".into(), "NaN".into()], Expect::Error),
        ("bench --seconds 0", vec!["bench".into(), s.clone(), "--seconds".into(), "0".into()], Expect::Error),
        ("bench --accel nope", vec!["bench".into(), s.clone(), "--accel".into(), "nope".into()], Expect::Error),
        (
            "bench --grid 0 0 0",
            vec!["bench".into(), s.clone(), "--grid".into(), "0".into(), "0".into(), "0".into()],
            Expect::Error,
        ),
        (
            "bench a tiny scene",
            vec!["bench".into(), s.clone(), "--size".into(), "8".into(), "--seconds".into(), "0.01".into()],
            Expect::Ok,
        ),
        ("compare sizes differ", vec!["compare".into(), cornell.clone(), furnace.clone()], Expect::Error),
        ("compare png with exr", vec!["compare".into(), cornell.clone(), path_str(out)], Expect::Error),
        ("compare unknown format", vec!["compare".into(), s.clone(), s.clone()], Expect::Error),
        (
            "converge --spp 0",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                cornell.clone(),
                "--integrator".into(),
                "phong".into(),
                "--spp".into(),
                "0".into(),
                "-o".into(),
                conv_out.clone(),
            ],
            Expect::Error,
        ),
        (
            "converge --times NaN",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                cornell.clone(),
                "--integrator".into(),
                "phong".into(),
                "--times".into(),
                "NaN".into(),
                "-o".into(),
                conv_out.clone(),
            ],
            Expect::Error,
        ),
        (
            "converge --times 1e300",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                cornell.clone(),
                "--integrator".into(),
                "phong".into(),
                "--times".into(),
                "1e300".into(),
                "-o".into(),
                conv_out.clone(),
            ],
            Expect::Error,
        ),
        (
            "converge --crop outside",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                cornell.clone(),
                "--integrator".into(),
                "phong".into(),
                "--spp".into(),
                "1".into(),
                "--crop".into(),
                "250,250,100,100".into(),
                "-o".into(),
                conv_out.clone(),
            ],
            Expect::Error,
        ),
        (
            "converge size mismatch",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                cornell.clone(),
                "--integrator".into(),
                "phong".into(),
                "--spp".into(),
                "1".into(),
                "-o".into(),
                conv_out.clone(),
            ],
            Expect::Error,
        ),
        (
            "convert a .ron",
            vec!["convert".into(), s.clone(), "-o".into(), path_str(&out.with_extension("ron"))],
            Expect::Error,
        ),
        ("raytracer no input", vec!["raytracer".into(), "-size".into(), "8".into(), "8".into()], Expect::Error),
        (
            "raytracer bad size",
            vec![
                "raytracer".into(),
                "-input".into(),
                path_str(&data("mit6837/assignment1/scene1_01.txt")),
                "-size".into(),
                "0".into(),
                "x".into(),
            ],
            Expect::Error,
        ),
        (
            "raytracer unknown option",
            vec![
                "raytracer".into(),
                "-input".into(),
                path_str(&data("mit6837/assignment1/scene1_01.txt")),
                "-frobnicate".into(),
            ],
            Expect::Error,
        ),
        ("merge nothing", vec!["merge".into(), "-o".into(), path_str(out)], Expect::Error),
    ];
    for (name, a, expect) in others {
        v.push(args_case("command line", name.into(), a, expect));
    }
}

fn file_kind_cases(v: &mut Vec<Case>, d: &Path) {
    let out = d.join("o.png");
    let sub = d.join("a_dir");
    std::fs::create_dir_all(&sub).unwrap();
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let fifo = d.join("fifo");
    let _ = std::fs::remove_file(&fifo);
    let have_fifo = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
    let mut kinds: Vec<(&str, String)> = vec![("a directory", path_str(&sub)), ("a device", "/dev/null".into())];
    if have_fifo {
        kinds.push(("a FIFO", path_str(&fifo)));
    }
    kinds.push(("missing", path_str(&d.join("missing"))));
    for (kind, target) in &kinds {
        // Named with each input extension, so the extension dispatch does not hide the kind.
        for ext in ["ron", "obj", "txt", "hdr", "exr", "png"] {
            let link = d.join(format!("link_{}.{ext}", kind.replace(' ', "_")));
            let _ = std::fs::remove_file(&link);
            let _ = std::fs::remove_dir(&link);
            #[cfg(unix)]
            std::os::unix::fs::symlink(target, &link).unwrap();
            let l = path_str(&link);
            match ext {
                "ron" | "obj" | "txt" => {
                    v.push(args_case(
                        "file kinds",
                        format!("{kind} as a .{ext} scene"),
                        vec!["render".into(), l.clone(), "-o".into(), path_str(&out), "-q".into()],
                        Expect::Error,
                    ));
                    if ext == "obj" {
                        let scene = d.join(format!("mesh_{}.ron", kind.replace(' ', "_")));
                        std::fs::write(&scene, format!("(camera: (), entities: [(shape: Mesh(path: {l:?}))])"))
                            .unwrap();
                        v.push(args_case(
                            "file kinds",
                            format!("{kind} as a mesh"),
                            vec!["render".into(), path_str(&scene), "-o".into(), path_str(&out), "-q".into()],
                            Expect::Error,
                        ));
                    }
                }
                _ => {
                    let env = d.join(format!("env_{}_{ext}.ron", kind.replace(' ', "_")));
                    std::fs::write(&env, format!("(camera: (), entities: [(light: Environment(map: {l:?}))])"))
                        .unwrap();
                    if ext != "png" {
                        v.push(args_case(
                            "file kinds",
                            format!("{kind} as a .{ext} environment map"),
                            vec!["render".into(), path_str(&env), "-o".into(), path_str(&out), "-q".into()],
                            Expect::Error,
                        ));
                    }
                    let tex = d.join(format!("tex_{}_{ext}.ron", kind.replace(' ', "_")));
                    std::fs::write(&tex, format!("(camera: (), textures: {{\"t\": Image(path: {l:?})}}, materials: {{\"m\": Lambert(albedo: Texture(\"t\"))}}, entities: [(shape: Sphere(), material: \"m\")])")).unwrap();
                    v.push(args_case(
                        "file kinds",
                        format!("{kind} as a .{ext} texture"),
                        vec!["render".into(), path_str(&tex), "-o".into(), path_str(&out), "-q".into()],
                        Expect::Error,
                    ));
                    v.push(args_case(
                        "file kinds",
                        format!("{kind} as a .{ext} compare input"),
                        vec!["compare".into(), l.clone(), l],
                        Expect::Error,
                    ));
                }
            }
        }
        let film = d.join(format!("film_{}.prism-film", kind.replace(' ', "_")));
        let _ = std::fs::remove_file(&film);
        #[cfg(unix)]
        std::os::unix::fs::symlink(target, &film).unwrap();
        let scene = d.join("s.ron");
        v.push(args_case(
            "file kinds",
            format!("{kind} as --resume"),
            vec![
                "render".into(),
                path_str(&scene),
                "--resume".into(),
                path_str(&film),
                "-o".into(),
                path_str(&out),
                "-q".into(),
            ],
            Expect::Error,
        ));
        v.push(args_case(
            "file kinds",
            format!("{kind} as a merge part"),
            vec!["merge".into(), path_str(&film), "-o".into(), path_str(&d.join("m.exr"))],
            Expect::Error,
        ));
    }
}

fn output_cases(v: &mut Vec<Case>, d: &Path, scene: &Path) {
    let s = path_str(scene);
    let readonly = d.join("readonly");
    std::fs::create_dir_all(&readonly).unwrap();
    let mut perms = std::fs::metadata(&readonly).unwrap().permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&readonly, perms).unwrap();
    // root can write anywhere: the read-only case is only a case for other users.
    let root_user = std::fs::write(readonly.join("probe"), b"").is_ok();
    let _ = std::fs::remove_file(readonly.join("probe"));
    let dir_png = d.join("dir.png");
    std::fs::create_dir_all(&dir_png).unwrap();
    let mut cases: Vec<(&str, Vec<String>)> = vec![
        ("missing directory", vec!["render".into(), s.clone(), "-o".into(), path_str(&d.join("no/dir/o.png"))]),
        ("output is a directory", vec!["render".into(), s.clone(), "-o".into(), path_str(&dir_png)]),
        ("output extension unknown", vec!["render".into(), s.clone(), "-o".into(), path_str(&d.join("o.jpg"))]),
        ("output is the scene", vec!["render".into(), s.clone(), "-o".into(), s.clone()]),
        (
            "film output in a missing directory",
            vec!["render".into(), s.clone(), "-o".into(), path_str(&d.join("x/o.prism-film"))],
        ),
        (
            "converge into a file",
            vec![
                "converge".into(),
                s.clone(),
                "--reference".into(),
                path_str(&refs("cornell.exr")),
                "--integrator".into(),
                "phong".into(),
                "--spp".into(),
                "1".into(),
                "-o".into(),
                s.clone(),
            ],
        ),
        (
            "convert into a missing directory",
            vec![
                "convert".into(),
                path_str(&data("mit6837/assignment1/scene1_01.txt")),
                "-o".into(),
                path_str(&d.join("no/dir/x.ron")),
            ],
        ),
        (
            "bench chart in a missing directory",
            vec![
                "bench".into(),
                s.clone(),
                "--size".into(),
                "8".into(),
                "--chart".into(),
                path_str(&d.join("no/dir/c.svg")),
            ],
        ),
    ];
    if !root_user {
        cases.push((
            "read-only directory",
            vec!["render".into(), s.clone(), "-o".into(), path_str(&readonly.join("o.png"))],
        ));
    }
    for (name, mut a) in cases {
        a.push("-q".into());
        if a[0] != "render" {
            a.pop();
        }
        v.push(args_case("outputs", name.into(), a, Expect::Error));
    }
}

fn film_cases(v: &mut Vec<Case>, d: &Path, scene: &Path) {
    // A real film of a 2-pass render stopped after 1 pass is made by a shard: --shard 0/2 of 2 passes.
    let film = d.join("part0.prism-film");
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
        .args([
            "render",
            &path_str(scene),
            "--spp",
            "2",
            "--passes",
            "2",
            "--shard",
            "0/2",
            "-o",
            &path_str(&film),
            "-q",
        ])
        .status()
        .unwrap();
    assert!(st.success(), "cannot make the film for the hostile film cases");
    let good = std::fs::read(&film).unwrap();
    let out = d.join("merged.exr");
    let mut rng = Rng(77);
    let mut variants: Vec<(String, Vec<u8>)> = vec![("empty".into(), vec![])];
    for frac in [1usize, 10, 30, 50, 70, 90, 99] {
        variants.push((format!("truncated to {frac}%"), good[..good.len() * frac / 100].to_vec()));
    }
    for k in 0..16 {
        let mut b = good.clone();
        let at = if k < 8 { 8 + rng.below(64) } else { rng.below(b.len()) };
        b[at] ^= 1 << (k % 8);
        variants.push((format!("bit {} of byte {at} flipped", k % 8), b));
    }
    let mut grown = good.clone();
    grown.extend_from_slice(&[0; 100]);
    variants.push(("100 bytes appended".into(), grown));
    for (k, (name, bytes)) in variants.into_iter().enumerate() {
        let p = d.join(format!("bad{k}.prism-film"));
        std::fs::write(&p, bytes).unwrap();
        v.push(args_case(
            "films",
            format!("--resume, film {name}"),
            vec![
                "render".into(),
                path_str(scene),
                "--spp".into(),
                "2".into(),
                "--passes".into(),
                "2".into(),
                "--resume".into(),
                path_str(&p),
                "-o".into(),
                path_str(&d.join("r.png")),
                "-q".into(),
            ],
            Expect::Error,
        ));
        v.push(args_case(
            "films",
            format!("merge, film {name}"),
            vec!["merge".into(), path_str(&film), path_str(&p), "-o".into(), path_str(&out)],
            Expect::Error,
        ));
    }
    v.push(args_case(
        "films",
        "merge the same shard twice".into(),
        vec!["merge".into(), path_str(&film), path_str(&film), "-o".into(), path_str(&out)],
        Expect::Error,
    ));
    v.push(args_case(
        "films",
        "merge a missing shard".into(),
        vec!["merge".into(), path_str(&film), "-o".into(), path_str(&out)],
        Expect::Error,
    ));
    v.push(args_case(
        "films",
        "merge --partial".into(),
        vec!["merge".into(), path_str(&film), "-o".into(), path_str(&out), "--partial".into()],
        Expect::Ok,
    ));
    v.push(args_case(
        "films",
        "resume with other settings".into(),
        vec![
            "render".into(),
            path_str(scene),
            "--spp".into(),
            "3".into(),
            "--resume".into(),
            path_str(&film),
            "-o".into(),
            path_str(&d.join("r.png")),
            "-q".into(),
        ],
        Expect::Error,
    ));
}

pub fn cases() -> Vec<Case> {
    let d = dir("cli");
    let scene = d.join("s.ron");
    std::fs::write(&scene, "(camera: (size: (8, 8)), render: (spp: 1), entities: [(shape: Sphere())])").unwrap();
    let out = d.join("o.png");
    let mut v = Vec::new();
    option_cases(&mut v, &scene, &out);
    file_kind_cases(&mut v, &dir("kinds"));
    output_cases(&mut v, &dir("outputs"), &scene);
    film_cases(&mut v, &dir("films"), &scene);
    v
}
