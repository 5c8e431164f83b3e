//! Regression tests for the hostile-input classes of issue 11, each named after what it guards: headers that
//! claim more than the file holds, user-controlled recursion depth, extreme values, wrong results accepted
//! silently and misleading messages (hangs and lost work: `reliability_work.rs`). Every case must end in a
//! correct result or a clean one-line error, never a panic, abort or hang. (`hostile/` runs several hundred
//! generated inputs of the same classes.)

use crate::common::{data, forged_exr, forged_hdr, prism_args, scratch};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Write `text` to `dir/name` and return the path.
pub(crate) fn file(dir: &Path, name: &str, text: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Assert a clean failure whose error line contains every needle.
pub(crate) fn assert_error(args: &[&str], needles: &[&str]) -> String {
    let r = prism_args(args);
    assert!(r.is_clean_error(), "expected a clean error from {args:?}, got {r:?}");
    for n in needles {
        assert!(r.error_line().contains(n), "error line lacks {n:?}: {}", r.error_line());
    }
    r.error_line().to_string()
}

fn assert_ok(args: &[&str]) {
    let r = prism_args(args);
    assert!(r.code == Some(0), "expected success from {args:?}, got {r:?}");
}

pub(crate) const SPHERE: &str = "(camera: (size: (8, 8)), entities: [(shape: Sphere())])";

// ---- Allocations sized from an untrusted header -------------------------------------------------------------

#[test]
fn forged_exr_and_hdr_headers_are_errors_not_allocations() {
    let dir = scratch("rel-forged");
    let big_exr = file(&dir, "big.exr", forged_exr(100_000, 50_000, false, 16));
    let big_hdr = file(&dir, "big.hdr", forged_hdr(100_000, 50_000, &[2, 2, 0, 0]));
    // Within the size cap, but the file holds far fewer bytes than the pixels need.
    let thin_exr = file(&dir, "thin.exr", forged_exr(8000, 4000, false, 64));
    let thin_zip = file(&dir, "thin_zip.exr", forged_exr(8000, 4000, true, 64));
    let thin_hdr = file(&dir, "thin.hdr", forged_hdr(8000, 4000, &[0; 64]));
    for f in [&big_exr, &thin_exr, &thin_zip] {
        assert_error(&["compare", s(f), s(f)], &[s(f), "EXR"]);
    }
    assert_error(&["compare", s(&big_hdr), s(&big_hdr)], &["HDR", "larger than Prism reads"]);
    assert_error(&["compare", s(&thin_hdr), s(&thin_hdr)], &["HDR", "file holds"]);
    for (name, map) in [("a", &big_exr), ("b", &big_hdr), ("c", &thin_exr), ("d", &thin_hdr)] {
        let scene = file(
            &dir,
            &format!("env_{name}.ron"),
            format!("(camera: (size: (8, 8)), entities: [(light: Environment(map: {:?}))])", s(map)),
        );
        assert_error(&["render", s(&scene), "-o", s(&dir.join("o.png")), "-q"], &[s(map)]);
        let tex = file(
            &dir,
            &format!("tex_{name}.ron"),
            format!(
                "(camera: (size: (8, 8)), textures: {{\"t\": Image(path: {:?})}}, materials: {{\"m\": \
                 Lambert(albedo: Texture(\"t\"))}}, entities: [(shape: Sphere(), material: \"m\")])",
                s(map)
            ),
        );
        assert_error(&["render", s(&tex), "-o", s(&dir.join("o.png")), "-q"], &[s(map)]);
    }
}

#[test]
fn bench_size_and_render_size_beyond_the_documented_limits_are_errors() {
    let dir = scratch("rel-sizes");
    let scene = file(&dir, "s.ron", SPHERE);
    assert_error(&["bench", s(&scene), "--size", "65536", "--seconds", "0.01"], &["--size", "4096"]);
    let out = dir.join("o.png");
    assert_error(&["render", s(&scene), "-o", s(&out), "--size", "16384x16384", "-q"], &["too large"]);
    assert_error(&["render", s(&scene), "-o", s(&out), "--size", "8192x8192", "-q"], &["too large"]);
    assert_eq!(prism::limits::MAX_IMAGE_PIXELS, 1 << 25, "docs/guide/reliability.md documents 2^25 pixels");
}

// ---- Recursion on user-controlled depth --------------------------------------------------------------------

fn nested_6837(depth: usize, block: &str) -> String {
    let mut t = String::from(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\nLights { numLights 0 }\n\
         Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }\nGroup { numObjects 1 MaterialIndex 0\n",
    );
    for _ in 0..depth {
        t += block;
        t += "\n";
    }
    t += "Sphere { center 0 0 0 radius 1 }\n";
    for _ in 0..depth {
        t += "}\n";
    }
    t + "}\n"
}

fn nested_ron(depth: usize) -> String {
    format!(
        "(camera: (size: (8, 8)), entities: [{}(name: \"leaf\", shape: Sphere()){}])",
        "(children: [".repeat(depth - 1),
        "])".repeat(depth - 1)
    )
}

#[test]
fn deep_but_valid_nesting_loads_in_ron_and_6837_scenes() {
    let dir = scratch("rel-deep");
    let out = dir.join("o.png");
    for depth in [30, 3000] {
        let g = file(&dir, &format!("g{depth}.txt"), nested_6837(depth, "Group { numObjects 1"));
        assert_ok(&["render", s(&g), "-o", s(&out), "--size", "8x8", "-q"]);
        let t = file(&dir, &format!("t{depth}.txt"), nested_6837(depth, "Transform { Translate 0 0 0"));
        assert_ok(&["render", s(&t), "-o", s(&out), "--size", "8x8", "-q"]);
        let r = file(&dir, &format!("r{depth}.ron"), nested_ron(depth));
        assert_ok(&["render", s(&r), "-o", s(&out), "-q"]);
    }
    // The documented limit itself.
    let limit = prism::limits::MAX_NESTING_DEPTH;
    let g = file(&dir, "glimit.txt", nested_6837(limit - 1, "Group { numObjects 1"));
    assert_ok(&["render", s(&g), "-o", s(&out), "--size", "8x8", "-q"]);
    let r = file(&dir, "rlimit.ron", nested_ron(limit));
    assert_ok(&["render", s(&r), "-o", s(&out), "-q"]);
}

#[test]
fn nesting_beyond_the_limit_is_an_error_at_the_users_file_and_line() {
    let dir = scratch("rel-too-deep");
    let out = dir.join("o.png");
    let limit = prism::limits::MAX_NESTING_DEPTH;
    // Line 4 opens the outer group; block k (1-based) opens on line 4 + k: the first one too deep is limit + 1.
    let g = file(&dir, "deep.txt", nested_6837(limit + 50, "Group { numObjects 1"));
    let line = format!("deep.txt:{}:", 4 + limit + 1);
    let e = assert_error(&["render", s(&g), "-o", s(&out), "-q"], &[&line, "nested deeper than"]);
    assert!(!e.contains("recursion limit") && !e.contains("serde"), "{e}");
    let r = file(&dir, "deep.ron", nested_ron(limit + 100));
    let e = assert_error(&["render", s(&r), "-o", s(&out), "-q"], &["deep.ron:1:", "nested too deeply"]);
    assert!(!e.contains("serde_stacker"), "{e}");
    // A deep RON value that is not an entity (the integrator's parameters are read as a raw value) is bounded the
    // same way.
    let v = file(
        &dir,
        "deepvalue.ron",
        format!(
            "(camera: (size: (8, 8)), render: (integrator: phong(x: {}0{})))",
            "[".repeat(100_000),
            "]".repeat(100_000)
        ),
    );
    assert_error(&["render", s(&v), "-o", s(&out), "-q"], &["deepvalue.ron:1:", "nested too deeply"]);
}

/// Depth of obvhs's CWBVH (levels of internal nodes from the root).
fn cwbvh_depth(bvh: &obvhs::cwbvh::CwBvh) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, d)) = stack.pop() {
        deepest = deepest.max(d);
        let n = &bvh.nodes[i];
        let mut offset = 0;
        for c in 0..8 {
            if n.imask & (1 << c) != 0 {
                stack.push((n.child_base_idx as usize + offset, d + 1));
                offset += 1;
            }
        }
    }
    deepest
}

