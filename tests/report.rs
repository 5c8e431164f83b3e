//! `prism report`: the small suite (`scenes/report/small.ron`) writes a complete page (every picture it names
//! exists, every chart has its curves, every measurement is in the CSV files) whose measurements show the physics
//! the atlas claims (error falls with the budget, the error-bounded offset has no acne where the others do, the
//! plain grid tests the whole teapot per ray); bad input (missing scene or reference, a reference of the wrong size,
//! an integrator that fails) is named in the page and the exit code while everything else is written; a malformed
//! suite is a one-line error with its position; the hardest-region search and the reference reduction are exact.

use crate::common::{prism, refs, root, scratch};
use glam::Vec3;
use prism::io::Image;
use prism::report::images::{fit_reference, hardest_region};
use std::path::Path;

/// The fields of one CSV line (RFC 4180 quoting: `"a, b"` is one field, `""` inside quotes is a quote).
fn fields(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut quoted, mut chars) = (vec![], String::new(), false, line.chars().peekable());
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    out.push(cur);
    out
}

/// The rows of a CSV file as maps from column name to value; every row has as many fields as the header.
fn csv(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head = fields(lines.next().unwrap());
    lines
        .map(|l| {
            let f = fields(l);
            assert_eq!(f.len(), head.len(), "{}: `{l}`", path.display());
            head.iter().cloned().zip(f).collect()
        })
        .collect()
}

/// Every `src="..."` of the page.
fn sources(html: &str) -> Vec<String> {
    html.split("src=\"").skip(1).map(|s| s[..s.find('"').unwrap()].to_string()).collect()
}

