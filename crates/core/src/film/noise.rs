//! The image's relative error estimated from the film alone, for noise targets (`--noise REL`).
//!
//! A render with a noise target keeps, besides the film, the per-pixel sums of the passes so far (`total`) and a
//! copy of them taken at the last power-of-two pass count `p0` (`first`), taken as the pass after it arrives. After
//! `k` passes (`p0 < k <= 2 p0`) they split the render into two contiguous halves: `A`, the first `p0` passes, and
//! `B`, the `k - p0` after them, of `n_a`, `n_b` samples with per-pixel means `a`, `b`. The variance of one sample
//! is estimated by `sigma^2 = (a - b)^2 n_a n_b / (n_a + n_b)` (its expectation is the true one when the halves are
//! independent), and the film's mean of `N` samples has variance `sigma^2 / N`. The relMSE estimate — `prism
//! compare`'s `mean((x - r)^2 / (r^2 + 0.01))` over pixels and channels — is the mean of `sigma^2 / N / (m^2 +
//! 0.01)`, `m` the film's mean.
//!
//! Why contiguous halves: the passes of one Sobol sequence are better together than apart (the first `2^j` passes
//! are one stratified set), so halves of alternating passes, each a set of scattered blocks, overestimated the
//! error by 25-30% on the Cornell box at 256-512 spp, and more the more passes. Two contiguous halves are each a
//! stratified set of their own; treating them as independent overestimates by one halving's gain only.
//!
//! Each pixel's `(a - b)^2` is one chi-square draw, so a pixel's own estimate is noisy; the image's mean of them is
//! not. It measures variance only: bias (a photon map's blur) is not seen. A film resumed from a file without the
//! halves (one rendered without a target) starts them empty, and `N` counts every sample.

use super::TileSamples;
use glam::DVec3;

/// Samples per pass of a render with a noise target and no sample count: the error is checked after each.
pub const NOISE_PASS_SPP: u32 = 16;

/// The `+ 0.01` of relMSE's denominator (as `prism compare`).
const REL_EPSILON: f64 = 0.01;

/// Per-pixel sums and counts of all passes and of the first `first_passes` of them.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseHalves {
    /// Sums of every pass (f64 per channel; each pixel receives its additions in pass order, so the sums do not
    /// depend on the thread count), row-major.
    pub total: Vec<DVec3>,
    /// Sample counts of every pass, row-major.
    pub total_count: Vec<u64>,
    /// `total` as it was after `first_passes` passes.
    pub first: Vec<DVec3>,
    /// `total_count` as it was after `first_passes` passes.
    pub first_count: Vec<u64>,
    /// Passes received.
    pub passes: u64,
    /// Passes in `first`: the last power of two below `passes` (0 before the second pass).
    pub first_passes: u64,
}

impl NoiseHalves {
    /// Empty halves for `pixels` pixels.
    pub fn new(pixels: usize) -> Self {
        NoiseHalves {
            total: vec![DVec3::ZERO; pixels],
            total_count: vec![0; pixels],
            first: vec![DVec3::ZERO; pixels],
            first_count: vec![0; pixels],
            passes: 0,
            first_passes: 0,
        }
    }

    /// Before a pass: at a power-of-two pass count, the first half becomes everything so far.
    fn start_pass(&mut self) {
        if self.passes.is_power_of_two() {
            self.first.copy_from_slice(&self.total);
            self.first_count.copy_from_slice(&self.total_count);
            self.first_passes = self.passes;
        }
    }

    /// Add one complete pass of an image `width` pixels wide.
    pub fn add_pass(&mut self, width: u32, tiles: &[TileSamples]) {
        self.start_pass();
        for t in tiles {
            for y in 0..t.tile.h {
                for x in 0..t.tile.w {
                    let i = ((t.tile.y0 + y) * width + t.tile.x0 + x) as usize;
                    let j = (y * t.tile.w + x) as usize;
                    if let (Some(s), Some(c)) = (self.total.get_mut(i), self.total_count.get_mut(i)) {
                        *s += t.sums[j].to_dvec3();
                        *c += t.counts[j] as u64;
                    }
                }
            }
        }
        self.passes += 1;
    }