#[test]
fn bvh_on_50000_identical_faces_and_1000_concentric_spheres_is_shallow_and_exact() {
    use prism::accel::{Accel, Accelerator};
    use prism::settings::{AccelKind, Overrides};
    let dir = scratch("rel-dup");
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for _ in 0..50_000 {
        obj += "f 1 2 3\n";
    }
    let mesh = file(&dir, "dup.obj", obj);
    let spheres: String = (1..=1000).map(|i| format!("(shape: Sphere(radius: {})),", i as f32 * 0.001)).collect();
    let cases = [
        format!(
            "(camera: (eye: (0.3, 0.3, 3), target: (0.3, 0.3, 0), size: (8, 8)), entities: [(shape: Mesh(path: {:?}))])",
            s(&mesh)
        ),
        format!("(camera: (size: (8, 8)), entities: [{spheres}])"),
    ];
    for text in cases {
        let mut app =
            crate::common::app_from_ron(&text, Overrides { accel: Some(AccelKind::Brute), ..Default::default() });
        app.setup().unwrap();
        let scene = app.resources.scene.as_ref().unwrap();
        let t0 = Instant::now();
        let bvh = prism::accel::BvhAccel::build(&scene.prims);
        let build = t0.elapsed();
        let depth = cwbvh_depth(bvh.cwbvh());
        assert!(depth <= 40, "CWBVH depth {depth}: a chain, not a tree");
        // A generous guard against the quadratic build (it took minutes): the fallback takes milliseconds.
        assert!(build < Duration::from_secs(20), "BVH build took {build:?}");
        let brute = Accel::build(AccelKind::Brute, &scene.prims).unwrap();
        for ray in prism::ray_sets::camera_rays(scene, 8, 8) {
            let (a, b) = (bvh.intersect(&scene.prims, &ray), brute.intersect(&scene.prims, &ray));
            assert_eq!(a.map(|h| h.t), b.map(|h| h.t), "closest hit differs from brute force");
            assert_eq!(bvh.occluded(&scene.prims, &ray), brute.occluded(&scene.prims, &ray));
        }
    }
}

