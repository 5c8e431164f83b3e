//! The film: per-pixel linear HDR radiance sums in fixed point ([`fixed`]) and sample counts, so any prefix of a
//! progressive render is a valid image and films add exactly: a render resumed from a `.prism-film` file, or merged
//! from shards, equals the one-process render bit for bit.
//!
//! Only **complete** passes are committed to the sums; the tiles of a pass cut short (cancellation) are kept apart
//! and shown in images (each pixel is then the mean of all its own samples) but never saved, so a saved film always
//! describes a whole number of passes and resumes exactly. Methods whose estimate is not a mean of samples
//! (photon mapping) replace the film's content with their estimate, counted as one sample per pixel they cover.
//! A render with a noise target also keeps the passes in two alternating halves, whose difference estimates the
//! image's error ([`noise`]).

pub mod file;
pub mod fixed;
pub mod noise;
mod tiles;

pub use file::{FilmFile, FilmHeader, ShardAxis, checksum, parse_film, read_film, write_film};
pub use fixed::FixedRgb;
pub use noise::{NOISE_PASS_SPP, NoiseHalves};
pub use tiles::{PassOutput, TILE_SIZE, Tile, TileSamples, tiles};

use glam::Vec3;
use rayon::prelude::*;

/// Per-pixel radiance sums (fixed point) and sample counts of the committed passes, plus the tiles of a pass cut
/// short.
#[derive(Clone, Debug)]
pub struct Film {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    sum: Vec<FixedRgb>,
    count: Vec<u64>,
    /// Tiles of a pass cut short: shown, never saved.
    partial: Vec<TileSamples>,
    /// Samples replaced by 0 because they were NaN or infinite.
    pub nonfinite: u64,
    /// For a film that covers pixel rows `y % n == k` only (a row shard): `(k, n)`.
    pub rows: Option<(u32, u32)>,
    /// The committed passes in two alternating halves, for the error estimate of a noise target (`None` without
    /// one: they double the film's memory).
    noise: Option<Box<NoiseHalves>>,
}

