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
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::RonText {
        text: text.to_string(),
        name: PathBuf::from("test.ron"),
        base_dir: root().join("scenes"),
    };
    app.resources.overrides = overrides;
    app
}

pub fn app_from_file(path: &Path, overrides: Overrides) -> App {
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::File(path.to_path_buf());
    app.resources.overrides = overrides;
    app
}

/// Render RON text to an image (panics on error: for scenes the test controls).
pub fn render_ron(text: &str, overrides: Overrides) -> Image {
    let mut app = app_from_ron(text, overrides);
    app.run().unwrap_or_else(|e| panic!("render failed: {e}"));
    prism::stages::film_image(&app.resources).unwrap()
}

pub fn render_file(path: &Path, overrides: Overrides) -> Image {
    let mut app = app_from_file(path, overrides);
    app.run().unwrap_or_else(|e| panic!("render of {} failed: {e}", path.display()));
    prism::stages::film_image(&app.resources).unwrap()
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

/// How a run of the `prism` binary ended.
#[derive(Debug)]
pub struct Run {
    /// Exit code (None: killed by a signal, or by the timeout).
    pub code: Option<i32>,
    pub timed_out: bool,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

impl Run {
    /// A clean error: exit code 1 and one `error: ...` line (warnings may precede it), no panic.
    pub fn is_clean_error(&self) -> bool {
        let errors: Vec<&str> = self.stderr.lines().filter(|l| l.starts_with("error:")).collect();
        self.code == Some(1) && errors.len() == 1 && !self.panicked()
    }
    pub fn panicked(&self) -> bool {
        self.stderr.contains("panicked") || self.code == Some(101)
    }
    /// The `error: ...` line, if any.
    pub fn error_line(&self) -> &str {
        self.stderr.lines().find(|l| l.starts_with("error:")).unwrap_or("")
    }
}

/// Run the `prism` binary with a timeout (killed when it expires), reading its output as it runs.
pub fn prism_run(args: &[&std::ffi::OsStr], timeout: std::time::Duration) -> Run {
    use std::io::Read;
    let t0 = std::time::Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(args)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("cannot run prism");
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let mut timed_out = false;
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if t0.elapsed() > timeout {
            timed_out = true;
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let stdout = String::from_utf8_lossy(&t_out.join().unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&t_err.join().unwrap()).into_owned();
    Run { code: status.and_then(|s| s.code()), timed_out, stdout, stderr, seconds: t0.elapsed().as_secs_f64() }
}

/// [`prism_run`] with string arguments and a 60-second timeout.
pub fn prism_args(args: &[&str]) -> Run {
    let a: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsStr::new).collect();
    prism_run(&a, std::time::Duration::from_secs(60))
}

/// A forged OpenEXR file: a valid scan-line header (B, G, R half channels, no compression, or ZIP when `zip`)
/// claiming `width x height` pixels, followed by `tail` bytes of zeros.
pub fn forged_exr(width: i32, height: i32, zip: bool, tail: usize) -> Vec<u8> {
    fn attr(out: &mut Vec<u8>, name: &str, ty: &str, data: &[u8]) {
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.extend_from_slice(ty.as_bytes());
        out.push(0);
        out.extend_from_slice(&(data.len() as i32).to_le_bytes());
        out.extend_from_slice(data);
    }
    let mut h = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    let mut ch = Vec::new();
    for n in ["B", "G", "R"] {
        ch.extend_from_slice(n.as_bytes());
        ch.push(0);
        ch.extend_from_slice(&1i32.to_le_bytes()); // half
        ch.extend_from_slice(&[0, 0, 0, 0]);
        ch.extend_from_slice(&1i32.to_le_bytes());
        ch.extend_from_slice(&1i32.to_le_bytes());
    }
    ch.push(0);
    attr(&mut h, "channels", "chlist", &ch);
    attr(&mut h, "compression", "compression", &[if zip { 3 } else { 0 }]);
    let window: Vec<u8> = [0, 0, width - 1, height - 1].iter().flat_map(|v: &i32| v.to_le_bytes()).collect();
    attr(&mut h, "dataWindow", "box2i", &window);
    attr(&mut h, "displayWindow", "box2i", &window);
    attr(&mut h, "lineOrder", "lineOrder", &[0]);
    attr(&mut h, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attr(&mut h, "screenWindowCenter", "v2f", &[0; 8]);
    attr(&mut h, "screenWindowWidth", "float", &1f32.to_le_bytes());
    h.push(0);
    h.extend(std::iter::repeat_n(0u8, tail));
    h
}

/// A forged Radiance HDR file: a valid header claiming `width x height` pixels, followed by `tail` bytes.
pub fn forged_hdr(width: u32, height: u32, tail: &[u8]) -> Vec<u8> {
    let mut h = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n").into_bytes();
    h.extend_from_slice(tail);
    h
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

/// A PNG of `w x h` pixels (colour type `ty`, bit depth `depth`) that holds its header and an empty data stream,
/// no pixels: decoders learn the size first.
pub fn png_header_only(w: u32, h: u32, depth: u8, ty: u8) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut out = (data.len() as u32).to_be_bytes().to_vec();
        let body = [kind, data].concat();
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
        out
    };
    let ihdr = [&w.to_be_bytes()[..], &h.to_be_bytes()[..], &[depth, ty, 0, 0, 0]].concat();
    [
        &b"\x89PNG\r\n\x1a\n"[..],
        &chunk(b"IHDR", &ihdr),
        &chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0, 0, 0, 0, 1]),
        &chunk(b"IEND", &[]),
    ]
    .concat()
}

/// A KTX2 file: `vk_format`, `w` x `h`, one level holding `level`, supercompression `scheme`, an empty DFD.
pub fn forged_ktx2(vk_format: u32, w: u32, h: u32, scheme: u32, level: &[u8]) -> Vec<u8> {
    let mut b = vec![0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n'];
    for v in [vk_format, 1, w, h, 0, 0, 1, 1, scheme] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    // Index: the DFD (its 4-byte total length alone) right after the level index; no key/value or global data.
    let dfd = 80 + 24;
    for v in [dfd as u32, 4, 0, 0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend_from_slice(&0u64.to_le_bytes());
    let level_at = (dfd + 4) as u64;
    let uncompressed = if scheme == 0 { level.len() as u64 } else { w as u64 * h as u64 * 3 };
    for v in [level_at, level.len() as u64, uncompressed] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&4u32.to_le_bytes());
    b.extend_from_slice(level);
    b
}