// ---- Panics on extreme values -------------------------------------------------------------------------------

#[test]
fn extreme_durations_and_thread_counts_are_errors_not_panics() {
    let dir = scratch("rel-extreme-cli");
    let scene = file(&dir, "s.ron", SPHERE);
    let out = dir.join("o.png");
    assert_error(&["render", s(&scene), "-o", s(&out), "--checkpoint", "1e20", "-q"], &["--checkpoint"]);
    assert_error(&["render", s(&scene), "-o", s(&out), "--checkpoint", "NaN", "-q"], &["--checkpoint"]);
    assert_error(&["render", s(&scene), "-o", s(&out), "--time", "1e300", "-q"], &["time budget"]);
    assert_error(&["bench", s(&scene), "--seconds", "1e300"], &["--seconds"]);
    assert_error(&["render", s(&scene), "-o", s(&out), "--threads", "100000", "-q"], &["--threads", "1024"]);
    assert_error(&["bench", s(&scene), "--threads", "100000"], &["--threads"]);
}

#[test]
fn huge_spheres_and_overflowing_coordinates_are_errors_naming_file_and_entity() {
    let dir = scratch("rel-extreme-geometry");
    let out = dir.join("o.png");
    let cases = [
        ("radius.ron", "(camera: (size: (8, 8)), entities: [(name: \"big\", shape: Sphere(radius: 3e38))])"),
        (
            "centre.ron",
            "(camera: (size: (8, 8)), entities: [(name: \"big\", shape: Sphere(center: (3e38, 0, 0), radius: 1e38))])",
        ),
        (
            "moved.ron",
            "(camera: (size: (8, 8)), entities: [(name: \"big\", shape: Sphere(), transform: [Translate((1e30, 0, 0))])])",
        ),
        (
            "tri.ron",
            "(camera: (size: (8, 8)), entities: [(name: \"big\", shape: Triangle(vertices: ((0,0,0), (1e30,0,0), (0,1,0))))])",
        ),
    ];
    for (name, text) in cases {
        let f = file(&dir, name, text);
        assert_error(&["render", s(&f), "-o", s(&out), "-q"], &[name, "'big'", "coordinate limit"]);
    }
}

#[test]
fn a_plane_with_a_tiny_normal_is_still_rendered() {
    // normal (0, 1e-30, 0), offset 0: the plane y = 0, seen from above. Its squared length underflowed in f32.
    let img = crate::common::render_ron(
        "(camera: (eye: (0, 5, 5), target: (0, 0, 0), size: (8, 8)), render: (integrator: debug(mode: normals)), \
         entities: [(shape: Plane(normal: (0, 1e-30, 0), offset: 0))])",
        Default::default(),
    );
    for p in &img.pixels {
        assert!((p.y - 1.0).abs() < 1e-4 && p.x.abs() < 1e-4, "the plane's normal is +y everywhere, got {p}");
    }
}