impl Film {
    /// An empty film of `width` x `height` pixels: every sum and count 0, no row shard.
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            sum: vec![FixedRgb::default(); n],
            count: vec![0; n],
            partial: vec![],
            nonfinite: 0,
            rows: None,
            noise: None,
        }
    }

    /// A film from saved sums and counts (`sum.len() == count.len() == width * height`).
    pub fn from_parts(width: u32, height: u32, sum: Vec<FixedRgb>, count: Vec<u64>, nonfinite: u64) -> Self {
        Film { width, height, sum, count, partial: vec![], nonfinite, rows: None, noise: None }
    }

    /// Keep the passes from now on in two halves for [`Film::relative_error`] (`halves`: a resumed film's, else
    /// empty ones).
    pub fn track_noise(&mut self, halves: Option<NoiseHalves>) {
        let pixels = self.sum.len();
        let halves = halves.filter(|h| h.total.len() == pixels);
        self.noise = Some(Box::new(halves.unwrap_or_else(|| NoiseHalves::new(pixels))));
    }

    /// The noise halves, when the film keeps them.
    pub fn noise_halves(&self) -> Option<&NoiseHalves> {
        self.noise.as_deref()
    }

    /// The committed image's estimated relMSE ([`noise`]): `None` without halves or before both have samples
    /// everywhere.
    pub fn relative_error(&self) -> Option<f64> {
        let halves = self.noise.as_deref()?;
        let mean: Vec<Vec3> = self
            .sum
            .iter()
            .zip(&self.count)
            .map(|(s, &c)| if c == 0 { Vec3::ZERO } else { (s.to_dvec3() / c as f64).as_vec3() })
            .collect();
        halves.relative_error(&mean, &self.count)
    }

    /// The committed sums and counts, row-major.
    pub fn parts(&self) -> (&[FixedRgb], &[u64]) {
        (&self.sum, &self.count)
    }

    /// Add one pass's tiles. The conversion to fixed point dominates (an f64 to i128 per channel), so bands of
    /// `TILE_SIZE` rows are added in parallel, each band by one task from the tiles inside it; every pixel still
    /// receives exactly the same additions, so the film does not depend on the thread count.
    fn add_tiles(&mut self, tiles: &[TileSamples]) {
        let (w, h) = (self.width, self.height);
        // Tiles inside one band of `TILE_SIZE` rows go to the parallel path; others (a plugin's own tiling) add
        // serially.
        let inside = |t: &TileSamples| t.tile.y0.is_multiple_of(TILE_SIZE) && t.tile.h <= TILE_SIZE && t.fits(w, h);
        self.nonfinite += tiles.iter().map(|t| t.nonfinite as u64).sum::<u64>();
        if w == 0 || !tiles.iter().all(inside) {
            tiles.iter().for_each(|t| Self::add_tile(&mut self.sum, &mut self.count, w, 0, t));
            return;
        }
        let mut bands: Vec<Vec<&TileSamples>> = vec![vec![]; h.div_ceil(TILE_SIZE) as usize];
        for t in tiles {
            bands[(t.tile.y0 / TILE_SIZE) as usize].push(t);
        }
        let band_len = (w * TILE_SIZE) as usize;
        self.sum.par_chunks_mut(band_len).zip(self.count.par_chunks_mut(band_len)).zip(bands.par_iter()).for_each(
            |((sum, count), band)| {
                for t in band {
                    Self::add_tile(sum, count, w, t.tile.y0, t);
                }
            },
        );
    }

    /// Add tile `t` to the rows of `sum`/`count` that start at image row `first_row`.
    fn add_tile(sum: &mut [FixedRgb], count: &mut [u64], width: u32, first_row: u32, t: &TileSamples) {
        for y in 0..t.tile.h {
            for x in 0..t.tile.w {
                let i = ((t.tile.y0 + y - first_row) * width + t.tile.x0 + x) as usize;
                sum[i].add(t.sums[(y * t.tile.w + x) as usize]);
                count[i] += t.counts[(y * t.tile.w + x) as usize] as u64;
            }
        }
    }

    /// Replace the content by a whole-image estimate (each covered pixel counts as one sample).
    pub fn set_estimate(&mut self, image: &[Vec3]) {
        let w = self.width.max(1) as usize;
        let rows = self.rows;
        let n = image.len().min(self.sum.len());
        self.sum[..n]
            .par_chunks_mut(w)
            .zip(self.count[..n].par_chunks_mut(w))
            .zip(image[..n].par_chunks(w))
            .enumerate()
            .for_each(|(y, ((sum, count), row))| {
                if rows.is_some_and(|(k, n)| y as u32 % n != k) {
                    return;
                }
                for ((s, c), v) in sum.iter_mut().zip(count.iter_mut()).zip(row) {
                    let v = if v.is_finite() { *v } else { Vec3::ZERO };
                    *s = FixedRgb::from_rgb(v.x as f64, v.y as f64, v.z as f64);
                    *c = 1;
                }
            });
    }

    /// Add a pass: committed when `complete`, otherwise kept apart as the visible part of an unfinished pass.
    pub fn merge(&mut self, out: &PassOutput, complete: bool) {
        self.partial.clear();
        match out {
            PassOutput::Samples(tiles) if complete => {
                self.add_tiles(tiles);
                if let Some(h) = &mut self.noise {
                    h.add_pass(self.width, tiles);
                }
            }
            PassOutput::Samples(tiles) => self.partial = tiles.clone(),
            // An estimate of an unfinished pass is the last complete one's (the integrator keeps it so).
            PassOutput::Estimate { image, .. } => self.set_estimate(image),
        }
    }

    /// Add another film's sums and counts (shards of one render); sizes must match.
    pub fn accumulate(&mut self, other: &Film) {
        for (a, b) in self.sum.iter_mut().zip(&other.sum) {
            a.add(*b);
        }
        // Counts from files: saturate rather than wrap (a forged film must not overflow).
        for (a, b) in self.count.iter_mut().zip(&other.count) {
            *a = a.saturating_add(*b);
        }
        self.nonfinite = self.nonfinite.saturating_add(other.nonfinite);
    }

    /// The partial pass's sums and counts per pixel (zero where it has none).
    fn partial_at(&self) -> Vec<(FixedRgb, u64)> {
        let mut out = vec![(FixedRgb::default(), 0u64); self.sum.len()];
        for t in &self.partial {
            for y in 0..t.tile.h {
                for x in 0..t.tile.w {
                    let i = ((t.tile.y0 + y) * self.width + t.tile.x0 + x) as usize;
                    out[i].0.add(t.sums[(y * t.tile.w + x) as usize]);
                    out[i].1 += t.counts[(y * t.tile.w + x) as usize] as u64;
                }
            }
        }
        out
    }

    /// Mean radiance of a pixel over its committed and partial samples (0 if it has none).
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        let i = (y * self.width + x) as usize;
        self.image()[i]
    }

    /// The current image, row-major from the top-left pixel.
    pub fn image(&self) -> Vec<Vec3> {
        let partial = (!self.partial.is_empty()).then(|| self.partial_at());
        self.sum
            .iter()
            .zip(&self.count)
            .enumerate()
            .map(|(i, (s, &c))| {
                let (mut total, mut n) = (s.to_dvec3(), c);
                if let Some(p) = &partial {
                    total += p[i].0.to_dvec3();
                    n = n.saturating_add(p[i].1);
                }
                if n == 0 { Vec3::ZERO } else { (total / n as f64).as_vec3() }
            })
            .collect()
    }

    /// Pixels whose committed sum reached the fixed-point range in some channel (radiance sums above
    /// [`fixed::MAX_SUM`], clipped there).
    pub fn saturated_pixels(&self) -> usize {
        self.sum.iter().filter(|s| s.saturated()).count()
    }

    /// Fewest and most samples any pixel has, partial pass included (they differ after a pass cut short).
    pub fn sample_range(&self) -> (u64, u64) {
        let partial = self.partial_at();
        let counts = self.count.iter().zip(&partial).map(|(c, p)| c.saturating_add(p.1));
        let (lo, hi) = counts.fold((u64::MAX, 0), |(lo, hi), c| (lo.min(c), hi.max(c)));
        (if lo == u64::MAX { 0 } else { lo }, hi)
    }
}
