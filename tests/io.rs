//! Bad input gets a clear one-line error naming the problem, a non-zero exit code, never a panic.

use crate::common::{data, prism, scratch};
use std::path::PathBuf;

/// Run `prism render` on scene text; return (exit ok, stderr).
fn render_text(name: &str, text: &str, extra: &[&str]) -> (bool, String) {
    let dir = scratch("io");
    let scene = dir.join(name);
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(format!("{name}.png"));
    let mut args = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    args.extend_from_slice(extra);
    let o = prism(&args);
    (o.status.success(), String::from_utf8_lossy(&o.stderr).to_string())
}

/// Assert a clean failure: non-zero exit, first line `error: ...` containing every needle, no panic.
fn assert_error(ok: bool, stderr: &str, needles: &[&str]) {
    assert!(!ok, "expected failure, stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    let first = stderr.lines().next().unwrap_or("");
    assert!(first.starts_with("error:"), "first line is not an error: {stderr}");
    for n in needles {
        assert!(first.contains(n), "error line lacks {n:?}: {first}");
    }
}

const OK_SCENE: &str = "(camera: (size: (8, 8)), entities: [(shape: Sphere())])";

#[test]
fn a_valid_minimal_scene_renders() {
    let (ok, err) = render_text("ok.ron", OK_SCENE, &[]);
    assert!(ok, "{err}");
}

#[test]
fn missing_scene_file_is_named() {
    let o = prism(&["render", "/nonexistent/scene.ron", "-q"]);
    assert_error(o.status.success(), &String::from_utf8_lossy(&o.stderr), &["/nonexistent/scene.ron"]);
}

#[test]
fn malformed_ron_reports_file_line_and_column() {
    let (ok, err) = render_text(
        "broken.ron",
        "(\n  camera: (size: (8, 8)),\n  entities: [(shape: Sphere(radius: 1.0,,))],\n)",
        &[],
    );
    assert_error(ok, &err, &["broken.ron:3:"]);
}

#[test]
fn unknown_field_reports_position_and_expected_fields() {
    let (ok, err) =
        render_text("unknown.ron", "(camera: (size: (8, 8)),\n entities: [(shape: Sphere(radios: 2))])", &[]);
    assert_error(ok, &err, &["unknown.ron:2:", "radios", "radius"]);
}

#[test]
fn unknown_integrator_lists_the_available_ones() {
    let (ok, err) = render_text("integ.ron", "(camera: (size: (8, 8)), render: (integrator: magic))", &[]);
    assert_error(ok, &err, &["unknown integrator 'magic'", "phong"]);
    let (ok, err) = render_text("integ2.ron", OK_SCENE, &["--integrator", "nope"]);
    assert_error(ok, &err, &["unknown integrator 'nope'"]);
}

#[test]
fn nan_in_a_transform_is_rejected_by_entity_name() {
    let (ok, err) = render_text(
        "nan.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"ball\", shape: Sphere(), transform: [Translate((NaN, 0, 0))])])",
        &[],
    );
    assert_error(ok, &err, &["ball", "NaN"]);
    let (ok, err) = render_text(
        "inf.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"m\", shape: Sphere(), transform: [Matrix(((1,0,0,inf),(0,1,0,0),(0,0,1,0),(0,0,0,1)))])])",
        &[],
    );
    assert_error(ok, &err, &["'m'", "NaN or infinity"]);
}

#[test]
fn singular_and_projective_transforms_are_rejected() {
    let (ok, err) = render_text(
        "flat.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"pancake\", shape: Sphere(), transform: [Scale((1, 0, 1))])])",
        &[],
    );
    assert_error(ok, &err, &["pancake", "zero factor"]);
    let (ok, err) = render_text(
        "proj.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"p\", shape: Sphere(), transform: [Matrix(((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,1,1)))])])",
        &[],
    );
    assert_error(ok, &err, &["'p'", "last row"]);
}

#[test]
fn zero_area_triangle_is_rejected_by_entity_name() {
    let (ok, err) = render_text(
        "tri.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"sliver\", shape: Triangle(vertices: ((0,0,0), (1,1,1), (2,2,2))))])",
        &[],
    );
    assert_error(ok, &err, &["sliver", "zero area"]);
}

#[test]
fn empty_and_absurd_image_sizes_are_rejected() {
    let (ok, err) = render_text("zero.ron", OK_SCENE, &["--size", "0x0"]);
    assert_error(ok, &err, &["0x0"]);
    let (ok, err) = render_text("zero2.ron", "(camera: (size: (0, 16)), entities: [])", &[]);
    assert_error(ok, &err, &["0x16"]);
    let (ok, err) = render_text("huge.ron", OK_SCENE, &["--size", "100000x100000"]);
    assert_error(ok, &err, &["too large"]);
    let (ok, err) = render_text("badsize.ron", OK_SCENE, &["--size", "wide"]);
    assert_error(ok, &err, &["WIDTHxHEIGHT"]);
}

#[test]
fn missing_mesh_names_the_path() {
    let (ok, err) = render_text(
        "mesh.ron",
        "(camera: (size: (8, 8)), entities: [(name: \"statue\", shape: Mesh(path: \"no/such/bunny.obj\"))])",
        &[],
    );
    assert_error(ok, &err, &["statue", "no/such/bunny.obj"]);
}

#[test]
fn unknown_material_lists_the_defined_ones() {
    let (ok, err) = render_text(
        "mat.ron",
        "(camera: (size: (8, 8)), materials: {\"red\": Lambert(albedo: (1, 0, 0))}, entities: [(name: \"b\", shape: Sphere(), material: \"blue\")])",
        &[],
    );
    assert_error(ok, &err, &["unknown material 'blue'", "red"]);
}

#[test]
fn non_physical_values_are_rejected() {
    for (name, text, needle) in [
        (
            "neg.ron",
            "(camera: (size: (8, 8)), materials: {\"m\": Lambert(albedo: (-1, 0, 0))}, entities: [])",
            "non-negative",
        ),
        ("rad.ron", "(camera: (size: (8, 8)), entities: [(name: \"s\", shape: Sphere(radius: 0))])", "radius"),
        ("fov.ron", "(camera: (size: (8, 8), fov: 180), entities: [])", "fov"),
        ("eye.ron", "(camera: (size: (8, 8), eye: (0, 0, 0)), entities: [])", "eye == target"),
        (
            "alight.ron",
            "(camera: (size: (8, 8)), entities: [(name: \"l\", light: Area(radiance: (1, 1, 1)))])",
            "needs a shape",
        ),
        (
            "plane.ron",
            "(camera: (size: (8, 8)), entities: [(name: \"pl\", shape: Plane(), light: Area(radiance: (1, 1, 1)))])",
            "plane cannot be an area light",
        ),
        ("nocam.ron", "(entities: [(shape: Sphere())])", "no camera"),
        ("spp.ron", "(camera: (size: (8, 8)), render: (spp: 0))", "spp"),
    ] {
        let (ok, err) = render_text(name, text, &[]);
        assert_error(ok, &err, &[needle]);
    }
}

#[test]
fn bad_command_line_values_are_rejected() {
    for (args, needle) in [
        (vec!["--accel", "octree"], "octree"),
        (vec!["--pattern", "halton"], "halton"),
        (vec!["--threads", "0"], "threads"),
        (vec!["--time", "-1"], "time budget"),
        (vec!["--spp", "4", "--passes", "8"], "passes"),
        (vec!["-o", "image.jpg"], "unsupported output format"),
    ] {
        let (ok, err) = render_text("cli.ron", OK_SCENE, &args);
        assert_error(ok, &err, &[needle]);
    }
}

#[test]
fn unsupported_scene_format_is_named() {
    let (ok, err) = render_text("scene.xyz", "whatever", &[]);
    assert_error(ok, &err, &["unsupported scene format"]);
}

#[test]
fn an_obj_file_renders_directly_as_a_scene() {
    let dir = scratch("objscene");
    let out = dir.join("bunny.png");
    let o = prism(&[
        "render",
        data("mit6837/assignment5/bunny_1k.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size",
        "32x32",
        "--spp",
        "1",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = prism::io::read_image(&out).unwrap();
    assert!(img.mean().x > 0.01, "the bunny is visible");
}

#[test]
fn compare_reports_metrics_and_rejects_mismatched_sizes() {
    let dir = scratch("compare");
    let a = dir.join("a.exr");
    let b = dir.join("b.exr");
    let c = dir.join("c.exr");
    let img = |v: f32, w: u32| prism::io::Image::new(w, 2, vec![glam::Vec3::splat(v); (w * 2) as usize]);
    prism::io::write_exr(&a, &img(1.0, 2)).unwrap();
    prism::io::write_exr(&b, &img(0.5, 2)).unwrap();
    prism::io::write_exr(&c, &img(0.5, 3)).unwrap();
    let o = prism(&["compare", a.to_str().unwrap(), b.to_str().unwrap(), "--json"]);
    assert!(o.status.success());
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("\"rmse\": 0.5,") && s.contains("\"mae\": 0.5,"), "{s}");
    let o = prism(&["compare", a.to_str().unwrap(), c.to_str().unwrap()]);
    assert_error(o.status.success(), &String::from_utf8_lossy(&o.stderr), &["sizes differ"]);
    let missing = PathBuf::from("/nonexistent.exr");
    let o = prism(&["compare", a.to_str().unwrap(), missing.to_str().unwrap()]);
    assert_error(o.status.success(), &String::from_utf8_lossy(&o.stderr), &["/nonexistent.exr"]);
    let junk = dir.join("junk.exr");
    std::fs::write(&junk, b"not an exr").unwrap();
    let o = prism(&["compare", junk.to_str().unwrap(), a.to_str().unwrap()]);
    assert_error(o.status.success(), &String::from_utf8_lossy(&o.stderr), &["junk.exr"]);
}

/// Where the squared error lies: noise of equal size everywhere puts exactly the fraction f of it in any fraction f
/// of the pixels; one outlier holding half of it shows as half in the worst 0.1%; equal images report 0. The
/// command line prints the shares and adds them to its JSON.
#[test]
fn error_concentration_reports_the_share_of_squared_error_in_the_worst_pixels() {
    use prism::compare::error_concentration;
    use prism::io::Image;
    let (w, h) = (100u32, 100u32);
    let reference = Image::new(w, h, vec![glam::Vec3::splat(0.5); (w * h) as usize]);
    let even = Image::new(w, h, vec![glam::Vec3::splat(0.51); (w * h) as usize]);
    let shares = error_concentration(&even, &reference).unwrap();
    for (share, f) in shares.iter().zip(prism::compare::TOP_FRACTIONS) {
        assert!((share - f).abs() < 1e-6, "even noise: {share} in the worst {f}");
    }
    // One pixel off by 1 in every channel, the rest by 0.01: the outlier holds 3 / (3 + 9999 * 3e-4) of it.
    let mut outlier = even.clone();
    outlier.pixels[4321] = glam::Vec3::splat(1.5);
    let shares = error_concentration(&outlier, &reference).unwrap();
    let d = |v: f32| ((v - 0.5) as f64).powi(2) * 3.0;
    let (big, small) = (d(1.5), d(0.51));
    let total = big + 9999.0 * small;
    for (share, k) in shares.iter().zip([10.0, 100.0, 1000.0]) {
        let expect = (big + (k - 1.0) * small) / total;
        // Per-pixel errors are kept as f32: shares to about 1e-7.
        assert!((share - expect).abs() < 1e-6, "outlier: {share} vs {expect} in the worst {k} pixels");
    }
    assert_eq!(error_concentration(&reference, &reference).unwrap(), [0.0; 3]);
    let small_image = Image::new(2, 2, vec![glam::Vec3::ZERO; 4]);
    assert!(error_concentration(&small_image, &reference).is_err(), "sizes differ");

    let dir = scratch("concentration");
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    prism::io::write_exr(&a, &outlier).unwrap();
    prism::io::write_exr(&b, &reference).unwrap();
    let o = prism(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("worst 0.1% / 1% / 10% of pixels: 50.0% / 50.5% / 55.0%"), "{text}");
    let o = prism(&["compare", a.to_str().unwrap(), b.to_str().unwrap(), "--json"]);
    let json = String::from_utf8_lossy(&o.stdout);
    assert!(json.trim_end().ends_with("}}") && json.contains("\"top_pixel_share\": {\"0.001\": 0.50"), "{json}");
}

/// Determinism of the output file, not only of its pixels: an EXR's blocks are compressed in parallel, and in the
/// exr crate's default (unspecified) line order they are stored in the order their compression finishes, so the
/// same image gave different bytes from run to run. Prism writes them in increasing-y order: the header says so,
/// the pixels read back exactly, and repeated writes of the same image are byte-identical.
#[test]
fn exr_files_are_byte_identical_for_the_same_image() {
    let dir = scratch("exr_bytes");
    let (w, h) = (256u32, 256u32);
    // Content whose blocks compress at different speeds (noise beside flat areas).
    let mut rng = prism::sampling::Rng::new(4, 2);
    let pixels: Vec<glam::Vec3> = (0..w * h)
        .map(|i| if (i / w) % 64 < 32 { glam::Vec3::splat(0.25) } else { glam::Vec3::splat(rng.next_f32()) })
        .collect();
    let img = prism::io::Image::new(w, h, pixels.clone());
    let first = dir.join("first.exr");
    prism::io::write_exr(&first, &img).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&first, false).unwrap();
    assert_eq!(meta.headers[0].line_order, exr::meta::attribute::LineOrder::Increasing);
    let back = prism::io::read_image(&first).unwrap();
    assert!(back.pixels == pixels, "pixels read back exactly");
    let bytes = std::fs::read(&first).unwrap();
    for k in 0..6 {
        let again = dir.join(format!("again{k}.exr"));
        prism::io::write_exr(&again, &img).unwrap();
        assert!(std::fs::read(&again).unwrap() == bytes, "write {k} differs from the first");
    }
}

#[test]
fn charts_are_standalone_svg_with_one_polyline_per_series() {
    use prism::chart::{Chart, Series};
    let chart = Chart {
        title: "RMSE vs time".into(),
        x_label: "seconds".into(),
        y_label: "RMSE".into(),
        log_x: true,
        log_y: true,
        series: vec![
            Series { name: "prism <phong>".into(), points: vec![(0.05, 0.2), (0.2, 0.1), (0.8, 0.05), (3.2, 0.025)] },
            Series { name: "mitsuba".into(), points: vec![(0.1, 0.19), (0.4, 0.09), (1.6, 0.045), (0.0, 1.0)] },
        ],
    };
    let svg = chart.to_svg();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert!(svg.contains("prism &lt;phong&gt;"), "labels are escaped");
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "a zero x on a log axis is dropped, not drawn");
    let path = scratch("chart").join("c.svg");
    chart.write_svg(&path).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 1000);
    // A long legend label widens the chart instead of running off its edge (at 7.2 px per character of the 12 px
    // font, more than any glyph of these labels needs).
    let width =
        |svg: &str| -> f64 { svg.split("width=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap() };
    assert_eq!(width(&svg), 760.0, "short labels keep the default width");
    let long = "ppm(max_depth: 12, mode: fixed, radius_pixels: 3)";
    let wide = Chart { series: vec![Series { name: long.into(), points: vec![(1.0, 0.1), (2.0, 0.05)] }], ..chart };
    let svg = wide.to_svg();
    let text_x: f64 = svg.split("<text x=\"").last().unwrap().split('"').next().unwrap().parse().unwrap();
    assert!(width(&svg) >= text_x + 7.2 * long.len() as f64, "legend of {} px in a chart {} wide", text_x, width(&svg));
}

// Portable float maps (`io/pfm.rs`).

fn pfm(header: &str, values: &[f32], little: bool) -> Vec<u8> {
    let mut b = header.as_bytes().to_vec();
    for v in values {
        b.extend(if little { v.to_le_bytes() } else { v.to_be_bytes() });
    }
    b
}

#[test]
fn pfm_rows_are_stored_from_the_bottom_in_either_byte_order() {
    for (little, scale) in [(true, "-1.0"), (false, "1.0")] {
        let b = pfm(&format!("PF\n2 2\n{scale}\n"), &[1., 2., 3., 4., 5., 6., 7., 8., 9., 10., 11., 12.], little);
        let img = prism::io::read_pfm_bytes(&b, std::path::Path::new("t.pfm")).unwrap();
        // The file's first row is the image's bottom row.
        assert_eq!(img.get(0, 1), glam::Vec3::new(1., 2., 3.));
        assert_eq!(img.get(1, 0), glam::Vec3::new(10., 11., 12.));
    }
    let grey = prism::io::read_pfm_bytes(&pfm("Pf 1 1 -1\n", &[0.5], true), std::path::Path::new("g.pfm")).unwrap();
    assert_eq!(grey.get(0, 0), glam::Vec3::splat(0.5));
}

#[test]
fn forged_pfm_headers_are_errors_before_allocation() {
    let p = std::path::Path::new("bad.pfm");
    for (bytes, needle) in [
        (b"P6\n1 1\n255\n".to_vec(), "not a portable float map"),
        (pfm("PF\n100000 100000\n-1\n", &[], true), "larger than Prism reads"),
        (pfm("PF\n4 4\n-1\n", &[1.0; 5], true), "truncated"),
        (pfm("PF\n4 x\n-1\n", &[], true), "height"),
        (pfm("PF\n1 1\n0\n", &[1.0; 3], true), "scale"),
        (pfm("PF\n1.5 1\n-1\n", &[1.0; 3], true), "whole numbers"),
    ] {
        let e = prism::io::read_pfm_bytes(&bytes, p).unwrap_err().to_string();
        assert!(e.contains(needle) && e.contains("bad.pfm"), "{e}");
    }
}

/// TGA textures (13 of Bitterli's pbrt-v4 scenes use them): classroom's wood decodes, 8-bit sRGB to linear, with
/// the image's own size and plausible wood colours (red above blue).
#[test]
fn tga_textures_decode() {
    let tex = prism::texture::TexImage::load(&crate::common::data("bitterli/classroom/textures/wood1.tga"), false)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(tex.width > 0 && tex.height > 0);
    let mean = tex.iter().fold(glam::Vec3::ZERO, |a, t| a + t) / tex.len() as f32;
    assert!(mean.x > mean.z && mean.max_element() < 1.0 && mean.min_element() > 0.0, "{mean}");
}
