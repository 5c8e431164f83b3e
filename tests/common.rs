//! Helpers shared by the test modules.

#![allow(dead_code)]

use prism::app::{App, SceneSource};
use prism::io::Image;
use prism::settings::Overrides;
use std::path::{Path, PathBuf};
use std::process::Output;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shared test data (`../shared/data`).
pub fn data(rel: &str) -> PathBuf {
    root().join("../shared/data").join(rel)
}

/// The shared reference renders (`../shared/refs`).
pub fn refs(rel: &str) -> PathBuf {
    root().join("../shared/refs").join(rel)
}

pub fn scene_path(name: &str) -> PathBuf {
    root().join("scenes").join(name)
}

/// An app for RON text (relative paths resolve against `scenes/`), with overrides.
pub fn app_from_ron(text: &str, overrides: Overrides) -> App {
    let mut app = App::with_default_plugins();
    app.resources.source = SceneSource::RonText {
        text: text.to_string(),
        name: PathBuf::from("test.ron"),
        base_dir: root().join("scenes"),
    };
    app.resources.overrides = overrides;
    app
}

pub fn app_from_file(path: &Path, overrides: Overrides) -> App {
    let mut app = App::with_default_plugins();
    app.resources.source = SceneSource::File(path.to_path_buf());
    app.resources.overrides = overrides;
    app
}

/// Render RON text to an image (panics on error: for scenes the test controls).
pub fn render_ron(text: &str, overrides: Overrides) -> Image {
    let mut app = app_from_ron(text, overrides);
    app.run().unwrap_or_else(|e| panic!("render failed: {e}"));
    prism::render::film_image(&app.resources).unwrap()
}

pub fn render_file(path: &Path, overrides: Overrides) -> Image {
    let mut app = app_from_file(path, overrides);
    app.run().unwrap_or_else(|e| panic!("render of {} failed: {e}", path.display()));
    prism::render::film_image(&app.resources).unwrap()
}

pub fn spp(n: u32) -> Overrides {
    Overrides { spp: Some(n), ..Default::default() }
}

/// Run the `prism` binary.
pub fn prism(args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_prism")).args(args).output().expect("cannot run prism")
}

/// A scratch directory unique to one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("prism-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Standard normal upper tail, for chi-square p-values (Abramowitz & Stegun 26.2.17, |error| < 7.5e-8).
pub fn normal_upper_tail(z: f64) -> f64 {
    if z < 0.0 {
        return 1.0 - normal_upper_tail(-z);
    }
    let t = 1.0 / (1.0 + 0.2316419 * z);
    let poly = t * (0.319381530 + t * (-0.356563782 + t * (1.781477937 + t * (-1.821255978 + t * 1.330274429))));
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt() * poly
}

/// Chi-square goodness of fit of observed counts against expected counts: bins expecting fewer than 5 are pooled.
/// Returns (statistic, degrees of freedom, p-value by the Wilson–Hilferty approximation).
pub fn chi_square(observed: &[f64], expected: &[f64]) -> (f64, usize, f64) {
    let mut pairs: Vec<(f64, f64)> = observed.iter().copied().zip(expected.iter().copied()).collect();
    pairs.sort_by(|a, b| a.1.partial_cmp(&b.1).unwrap());
    let (mut stat, mut bins) = (0.0, 0usize);
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (o, e) in pairs {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
            if pool_e >= 5.0 {
                stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
                bins += 1;
                pool_o = 0.0;
                pool_e = 0.0;
            }
        } else {
            stat += (o - e) * (o - e) / e;
            bins += 1;
        }
    }
    if pool_e > 0.0 {
        // Observations where nothing was expected are a failure of the sampler: count them fully.
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e.max(1e-3);
        bins += 1;
    }
    let df = bins.saturating_sub(1).max(1) as f64;
    let z = ((stat / df).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * df))) / (2.0 / (9.0 * df)).sqrt();
    (stat, df as usize, normal_upper_tail(z))
}

/// Relative difference of two numbers.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// Render a shipped scene at each sample count, assert every channel's image mean is within `mean_tol` (relative)
/// of the reference's, and return the RMSE at each count.
pub fn rmse_against_reference(scene: &str, reference: &str, spps: &[u32], mean_tol: f64) -> Vec<f64> {
    let reference = prism::io::read_exr(&refs(reference)).unwrap();
    let mut rmse = vec![];
    for &n in spps {
        let img = render_file(&scene_path(scene), spp(n));
        let m = prism::compare::compare(&img, &reference).unwrap();
        for c in 0..3 {
            let rel = (m.mean_test[c] - m.mean_reference[c]).abs() / m.mean_reference[c];
            assert!(
                rel < mean_tol,
                "{scene} at {n} spp: channel {c} mean {} vs reference {} ({:.2}%)",
                m.mean_test[c],
                m.mean_reference[c],
                100.0 * rel
            );
        }
        eprintln!("{scene} {n} spp: RMSE {:.5}", m.rmse);
        rmse.push(m.rmse);
    }
    rmse
}

/// A box-filtered reduction of `img` by an integer factor: each output pixel is the mean of a `factor x factor`
/// block, which is exactly what a render at the smaller size with a box pixel filter converges to.
pub fn downsample(img: &prism::io::Image, factor: u32) -> prism::io::Image {
    let (w, h) = (img.width / factor, img.height / factor);
    let mut px = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut s = glam::DVec3::ZERO;
            for dy in 0..factor {
                for dx in 0..factor {
                    s += img.get(x * factor + dx, y * factor + dy).as_dvec3();
                }
            }
            px.push((s / (factor * factor) as f64).as_vec3());
        }
    }
    prism::io::Image::new(w, h, px)
}
