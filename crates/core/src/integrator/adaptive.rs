//! Adaptive sampling (`render: (adaptive: true)`, `--adaptive`): the samples after the first pass go where the
//! image is noisy, the total staying the requested `spp` x pixels.
//!
//! The first pass (the pilot) gives every pixel the same samples. From it, each pixel gets a rate `r` (mean 1 over
//! the image) in proportion to the **square root** of the standard deviation `sigma` of one sample there (see
//! [`NOISE_EXPONENT`]), clamped to [`MIN_RATE`, `MAX_RATE`] = [1/4, 8]. Pixel `i`'s cumulative sample count after
//! `S` nominal samples per pixel is then
//!
//! `C_i(S) = S` for `S <= s0` (the pilot's count), else `s0 + floor(r_i (S - s0) + d_i)`
//!
//! with a fixed per-pixel dither `d_i` in [0, 1), so a pass renders samples `C_i(S_p) .. C_i(S_p+1)` of each pixel's
//! sequence (its Sobol points continue; stratification of every prefix is kept) and the image holds `spp` x pixels
//! samples to within rounding. Every count is a pure function of (scene, settings, pilot), so thread counts, shards
//! and resumes give the same image bit for bit (a process that starts after the pilot re-renders it to know the
//! rates, without adding it to its film).
//!
//! **Bias**: `sigma_i` is estimated from the pilot samples of pixel `i`'s eight neighbours only (their pooled
//! variance, which also sees edges running through the neighbourhood), never from pixel `i`'s own samples. Pixels'
//! random numbers are independent, so a rate chosen from the neighbours' estimate alone would be independent of the
//! pixel's values and its mean exactly unbiased. (A rate chosen from the pixel's own samples would correlate count
//! and value: a pilot that happened to be extreme would attract samples, and the mean would be biased.) One link
//! remains: rates are normalised to mean 1 over the image, and the neighbours' estimates that enter that mean
//! contain pixel `i`'s samples, so its rate depends on them through a weight of about 8 / pixels. The resulting
//! bias is O(1 / pixels) of the pixel's value: an adversarial case (radiance 10 with probability 0.1, 1-sample
//! pilot) measured +2.5% at 2x2 pixels, +0.2% at 6x6; images below [`MIN_ADAPTIVE_PIXELS`] (32x32) therefore
//! sample uniformly, and at 256x256 it is of order 1e-5, far below the noise of any render.
//!
//! **Defence**: the estimate comes from few samples and misses rare bright paths (a caustic seen by path tracing
//! through glass). A pixel it judges smooth still keeps a quarter of the uniform rate (its variance grows by 4x at
//! most), and the square root halves every misjudgement's effect on the rate (an estimate 4x too low costs the
//! pixel half its samples, not three quarters).

use glam::Vec3;

/// Rates follow `sigma ^ NOISE_EXPONENT`. Rates in proportion to `sigma` itself (the exponent 1) would minimise the
/// image's squared error if every pixel's error fell as `sigma^2 / n` and the estimates were exact; neither holds:
/// - the Sobol points make a pixel's error fall faster than `1 / n` most where the one-sample deviation is largest
///   (on the Cornell box's emitter edge its 64-spp variance is 0.06x the independent-sample prediction, on dim
///   walls 0.8x). Were the error `sigma^2 / n^a`, the best rates would be `sigma ^ (2 / (1 + a))`, an exponent
///   below 1 for any `a > 1`;
/// - four pilot samples per neighbour give a noisy `sigma`; a smaller exponent shrinks its errors.
///
/// No share of the samples is spread uniformly: a uniform share defends against pixels the estimate misjudges, at
/// the price of spending those samples blindly, and at equal samples the square root alone has the lower squared
/// error on every scene measured. Exponents from 0.45 to 0.65 measure within 0.5% of 0.5; the measurements, and the
/// rules tried and not kept, are in `docs/decisions/0014-adaptive-square-root-rates.md`.
pub const NOISE_EXPONENT: f64 = 0.5;
/// Fewest samples (relative to the uniform rate) a pixel receives after the pilot.
pub const MIN_RATE: f32 = 0.25;
/// Most samples (relative to the uniform rate) a pixel receives after the pilot.
pub const MAX_RATE: f32 = 8.0;

/// Per-pixel sample rates after the pilot pass.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleAllocation {
    /// Samples per pixel of the pilot (every pixel has exactly these first).
    pub pilot: u64,
    /// Relative rate of each pixel (row-major), mean 1.
    rates: Vec<f32>,
    /// Keys the rounding dither of each pixel, in [0, 1) (hashed from the pixel index when needed).
    seed: u64,
}