// ---- Wrong results accepted silently ----------------------------------------------------------------------------

#[test]
fn negative_nan_and_infinite_mtl_values_are_errors_at_their_line() {
    let dir = scratch("rel-mtl");
    let obj = file(&dir, "t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    let out = dir.join("o.exr");
    for (line, key) in [
        ("Kd -1 0.5 0.5", "Kd"),
        ("Kd nan 0.5 0.5", "Kd"),
        ("Ks 1 inf 1", "Ks"),
        ("Ke 1e39 1 1", "Ke"),
        ("Ns inf", "Ns"),
        ("Ns -3", "Ns"),
        ("Kd 0.5", "Kd"), // tobj panicked on colours of fewer than three numbers
        ("Ke 1 x 1", "Ke"),
    ] {
        std::fs::write(dir.join("m.mtl"), format!("# material\nnewmtl a\nKd 0.5 0.5 0.5\n{line}\n")).unwrap();
        assert_error(&["render", s(&obj), "-o", s(&out), "-q"], &["m.mtl:4:", key]);
    }
    std::fs::write(dir.join("m.mtl"), "newmtl a\nillum 7\nNi nan\n").unwrap();
    assert_error(&["render", s(&obj), "-o", s(&out), "-q"], &["m.mtl:3:", "Ni"]);
}

#[test]
fn overflowing_light_powers_and_non_finite_debug_distances_are_errors() {
    let dir = scratch("rel-overflow");
    let out = dir.join("o.exr");
    let env = file(
        &dir,
        "env.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"sky\", light: Environment(radiance: (10, 10, 10), scale: 3e38)), (shape: Sphere())])",
    );
    assert_error(&["render", s(&env), "-o", s(&out), "-q"], &["env.ron", "sky", "overflows"]);
    let area = file(
        &dir,
        "area.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"lamp\", shape: Quad(), light: Area(radiance: (3e38, 1, 1)), transform: [UniformScale(100)])])",
    );
    assert_error(
        &["render", s(&area), "-o", s(&out), "-q", "--integrator", "envlight"],
        &["area.ron", "lamp", "overflows"],
    );
    let sphere = file(&dir, "s.ron", SPHERE);
    for spec in ["debug(near: NaN)", "debug(mode: depth, near: NaN)", "debug(mode: depth, far: inf)"] {
        assert_error(&["render", s(&sphere), "-o", s(&out), "-q", "--integrator", spec], &["debug", "finite"]);
    }
}

#[test]
fn compare_json_is_valid_json_when_metrics_are_infinite() {
    let dir = scratch("rel-json");
    let a = dir.join("a.exr");
    let b = dir.join("b.exr");
    prism::io::write_exr(&a, &prism::io::Image::new(1, 1, vec![glam::Vec3::ZERO])).unwrap();
    prism::io::write_exr(&b, &prism::io::Image::new(1, 1, vec![glam::Vec3::splat(f32::INFINITY)])).unwrap();
    let r = prism_args(&["compare", s(&a), s(&b), "--json"]);
    assert_eq!(r.code, Some(0), "{r:?}");
    let line = r.stdout.trim();
    assert!(!line.contains("inf") && !line.contains("NaN"), "not JSON: {line}");
    assert!(line.contains("\"rmse\": null"), "{line}");
}

#[test]
fn a_forced_equirect_layout_is_used_whatever_the_aspect_ratio() {
    use prism::envmap::{EnvLayout, EnvMap, SourceLayout};
    // A 3:2 map (no guessable layout) forced to equirect: the given layout used to be ignored.
    let odd = prism::io::Image::new(6, 4, vec![glam::Vec3::ONE; 24]);
    let m = EnvMap::from_image(odd.clone(), std::path::Path::new("odd.exr"), Some(SourceLayout::Equirect)).unwrap();
    assert_eq!(m.layout, EnvLayout::Equirect);
    assert!(EnvMap::from_image(odd, std::path::Path::new("odd.exr"), None).is_err());
    // A square one forced to equirect too (unforced, a square is pbrt-v4's equal-area layout).
    let square = prism::io::Image::new(4, 4, vec![glam::Vec3::ONE; 16]);
    let m = EnvMap::from_image(square.clone(), std::path::Path::new("sq.exr"), Some(SourceLayout::Equirect)).unwrap();
    assert_eq!(m.layout, EnvLayout::Equirect);
    assert_eq!(EnvMap::from_image(square, std::path::Path::new("sq.exr"), None).unwrap().layout, EnvLayout::EqualArea);
    let cross = data("envmaps/cross/grace_cross.hdr");
    let m = EnvMap::load(std::slice::from_ref(&cross), Some(SourceLayout::Equirect)).unwrap();
    assert_eq!(m.layout, EnvLayout::Equirect);
    assert_eq!(m.images.len(), 1);
    let guessed = EnvMap::load(std::slice::from_ref(&cross), None).unwrap();
    assert_eq!(guessed.layout, EnvLayout::Cube);
    // And through a scene: a 1x1 image of a 0.2-degree view straight ahead shows the equirect lookup of the raw
    // image there (bracketed by the lookups across the pixel).
    let dir = scratch("rel-layout");
    let scene = file(
        &dir,
        "l.ron",
        format!(
            "(camera: (fov: 0.2, size: (1, 1)), entities: [(light: Environment(map: {:?}, layout: Equirect))])",
            s(&cross)
        ),
    );
    let img = crate::common::render_file(&scene, crate::common::spp(4));
    let (mut lo, mut hi) = (glam::Vec3::splat(f32::INFINITY), glam::Vec3::ZERO);
    for i in -2..=2 {
        for j in -2..=2 {
            let d = glam::Vec3A::new(i as f32 * 0.0009, j as f32 * 0.0009, -1.0).normalize();
            lo = lo.min(m.lookup(d));
            hi = hi.max(m.lookup(d));
        }
    }
    let got = img.get(0, 0);
    assert!(got.cmpge(lo * 0.999).all() && got.cmple(hi * 1.001).all(), "{got} not within [{lo}, {hi}]");
    assert!((guessed.lookup(glam::Vec3A::NEG_Z) - got).abs().max_element() > 1e-3, "the cross layout gives the same");
}

// ---- Misleading messages --------------------------------------------------------------------------------------

#[test]
fn obj_errors_name_the_file_and_line() {
    let dir = scratch("rel-obj");
    let out = dir.join("o.exr");
    let cases = [
        ("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "nan.obj:2:", "non-finite"),
        ("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n", "inf.obj:3:", "non-finite"),
        ("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n", "index.obj:5:", "vertex 7"),
        ("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "neg.obj:4:", "vertex -4"),
        ("word.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "word.obj:4:", "`x`"),
        ("vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n", "vn.obj:5:", "normal 2"),
        // Found by fuzzing: tobj overflowed on a relative texture index beyond those defined.
        ("negvt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-6 2/1 3/1\n", "negvt.obj:5:", "texture coordinate -6"),
    ];
    for (name, text, at, what) in cases {
        let f = file(&dir, name, text);
        let e = assert_error(&["render", s(&f), "-o", s(&out), "-q"], &[at, what]);
        assert!(!e.contains("camera"), "{e}");
        // Referenced from a scene, the same error.
        let scene =
            file(&dir, &format!("{name}.ron"), format!("(camera: (), entities: [(shape: Mesh(path: {name:?}))])"));
        assert_error(&["render", s(&scene), "-o", s(&out), "-q"], &[at]);
    }
}

#[test]
fn directories_fifos_and_devices_as_inputs_are_named_as_such() {
    let dir = scratch("rel-kinds");
    let out = dir.join("o.png");
    let d = dir.join("scene.ron");
    std::fs::create_dir_all(&d).unwrap();
    assert_error(&["render", s(&d), "-o", s(&out), "-q"], &["is a directory"]);
    assert_error(&["render", "/dev/null", "-o", s(&out), "-q"], &["is a device"]);
    let fifo = dir.join("fifo.ron");
    let fifo_exr = dir.join("fifo.exr");
    let _ = std::fs::remove_file(&fifo_exr);
    let _ = std::fs::remove_file(&fifo);
    if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|st| st.success()) {
        // A FIFO nobody writes to blocked the read forever.
        let r = prism_args(&["render", s(&fifo), "-o", s(&out), "-q"]);
        assert!(r.is_clean_error() && r.error_line().contains("FIFO") && r.seconds < 10.0, "{r:?}");
        let mesh = file(&dir, "m.ron", format!("(camera: (), entities: [(shape: Mesh(path: {:?}))])", "fifo.obj"));
        let _ = std::process::Command::new("mkfifo").arg(dir.join("fifo.obj")).status();
        let r = prism_args(&["render", s(&mesh), "-o", s(&out), "-q"]);
        assert!(r.is_clean_error() && r.error_line().contains("FIFO"), "{r:?}");
        let _ = std::process::Command::new("mkfifo").arg(&fifo_exr).status();
        assert_error(&["compare", s(&fifo_exr), s(&fifo_exr)], &["FIFO"]);
    }
    assert_error(&["compare", s(&d), s(&d)], &["directory"]);
}

#[test]
fn messages_escape_control_characters_and_name_no_internal_types() {
    let dir = scratch("rel-messages");
    let out = dir.join("o.png");
    let f = file(
        &dir,
        "ctl.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"a\\u{1b}[31mred\\nline\", shape: Sphere(radius: -1))])",
    );
    let r = prism_args(&["render", s(&f), "-o", s(&out), "-q"]);
    assert!(r.is_clean_error(), "{r:?}");
    assert!(!r.stderr.contains('\u{1b}'), "raw escape in {:?}", r.stderr);
    assert_eq!(r.stderr.lines().count(), 1, "one line: {:?}", r.stderr);
    assert!(r.error_line().contains("\\u{1b}") && r.error_line().contains("\\n"), "{}", r.error_line());
    // A file name with a newline.
    let weird = dir.join("bad\nname.ron");
    std::fs::write(&weird, "(camera: (size: (8, 8)), entities: [(shape: Sphere(radius: -1))])").unwrap();
    let r = prism_args(&["render", s(&weird), "-o", s(&out), "-q"]);
    assert!(r.is_clean_error() && r.stderr.lines().count() == 1, "{r:?}");
    // Schema and parameter errors never show the Rust types behind them.
    let sphere = file(&dir, "s.ron", SPHERE);
    let accel = file(&dir, "accel.ron", "(camera: (size: (8, 8)), render: (accel: 5))");
    let texture = file(&dir, "tex.ron", "(camera: (size: (8, 8)), textures: {\"t\": 5})");
    let errors = [
        assert_error(&["render", s(&accel), "-o", s(&out), "-q"], &["accel.ron:1:"]),
        assert_error(&["render", s(&texture), "-o", s(&out), "-q"], &["tex.ron:1:"]),
        assert_error(
            &["render", s(&sphere), "-o", s(&out), "-q", "--integrator", "phong(max_depth: \"x\")"],
            &["max_depth"],
        ),
        assert_error(&["render", s(&sphere), "-o", s(&out), "-q", "--integrator", "phong(3)"], &["phong"]),
        assert_error(&["render", s(&sphere), "-o", s(&out), "-q", "--integrator", "ppm(mode: 3)"], &["ppm"]),
    ];
    for e in errors {
        assert!(!e.contains("Desc") && !e.contains("Params") && !e.contains("r#"), "internal name in: {e}");
    }
}

#[test]
fn errors_after_loading_name_the_scene_file() {
    let dir = scratch("rel-file-names");
    let out = dir.join("o.png");
    let f = file(
        &dir,
        "singular.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"g\", transform: [UniformScale(1e-13)], children: [(name: \"c\", transform: [UniformScale(1e-13)], shape: Sphere())])])",
    );
    assert_error(&["render", s(&f), "-o", s(&out), "-q"], &["singular.ron", "'c'"]);
}

#[test]
fn a_closed_stdout_is_not_a_panic() {
    let dir = scratch("rel-pipe");
    let a = dir.join("a.exr");
    prism::io::write_exr(&a, &prism::io::Image::new(2, 2, vec![glam::Vec3::ONE; 4])).unwrap();
    for json in [false, true] {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_prism"));
        cmd.args(["compare", s(&a), s(&a)]);
        if json {
            cmd.arg("--json");
        }
        let mut child = cmd.stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped()).spawn().unwrap();
        drop(child.stdout.take()); // `| head -0`: the reader is gone before anything is written
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked") && o.status.code() != Some(101), "{err}");
    }
}
