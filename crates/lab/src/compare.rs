//! Image error metrics against a reference: RMSE, relative MSE and mean absolute error over all pixels and
//! channels (linear values).
//!
//! relMSE = mean((a - r)^2 / (r^2 + 0.01)): the 0.01 keeps dark reference pixels from dominating.
//!
//! [`error_concentration`] says where the squared error lies: the share of it held by the worst 0.1%, 1% and 10%
//! of the pixels. Noise spread over the image gives shares near those fractions; a few pixels holding most of it
//! point at edges and outliers (at 16 spp half the Cornell box's squared error is in the hundred pixels along the
//! light's edges, where the pixel position decides between 18 and 0.3), which adaptive sampling or a better pixel
//! pattern address and which more samples everywhere do not.

use glam::Vec3;
use prism_core::error::{PrismError, Result};
use prism_core::io::Image;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Metrics {
    pub rmse: f64,
    pub relmse: f64,
    pub mae: f64,
    pub mean_test: [f64; 3],
    pub mean_reference: [f64; 3],
}

impl Metrics {
    /// One JSON object: `{"rmse": .., "relmse": .., "mae": .., "mean_test": [r, g, b], "mean_reference": [r, g, b]}`,
    /// with `"top_pixel_share": {"0.001": .., "0.01": .., "0.1": ..}` added when `top` holds the
    /// [`error_concentration`] of the same images. JSON has no infinity or NaN: a value that is not finite (images
    /// with infinite or NaN pixels) is `null`.
    pub fn to_json(&self, top: Option<[f64; 3]>) -> String {
        struct Num(f64);
        impl std::fmt::Display for Num {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                if self.0.is_finite() { write!(f, "{}", self.0) } else { f.write_str("null") }
            }
        }
        let v = |a: [f64; 3]| format!("[{}, {}, {}]", Num(a[0]), Num(a[1]), Num(a[2]));
        let (rmse, relmse, mae) = (Num(self.rmse), Num(self.relmse), Num(self.mae));
        let shares = match top {
            Some(t) => {
                let pairs: Vec<String> =
                    TOP_FRACTIONS.iter().zip(t).map(|(f, s)| format!("\"{f}\": {}", Num(s))).collect();
                format!(", \"top_pixel_share\": {{{}}}", pairs.join(", "))
            }
            None => String::new(),
        };
        format!(
            "{{\"rmse\": {}, \"relmse\": {}, \"mae\": {}, \"mean_test\": {}, \"mean_reference\": {}{}}}",
            rmse,
            relmse,
            mae,
            v(self.mean_test),
            v(self.mean_reference),
            shares
        )
    }
}

/// `reference` box-filtered to `width` x `height` when it is an integer multiple of that size in both axes (a
/// reference rendered at full resolution beside a test at a fraction of it); `None` when it is not.
pub fn box_downsample(reference: &Image, width: u32, height: u32) -> Option<Image> {
    if width == 0 || height == 0 || !reference.width.is_multiple_of(width) || !reference.height.is_multiple_of(height) {
        return None;
    }
    let (fx, fy) = (reference.width / width, reference.height / height);
    if fx != fy {
        return None;
    }
    let mut pixels = Vec::with_capacity(width as usize * height as usize);
    for y in 0..height {
        for x in 0..width {
            let mut sum = glam::DVec3::ZERO;
            for dy in 0..fy {
                let row = ((y * fy + dy) * reference.width) as usize;
                for dx in 0..fx {
                    sum += reference.pixels[row + (x * fx + dx) as usize].as_dvec3();
                }
            }
            pixels.push((sum / (fx * fy) as f64).as_vec3());
        }
    }
    Some(Image { width, height, pixels })
}

pub fn compare(test: &Image, reference: &Image) -> Result<Metrics> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(PrismError::invalid(format!(
            "image sizes differ: {}x{} vs {}x{}",
            test.width, test.height, reference.width, reference.height
        )));
    }
    let (mut se, mut rel, mut ae) = (0.0f64, 0.0f64, 0.0f64);
    let (mut mt, mut mr) = ([0.0f64; 3], [0.0f64; 3]);
    for (a, r) in test.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let (a, r) = (a[c] as f64, r[c] as f64);
            let d = a - r;
            se += d * d;
            rel += d * d / (r * r + 0.01);
            ae += d.abs();
            mt[c] += a;
            mr[c] += r;
        }
    }
    let n = (test.pixels.len() * 3).max(1) as f64;
    let np = test.pixels.len().max(1) as f64;
    Ok(Metrics {
        rmse: (se / n).sqrt(),
        relmse: rel / n,
        mae: ae / n,
        mean_test: mt.map(|v| v / np),
        mean_reference: mr.map(|v| v / np),
    })
}

/// Fractions of the pixels [`error_concentration`] reports on: the worst 0.1%, 1% and 10%.
pub const TOP_FRACTIONS: [f64; 3] = [0.001, 0.01, 0.1];

/// The share of the squared error (summed over RGB) held by the worst [`TOP_FRACTIONS`] of the pixels, each in
/// [0, 1] (a fraction of at least one pixel, rounded up); 0 where the images are equal, NaN where a pixel's squared
/// error is not finite as an f32 (a difference beyond about 1e19).
pub fn error_concentration(test: &Image, reference: &Image) -> Result<[f64; 3]> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(PrismError::invalid(format!(
            "image sizes differ: {}x{} vs {}x{}",
            test.width, test.height, reference.width, reference.height
        )));
    }
    // Per-pixel squared errors as f32 (half the memory of f64 on the largest images), summed in f64.
    let mut se: Vec<f32> = test
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, r)| (0..3).map(|c| (a[c] as f64 - r[c] as f64).powi(2)).sum::<f64>() as f32)
        .collect();
    let total: f64 = se.iter().map(|&v| v as f64).sum();
    if !total.is_finite() {
        return Ok([f64::NAN; 3]);
    }
    if total == 0.0 {
        return Ok([0.0; 3]);
    }
    // The worst k pixels by selection, largest fraction first, each selection within the previous one's prefix:
    // linear time, no full sort.
    let n = se.len();
    let k_of = |f: f64| ((f * n as f64).ceil() as usize).clamp(1, n);
    let mut shares = [0.0f64; 3];
    for i in (0..TOP_FRACTIONS.len()).rev() {
        let k = k_of(TOP_FRACTIONS[i]);
        let prefix = if i + 1 < TOP_FRACTIONS.len() { k_of(TOP_FRACTIONS[i + 1]) } else { n };
        if k < prefix {
            se[..prefix].select_nth_unstable_by(k - 1, |a, b| b.total_cmp(a));
        }
        shares[i] = (se[..k].iter().map(|&v| v as f64).sum::<f64>() / total).min(1.0);
    }
    Ok(shares)
}

/// Relative difference of two colours' channel means (for "image mean within x%" checks).
pub fn mean_rel_diff(a: Vec3, b: Vec3) -> f32 {
    ((a.x + a.y + a.z) - (b.x + b.y + b.z)).abs() / (b.x + b.y + b.z)
}