    /// Add one iteration's per-pixel estimates as one sample each (methods whose film holds an estimate, not sums:
    /// `ppm`).
    pub fn add_estimates(&mut self, values: &[DVec3]) {
        self.start_pass();
        for ((s, c), v) in self.total.iter_mut().zip(&mut self.total_count).zip(values) {
            *s += *v;
            *c += 1;
        }
        self.passes += 1;
    }

    /// The estimated relMSE of the image whose per-pixel means are `mean` over `count` samples (the whole film,
    /// resumed samples included); `None` before two passes, or while a pixel with samples has none in a half.
    pub fn relative_error(&self, mean: &[glam::Vec3], count: &[u64]) -> Option<f64> {
        if self.first_passes == 0 || self.passes <= self.first_passes {
            return None;
        }
        let mut total = 0.0f64;
        let mut pixels = 0usize;
        for i in 0..mean.len().min(count.len()).min(self.total.len()) {
            if count[i] == 0 {
                continue;
            }
            let (na, nb) = (self.first_count[i], self.total_count[i].saturating_sub(self.first_count[i]));
            if na == 0 || nb == 0 {
                return None;
            }
            let a = self.first[i] / na as f64;
            let b = (self.total[i] - self.first[i]) / nb as f64;
            let (na, nb) = (na as f64, nb as f64);
            let sigma2 = (a - b) * (a - b) * (na * nb / (na + nb));
            let m = mean[i].as_dvec3();
            let rel = sigma2 / count[i] as f64 / (m * m + DVec3::splat(REL_EPSILON));
            total += (rel.x + rel.y + rel.z) / 3.0;
            pixels += 1;
        }
        (pixels > 0).then(|| total / pixels as f64)
    }

    /// The halves as bytes: the two pass counts, then per pixel three `f64` sums and a `u64` count of `total`, then
    /// of `first` (little-endian; [`NoiseHalves::byte_len`] bytes).
    pub fn to_bytes(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.passes.to_le_bytes());
        out.extend_from_slice(&self.first_passes.to_le_bytes());
        for (sums, counts) in [(&self.total, &self.total_count), (&self.first, &self.first_count)] {
            for (s, c) in sums.iter().zip(counts) {
                for v in s.to_array() {
                    out.extend_from_slice(&v.to_le_bytes());
                }
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }

    /// Bytes [`NoiseHalves::to_bytes`] writes for `pixels` pixels.
    pub fn byte_len(pixels: usize) -> usize {
        16 + 64 * pixels
    }

    /// Read what `to_bytes` wrote (`b.len() == byte_len(pixels)`); `None` for a wrong length, a sum that is not
    /// finite and non-negative, or counts that do not fit together.
    pub fn from_bytes(b: &[u8], pixels: usize) -> Option<Self> {
        if b.len() != Self::byte_len(pixels) {
            return None;
        }
        let word = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap_or_default());
        let mut h = NoiseHalves::new(pixels);
        (h.passes, h.first_passes) = (word(0), word(8));
        if h.first_passes > h.passes {
            return None;
        }
        let mut at = 16;
        for half in 0..2 {
            for i in 0..pixels {
                let v = [0, 1, 2].map(|c| f64::from_bits(word(at + 8 * c)));
                if v.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
                    return None;
                }
                let (s, c) = if half == 0 {
                    (&mut h.total[i], &mut h.total_count[i])
                } else {
                    (&mut h.first[i], &mut h.first_count[i])
                };
                (*s, *c) = (DVec3::from_array(v), word(at + 24));
                at += 32;
            }
        }
        h.first_count.iter().zip(&h.total_count).all(|(f, t)| f <= t).then_some(h)
    }
}