/// Images with fewer pixels sample uniformly (see the module notes on the normalisation).
pub const MIN_ADAPTIVE_PIXELS: usize = 1024;

impl SampleAllocation {
    /// The allocation from the pilot's per-pixel sums and sums of squares of `pilot` samples each (row-major,
    /// `width * height` entries); `seed` keys the rounding dither.
    pub fn from_pilot(width: u32, height: u32, pilot: u64, sums: &[Vec3], squares: &[Vec3], seed: u64) -> Self {
        let (w, h) = (width as usize, height as usize);
        let n = w * h;
        debug_assert!(sums.len() == n && squares.len() == n);
        let k = pilot.max(1) as f32;
        let mut sigma = vec![0.0f32; n];
        for y in 0..h {
            for x in 0..w {
                // Pooled over the neighbours' samples: E[v^2] - E[v]^2 per channel, averaged over RGB.
                let (mut m, mut q, mut count) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
                for ny in y.saturating_sub(1)..(y + 2).min(h) {
                    for nx in x.saturating_sub(1)..(x + 2).min(w) {
                        if (nx, ny) != (x, y) {
                            let j = ny * w + nx;
                            m += sums[j];
                            q += squares[j];
                            count += k;
                        }
                    }
                }
                if count > 0.0 {
                    let mean = m / count;
                    let var = (q / count - mean * mean).max(Vec3::ZERO);
                    let v = (var.x + var.y + var.z) / 3.0;
                    // A sample so bright that its square overflows: the neighbourhood is as noisy as it gets.
                    sigma[y * w + x] = if v.is_finite() { v.sqrt() } else { f32::INFINITY };
                }
            }
        }
        let weights: Vec<f32> = sigma.iter().map(|&s| (s as f64).powf(NOISE_EXPONENT) as f32).collect();
        let rates = if n < MIN_ADAPTIVE_PIXELS { vec![1.0; n] } else { normalized_rates(&weights) };
        SampleAllocation { pilot, rates, seed }
    }

    /// The rounding dither of `pixel`, in [0, 1).
    #[inline]
    fn dither(&self, pixel: usize) -> f64 {
        let h = crate::sampling::hash_u64(self.seed ^ 0xada9_717e ^ crate::sampling::hash_u64(pixel as u64));
        (h >> 40) as f64 / 16_777_216.0
    }

    /// Samples pixel `pixel` has received once every pixel would have `nominal` under uniform sampling. Capped at
    /// `u32::MAX`, the length of a pixel's sample sequence (only reachable with absurd `spp`).
    #[inline]
    pub fn samples_before(&self, pixel: usize, nominal: u64) -> u64 {
        if nominal <= self.pilot {
            return nominal;
        }
        let extra = self.rates[pixel] as f64 * (nominal - self.pilot) as f64 + self.dither(pixel);
        // `extra >= 0`, so the (saturating) conversion truncates exactly as `floor` would, without its libm call
        // (this runs three times per pixel and pass).
        (self.pilot.saturating_add(extra as u64)).min(u32::MAX as u64)
    }

    /// The relative rates (row-major, mean 1).
    pub fn rates(&self) -> &[f32] {
        &self.rates
    }
}

/// Rates with mean 1 in proportion to `weights`, clamped to [`MIN_RATE`, `MAX_RATE`] (the clamp and the
/// normalisation alternate until they agree). A flat image gets rate 1 everywhere; an infinite weight the highest
/// rate.
fn normalized_rates(weights: &[f32]) -> Vec<f32> {
    let n = weights.len().max(1) as f64;
    // The scale comes from the finite weights.
    let finite = weights.iter().filter(|s| s.is_finite());
    let mean = finite.clone().map(|&s| s as f64).sum::<f64>() / finite.count().max(1) as f64;
    if !(mean > 0.0 && mean.is_finite()) {
        return vec![1.0; weights.len()];
    }
    let mut scale = 1.0 / mean;
    let mut rates = vec![1.0f32; weights.len()];
    for _ in 0..32 {
        for (r, &s) in rates.iter_mut().zip(weights) {
            *r = ((s as f64 * scale) as f32).clamp(MIN_RATE, MAX_RATE);
        }
        let m = rates.iter().map(|&r| r as f64).sum::<f64>() / n;
        if (m - 1.0).abs() < 1e-4 {
            break;
        }
        scale /= m;
    }
    // The last clamp may leave the mean a hair off 1; divide it out exactly (rates may then leave the clamp by as
    // much, which is harmless).
    let m = rates.iter().map(|&r| r as f64).sum::<f64>() / n;
    rates.iter_mut().for_each(|r| *r = (*r as f64 / m) as f32);
    rates
}