#[test]
fn the_small_suite_writes_a_complete_page_whose_measurements_show_the_physics() {
    let dir = scratch("report-small");
    let out = prism(&["report", root().join("scenes/report/small.ron").to_str().unwrap(), "-o", dir.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    // Self-contained: no script, nothing fetched from elsewhere (the SVG namespace is a name, not an address),
    // every picture beside the page.
    let addresses = html.replace(r#"xmlns="http://www.w3.org/2000/svg""#, "");
    assert!(!html.contains("<script") && !addresses.contains("http://") && !addresses.contains("https://"));
    let srcs = sources(&html);
    assert!(srcs.len() >= 40, "{} pictures", srcs.len());
    for s in &srcs {
        assert!(s.starts_with("img/") && dir.join(s).is_file(), "missing picture {s}");
    }
    // Every chart has one curve per series of its legend, each with at least two points.
    let charts: Vec<&str> = html.split("<svg").skip(1).filter(|s| s.contains("class=\"curve\"")).collect();
    assert!(charts.len() >= 9, "{} charts", charts.len());
    for c in &charts {
        for p in c.split("<polyline").skip(1) {
            let points = p.split("points=\"").nth(1).unwrap();
            assert!(points[..points.find('"').unwrap()].split(' ').count() >= 2, "a curve of fewer than 2 points");
        }
    }
    assert!(!html.contains("class=\"problem\""), "the small suite is clean");
    // Convergence: 2 methods x 3 budgets on the furnace, 2 x 2 on the Cornell box, plus Mitsuba's 5 furnace points.
    let conv = csv(&dir.join("convergence.csv"));
    assert_eq!(conv.len(), 6 + 4 + 5);
    let furnace: Vec<f64> = conv
        .iter()
        .filter(|r| r["scene"] == "furnace" && r["method"] == "path tracer, Sobol")
        .map(|r| r["rmse"].parse().unwrap())
        .collect();
    assert!(furnace[0] > furnace[1] && furnace[1] > furnace[2], "error falls with samples: {furnace:?}");
    assert!(csv(&dir.join("equal_error.csv")).iter().any(|r| r["target"] == "vs Mitsuba 3" && !r["ratio"].is_empty()));
    // Accelerators: 4 on bunny_200 and bunny_1k.
    assert_eq!(csv(&dir.join("accelerators.csv")).len(), 8);
    // The teapot in a stadium: the plain grid tests the whole teapot per ray, nested grids a handful.
    let trav = csv(&dir.join("traversal.csv"));
    let prims = |case: &str, accel: &str| -> f64 {
        trav.iter().find(|r| r["case"] == case && r["accel"] == accel).unwrap()["prims_per_ray"].parse().unwrap()
    };
    assert!(prims("grid-stadium", "grid:flat") > 5000.0);
    assert!(prims("grid-stadium", "grid") < 50.0 && prims("grid-stadium", "bvh") < 50.0);
    // Shadow acne: rays from the hit point itself re-hit their surface; Prism's offset never does, at any scale.
    let stab = csv(&dir.join("stability.csv"));
    let acne = |variant: &str| -> f64 {
        stab.iter().find(|r| r["case"] == "acne" && r["variant"] == variant).unwrap()["value"].parse().unwrap()
    };
    assert!(acne("unit scale / no offset") > 5.0);
    assert_eq!(acne("unit scale / fixed epsilon 1e-4"), 0.0);
    assert_eq!(acne("unit scale / error-bounded offset"), 0.0);
    // 2 x 10^5 units from the origin a fixed epsilon of 1e-4 is below the rounding error of the hit point.
    assert!(acne("far / no offset") > 5.0);
    assert!(acne("far / fixed epsilon 1e-4") > 5.0);
    assert_eq!(acne("far / error-bounded offset"), 0.0);
    // Newton at grazing angles: the sphere made as a surface of revolution covers the rim's samples exactly as the
    // analytic sphere does (a single missed or spurious sample at 32x32, 4 spp would be an RMSE of about 1e-3);
    // meshes of it miss the rim by their chords, the coarser the more.
    let newton = |variant: &str| -> f64 {
        stab.iter().find(|r| r["case"] == "newton-grazing" && r["variant"] == variant && r["metric"] == "rmse").unwrap()
            ["value"]
            .parse()
            .unwrap()
    };
    assert!(newton("exact (Newton)") < 1e-5, "{}", newton("exact (Newton)"));
    assert_eq!(newton("analytic sphere"), 0.0);
    assert!(newton("mesh 16 x 8") > 1e-2 && newton("mesh 16 x 8") > 3.0 * newton("mesh 32 x 32"));
    assert!(newton("mesh 32 x 32") > 1e-3);
    // Non-finite input: the NaN scene and the infinite texel are rejected, the NaN texels render finite.
    let errors: Vec<_> = stab.iter().filter(|r| r["case"] == "nonfinite" && r["metric"] == "error").collect();
    assert_eq!(errors.len(), 2);
    assert!(
        stab.iter()
            .any(|r| r["variant"] == "sky with NaN texels" && r["metric"] == "nonfinite_pixels" && r["value"] == "0")
    );
    assert!(err.contains("wrote"), "{err}");
    the_shown_render_is_what_prism_render_gives(&dir);
}

/// The furnace's Sobol render at 4 spp, made again by `prism render` (deterministic: same scene, seed and spp),
/// has the RMSE the CSV reports, and the page's thumbnail and error map are that render and its error against the
/// reference on the scale `maps.csv` names.
fn the_shown_render_is_what_prism_render_gives(dir: &Path) {
    let exr = dir.join("furnace-sobol-4.exr");
    let out = prism(&[
        "render",
        root().join("scenes/furnace.ron").to_str().unwrap(),
        "--integrator",
        "envlight",
        "--sampler",
        "sobol",
        "--spp",
        "4",
        "-q",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let render = prism::io::read_image(&exr).unwrap();
    let reference = prism::io::read_image(&refs("furnace.exr")).unwrap();
    let rmse = prism::compare::compare(&render, &reference).unwrap().rmse;
    let row = csv(&dir.join("convergence.csv"))
        .into_iter()
        .find(|r| r["scene"] == "furnace" && r["method"] == "path tracer, Sobol" && r["spp"] == "4")
        .unwrap();
    let reported: f64 = row["rmse"].parse().unwrap();
    assert!((reported - rmse).abs() <= 1e-6 * rmse, "the CSV says RMSE {reported}, prism render gives {rmse}");
    // The thumbnail: the render in sRGB bytes (the furnace's exposure is 0).
    let thumb = image::open(dir.join("img/furnace-m0.png")).unwrap().to_rgb8();
    let expected = prism::report::images::srgb_bytes(&render, 0.0);
    assert_eq!((thumb.width(), thumb.height()), (render.width, render.height));
    let worst = thumb.as_raw().iter().zip(&expected).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(worst <= 1, "the thumbnail differs from the render by {worst} levels");
    // The error map: |render - reference| (mean of RGB) through viridis, 0 to the scale's top.
    let map = csv(&dir.join("maps.csv")).into_iter().find(|r| r["picture"] == "img/furnace-m0-error.png").unwrap();
    let max: f32 = map["scale_max"].parse().unwrap();
    assert!(max > 0.0);
    let colours = image::open(dir.join("img/furnace-m0-error.png")).unwrap().to_rgb8();
    let errors = prism::report::images::abs_error(&render, &reference);
    let mut off = 0;
    for (px, e) in colours.pixels().zip(&errors) {
        let want = prism::report::images::viridis(e / max);
        if px.0.iter().zip(want).any(|(a, b)| a.abs_diff(b) > 3) {
            off += 1;
        }
    }
    assert_eq!(off, 0, "{off} pixels of the error map do not show the render's error");
    // A map that showed nothing (or another render) would fail: the sphere's pixels have error, the rest none.
    assert!(errors.iter().filter(|e| **e > 0.0).count() > 1000);
}

#[test]
fn bad_input_is_named_in_the_page_and_the_exit_code_and_everything_else_is_written() {
    let dir = scratch("report-bad");
    let scenes = root().join("scenes");
    let suite = format!(
        r#"(
            scenes: [
                (name: "good", scene: "{furnace}", reference: File("{furnace_ref}"), size: Some((32, 32)),
                 methods: [(integrator: "envlight")], budgets: Spp([1, 2])),
                (name: "no-scene", scene: "{dir}/missing.ron", reference: File("{furnace_ref}"),
                 methods: [(integrator: "envlight")], budgets: Spp([1])),
                (name: "no-reference", scene: "{furnace}", reference: File("{dir}/missing.exr"),
                 methods: [(integrator: "envlight")], budgets: Spp([1])),
                (name: "wrong-size", scene: "{furnace}", reference: File("{furnace_ref}"), size: Some((100, 100)),
                 methods: [(integrator: "envlight")], budgets: Spp([1])),
                (name: "failing", scene: "{furnace}", reference: File("{furnace_ref}"), size: Some((32, 32)),
                 methods: [(label: Some("grid view without a grid"), integrator: "debug(mode: grid_cells)"),
                           (label: Some("path tracer"), integrator: "envlight")],
                 budgets: Spp([1])),
            ],
        )"#,
        furnace = scenes.join("furnace.ron").display(),
        furnace_ref = refs("furnace.exr").display(),
        dir = dir.display(),
    );
    let suite_path = dir.join("bad.ron");
    std::fs::write(&suite_path, suite).unwrap();
    let out = prism(&["report", suite_path.to_str().unwrap(), "-o", dir.join("page").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "bad input must fail the exit code");
    let last = err.lines().last().unwrap();
    assert!(last.starts_with("error: 4 item(s) could not be measured"), "{last}");
    let html = std::fs::read_to_string(dir.join("page/index.html")).unwrap();
    for needle in ["missing.ron", "missing.exr", "neither the same size nor an integer multiple", "--accel grid"] {
        assert!(html.contains(needle), "the page must name the problem `{needle}`");
    }
    assert!(html.contains("4 problems"));
    // The good scene and the failing scene's other method are still measured and pictured.
    let conv = csv(&dir.join("page/convergence.csv"));
    assert_eq!(conv.iter().filter(|r| r["scene"] == "good").count(), 2);
    assert_eq!(conv.iter().filter(|r| r["scene"] == "failing" && r["method"] == "path tracer").count(), 1);
    assert!(dir.join("page/img/good-m0.png").is_file() && dir.join("page/img/failing-m0.png").is_file());
    assert_eq!(csv(&dir.join("page/problems.csv")).len(), 4);
}

#[test]
fn a_malformed_suite_is_a_one_line_error_with_its_position() {
    let dir = scratch("report-malformed");
    let path = dir.join("typo.ron");
    std::fs::write(&path, "(\n  title: \"x\",\n  scens: [],\n)").unwrap();
    let out = prism(&["report", path.to_str().unwrap(), "-o", dir.join("page").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("typo.ron:3:") && err.contains("unknown field `scens`"), "{err}");
    assert!(!dir.join("page/index.html").exists());
}

#[test]
fn the_hardest_region_is_the_window_with_the_largest_error() {
    // A 40x30 map of small noise with a planted block of large error at (23, 11): found exactly.
    let (w, h) = (40u32, 30u32);
    let mut v: Vec<f32> = (0..w * h).map(|i| ((i * 7919) % 13) as f32 * 1e-3).collect();
    for y in 11..19 {
        for x in 23..31 {
            v[(y * w + x) as usize] = 1.0;
        }
    }
    assert_eq!(hardest_region(&v, w, h, 8, 8), (23, 11, 8, 8));
    // A window larger than the image is clipped to it.
    assert_eq!(hardest_region(&v, w, h, 100, 100), (0, 0, 40, 30));
}

#[test]
fn a_reference_is_reduced_by_box_filtering_or_refused_when_the_sizes_do_not_divide() {
    // 4x2 -> 2x1: each pixel the mean of its 2x2 block (what a box-filtered render at the smaller size converges to).
    let px: Vec<Vec3> = [1.0, 3.0, 10.0, 20.0, 5.0, 7.0, 30.0, 40.0].iter().map(|&v| Vec3::splat(v)).collect();
    let (small, factor) = fit_reference(Image::new(4, 2, px.clone()), 2, 1).unwrap();
    assert_eq!(factor, 2);
    assert_eq!(small.pixels, vec![Vec3::splat(4.0), Vec3::splat(25.0)]);
    let (same, factor) = fit_reference(Image::new(4, 2, px.clone()), 4, 2).unwrap();
    assert_eq!((factor, same.pixels.len()), (1, 8));
    let err = fit_reference(Image::new(4, 2, px), 3, 1).unwrap_err();
    assert!(err.contains("4x2") && err.contains("3x1"), "{err}");
}
