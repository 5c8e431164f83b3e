//! Tile-parallel rendering of a [`PixelIntegrator`]: rayon over 16x16 tiles, each pixel's random numbers seeded
//! from (seed, pixel, pass) and its sampler's scramble from (seed, pixel), so the image does not depend on the number
//! of threads or the order tiles run in.
//!
//! Per camera sample: the sampler's dimensions 0-1 place the sample in the pixel (or an explicit pattern does),
//! warped by the pixel filter around the pixel centre; dimensions 2-3 are the lens sample (drawn only for a thin
//! lens, skipped otherwise so the integrator's dimensions do not move); the integrator continues from dimension 4.
//!
//! **Lens pairing.** The lens point of a sample is the lens dimensions' point of another sample of the same block
//! (the pixel's whole render, or the set an explicit pattern stratifies over: [`lens_sample_index`]), chosen by a
//! random permutation of the block, as pbrt-v4's padded Sobol sampler pairs every dimension. The block's lens
//! points are the same set, so their stratification is kept; what changes is which pixel point each meets. The
//! Sobol sampler's own shuffle (a nested scramble of the index) pairs the two sets hierarchically, and a defocused
//! edge — a function of pixel and lens position together — then converged no faster than with random pixel
//! positions: the thin-lens Cornell box (`scenes/dof.ron`) at 64 spp had 21% more squared error (RMSE 0.0280
//! against 0.0255 over 17 seeds, higher on every one; Mitsuba's `ldsampler`, which pairs by permutation, 0.0261).
//!
//! **Camera-ray packets.** A tile is rendered a row at a time, its pixels' samples in order in chunks. Where the
//! integrator takes camera hits ([`PixelIntegrator::takes_camera_hits`]) and the sampler's numbers are pure
//! functions of (sample, dimension) — the Sobol sampler without an explicit pattern — a chunk holds up to sixteen
//! samples (one pixel's, or its row neighbours' when a pass gives each fewer), whose camera rays go down the
//! accelerator together ([`Scene::intersect_packet`]) before their paths: one descent for rays that take nearly the
//! same path through the tree (Cornell box 4% faster), with the same numbers drawn, so the same image.
//!
//! With `adaptive` settings the first pass is the pilot of a [`SampleAllocation`] and later passes give each pixel
//! the samples it allots (see [`super::adaptive`]).

use super::{Integrator, PassInfo, PassOutput, PixelIntegrator, SampleAllocation, Tile, TileSamples, tiles};
use crate::accel::PACKET;
use crate::error::Result;
use crate::film::FixedRgb;
use crate::geometry::Ray;
use crate::sampling::{Rng, SOBOL_BATCH, Sampler, SamplerKind, SobolBatch, hash_u64};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Samples of a tile after which its Sobol batch drops the dimensions few of them reached.
const BATCH_WARMUP: u32 = 256;
/// The share of a tile's first samples that must have reached a batched dimension for the batch to keep computing
/// it: a point computed ahead for a path that ended before asking for it is wasted work (short paths: an open scene
/// whose rays escape), one not computed ahead is computed alone when asked for. The numbers are the same either way.
/// `textured` renders 6% faster than with all thirteen dimensions, the Cornell box (which keeps five to nine) about 1%
/// (0.25 and 0.75 measure within 1% of it; see `docs/decisions/0012-sobol-batch-of-sixteen.md`).
const BATCH_REACH: f32 = 0.5;

// A chunk's samples are the Sobol batch's lanes.
const _: () = assert!(PACKET == SOBOL_BATCH);

/// The sample whose lens point sample `index` uses: `index` is at `position` of a block of `count` consecutive
/// samples (`position < count`), and the block is permuted by `key` (see the module notes). A bijection of the
/// block onto itself for every `key`.
#[inline]
pub fn lens_sample_index(index: u64, position: u32, count: u32, key: u32) -> u64 {
    index - position as u64 + crate::sampling::permute(position, count, key ^ 0x6c65_6e73) as u64
}

/// Begin sample `index` on `sampler`, lane `lane` of its chunk: with the Sobol batch's bit-reversed index where the
/// chunk has a batch (the same numbers as [`Sampler::start`], without reversing the index again).
#[inline(always)]
fn start_sample(sampler: &mut Sampler, index: u64, lane: usize, batch: &SobolBatch) {
    if batch.is_empty() {
        sampler.start(index as u32);
    } else {
        sampler.start_reversed(index as u32, batch.index_rev(lane));
    }
}

/// Adapts a per-ray estimator to the pass-based [`Integrator`] interface.
pub struct PerPixel<T> {
    estimator: T,
    /// The adaptive renders' allocation, once the pilot pass is known.
    allocation: Option<SampleAllocation>,
    /// The Sobol dimensions a chunk of camera-ray packets computes together ([`SobolBatch`]): the pixel
    /// position's, then those the estimator names ([`PixelIntegrator::batched_2d_dims`]); set by `prepare`.
    batch_dims: Vec<u32>,
    /// Those of `batch_dims` the estimator asks for as BSDF directions ([`PixelIntegrator::batched_direction_dims`]).
    direction_dims: Vec<u32>,
}

/// One pixel's samples in a pass, and their sums so far.
struct PixelSamples {
    sampler: Sampler,
    /// The pass's samples of the pixel's sequence: `first..end`.
    first: u64,
    end: u64,
    /// The set an explicit pattern (and the lens pairing) stratifies over: indices `base..base + total`, keyed by
    /// `key`.
    base: u32,
    total: u32,
    key: u32,
    centre: Vec2,
    /// The samples' sum, each sample converted to fixed point as it is added (exact and order-independent).
    sum: FixedRgb,
    /// The sum of squared samples (the adaptive pilot's noise estimate).
    sum_sq: Vec3,
}

/// One tile's sums, and for the pilot of an adaptive render the sums of squared samples.
struct TileOut {
    samples: TileSamples,
    squares: Vec<Vec3>,
}

impl<T: PixelIntegrator> PerPixel<T> {
    /// The integrator that renders `estimator` per pixel.
    pub fn new(estimator: T) -> Self {
        PerPixel { estimator, allocation: None, batch_dims: Vec::new(), direction_dims: Vec::new() }
    }

    /// Pixel `(x, y)`'s samples in this pass: its sampler, the range of its sequence, and the set an explicit
    /// pattern stratifies them over.
    fn pixel_samples(&self, pass: &PassInfo, x: u32, y: u32) -> PixelSamples {
        let s = pass.settings;
        let next_nominal = pass.first_sample + pass.spp as u64;
        let pixel = y as u64 * s.width as u64 + x as u64;
        let px = pixel as usize;
        let pixel_key = hash_u64(s.seed ^ hash_u64(pixel)) as u32;
        // The pixel's stream: each sample's independent numbers derive from it and the sample's index alone.
        let sampler = Sampler::new(s.sampler, pixel_key, Rng::for_pixel(s.seed, pixel, 0));
        // This pass's samples of the pixel's sequence (the nominal range, or the allocation's), and the set an
        // explicit pattern stratifies them over: `(first index, count, key)`. With a known total, the pixel's whole
        // render (its key the same in every pass); in an adaptive render the pilot, then the pixel's samples after
        // it (their count is known once the pilot is); with a time budget, the pass.
        let (first, end, strata) = match &self.allocation {
            Some(a) => {
                let (f, e) = (a.samples_before(px, pass.first_sample), a.samples_before(px, next_nominal));
                let rest =
                    s.spp.map(|n| (f - a.pilot, a.samples_before(px, n as u64) - a.pilot, pixel_key ^ 0x5bd1_e995));
                (f, e, rest)
            }
            None if s.adaptive => (pass.first_sample, next_nominal, Some((0, pass.spp as u64, pixel_key))),
            None => (pass.first_sample, next_nominal, s.spp.map(|n| (pass.first_sample, n as u64, pixel_key))),
        };
        let (base, total, key) = match strata {
            Some((b, n, k)) => (b as u32, n.min(u32::MAX as u64) as u32, k),
            // With a time budget the pass is its own set, keyed by the pass.
            None => (0, (end - first) as u32, hash_u64(pixel_key as u64 ^ hash_u64(pass.index as u64)) as u32),
        };
        PixelSamples {
            sampler,
            first,
            end,
            base,
            total,
            key,
            centre: Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
            sum: FixedRgb::default(),
            sum_sq: Vec3::ZERO,
        }
    }

    /// One tile of the pass; `None` when `cancel` was set while it was rendered (a tile cut short is not kept:
    /// cancellation is checked after every sample, so a tile of heavy pixels stops within one sample). `squares`:
    /// also sum the squared samples (the adaptive pilot).
    ///
    /// A row of the tile at a time: its pixels' samples in order, pixel after pixel, in chunks. Where the integrator
    /// takes camera hits and the sampler's numbers are pure functions of (sample, dimension) — the Sobol sampler
    /// without an explicit pixel pattern — a chunk is up to sixteen samples (one pixel's, or neighbouring pixels'
    /// when a pass gives each fewer), whose camera rays are made first and traced together as a packet
    /// ([`Scene::intersect_packet`]), then their paths follow; no random number changes. Otherwise a chunk is one
    /// sample, its camera ray and path back to back.
    fn render_tile(
        &self,
        scene: &Scene,
        pass: &PassInfo,
        tile: Tile,
        cancel: &AtomicBool,
        squares: bool,
    ) -> Option<TileOut> {
        let s = pass.settings;
        let pattern = s.pixel_pattern();
        let camera = &scene.camera;
        let n = (tile.w * tile.h) as usize;
        let mut sums = Vec::with_capacity(n);
        let mut counts = Vec::with_capacity(n);
        let mut sq = Vec::with_capacity(if squares { n } else { 0 });
        let mut nonfinite = 0;
        let packets = self.estimator.takes_camera_hits() && pattern.is_none() && s.sampler == SamplerKind::Sobol;
        let chunk = if packets { PACKET } else { 1 };
        // Packets of a pinhole's rays take their pixel positions from the batch and need nothing else of the sampler.
        let pinhole_batch = packets && !camera.has_lens();
        let mut rays = [Ray::new(glam::Vec3A::ZERO, glam::Vec3A::Z); PACKET];
        let mut hits = [None; PACKET];
        let mut owner = [(0usize, 0u64); PACKET];
        // With packets, the chunk's Sobol points are computed together ([`SobolBatch`]): the pixel position (the
        // batch's first dimension) and those the estimator asks for at its first vertices.
        let mut batch = SobolBatch::new(if packets { &self.batch_dims } else { &[] }, &self.direction_dims);
        // How many of the tile's first samples reached each batched dimension: once `BATCH_WARMUP` samples are in,
        // the batch keeps only the dimensions most samples reach (see `BATCH_REACH`).
        let mut reach = [0u32; crate::sampling::MAX_BATCH_DIMS];
        let mut seen = 0u32;
        // The camera ray of sample `index` of pixel `p`, lane `lane` of its chunk (its dimensions 0-3 drawn from the
        // pixel's sampler, the pixel position from the batch where there is one).
        let camera_ray = |p: &mut PixelSamples, index: u64, lane: usize, batch: &SobolBatch| {
            let i = (index - p.first) as u32;
            start_sample(&mut p.sampler, index, lane, batch);
            let u_pixel = match pattern {
                Some(pat) => {
                    p.sampler.skip_2d();
                    pat.offset(p.base + i, p.total, p.key, p.sampler.rng())
                }
                None if !batch.is_empty() => {
                    p.sampler.skip_2d();
                    batch.point(lane, 0)
                }
                None => p.sampler.next_2d(),
            };
            let u_lens = if camera.has_lens() {
                p.sampler.next_2d_of(lens_sample_index(index, p.base + i, p.total, p.key) as u32)
            } else {
                p.sampler.skip_2d();
                Vec2::ZERO
            };
            camera.generate_ray_lens(p.centre + s.filter.warp(u_pixel), u_lens)
        };
        for y in tile.y0..tile.y0 + tile.h {
            let mut row: Vec<PixelSamples> =
                (tile.x0..tile.x0 + tile.w).map(|x| self.pixel_samples(pass, x, y)).collect();
            let (mut k, mut index) = (0, row[0].first);
            loop {
                // The next chunk of the row's samples, pixel after pixel.
                let mut m = 0;
                while m < chunk && k < row.len() {
                    if index >= row[k].end {
                        k += 1;
                        index = row.get(k).map_or(0, |p| p.first);
                        continue;
                    }
                    owner[m] = (k, index);
                    (m, index) = (m + 1, index + 1);
                }
                if m == 0 {
                    break;
                }
                if !batch.is_empty() {
                    // The lanes pixel by pixel (a pixel's samples in a chunk are consecutive).
                    let mut lane = 0;
                    while lane < m {
                        let (k, index) = owner[lane];
                        let count = owner[lane..m].iter().take_while(|o| o.0 == k).count();
                        batch.set_lanes(lane, count, &mut row[k].sampler, index as u32);
                        lane += count;
                    }
                    batch.compute();
                }
                if pinhole_batch {
                    // The pixel positions from the batch, the rays all at once (the path starts its sampler anew).
                    let mut films = [Vec2::ZERO; PACKET];
                    for (lane, &(k, _)) in owner[..m].iter().enumerate() {
                        films[lane] = row[k].centre + s.filter.warp(batch.point(lane, 0));
                    }
                    camera.generate_rays(&films[..m], &mut rays[..m]);
                } else {
                    for (lane, &(k, index)) in owner[..m].iter().enumerate() {
                        rays[lane] = camera_ray(&mut row[k], index, lane, &batch);
                    }
                }
                if packets {
                    scene.intersect_packet(&rays[..m], &mut hits[..m]);
                }
                for j in 0..m {
                    let (k, index) = owner[j];
                    let p = &mut row[k];
                    let l = if packets {
                        // The camera dimensions are drawn: the path goes on from the integrator's first.
                        start_sample(&mut p.sampler, index, j, &batch);
                        p.sampler.skip_2d();
                        p.sampler.skip_2d();
                        batch.load(j, &mut p.sampler);
                        self.estimator.radiance_from(scene, rays[j], hits[j], &mut p.sampler)
                    } else {
                        self.estimator.radiance(scene, rays[j], &mut p.sampler)
                    };
                    if seen < BATCH_WARMUP && !batch.is_empty() {
                        seen += 1;
                        let used = p.sampler.dimension();
                        for (r, &d) in reach.iter_mut().zip(batch.dims()) {
                            *r += (used > d) as u32;
                        }
                        if seen == BATCH_WARMUP {
                            let kept = reach.iter().take_while(|&&r| r as f32 >= BATCH_REACH * seen as f32).count();
                            batch.keep(kept);
                        }
                    }
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    if l.is_finite() {
                        p.sum.add_sample(l);
                        p.sum_sq += l * l;
                    } else {
                        nonfinite += 1;
                    }
                }
            }
            for p in row {
                sums.push(p.sum);
                counts.push((p.end - p.first) as u32);
                if squares {
                    sq.push(p.sum_sq);
                }
            }
        }
        Some(TileOut { samples: TileSamples { tile, counts, sums, nonfinite }, squares: sq })
    }

    /// Render the tiles of `pass` in parallel (absent: cut short by `cancel`).
    fn render_tiles(&self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool, squares: bool) -> Vec<TileOut> {
        let done: Vec<Option<TileOut>> = tiles(pass.settings.width, pass.settings.height)
            .into_par_iter()
            // One job per tile: costs differ across the image (an adaptive pass most), and a run of tiles that
            // rayon left unsplit would otherwise keep one thread busy while the other waits.
            .with_max_len(1)
            .map(|tile| {
                if cancel.load(Ordering::Relaxed) { None } else { self.render_tile(scene, pass, tile, cancel, squares) }
            })
            .collect();
        done.into_iter().flatten().collect()
    }

    /// The allocation from a complete pilot pass (`None` if some tile is missing).
    fn allocation_from(settings: &RenderSettings, pilot: u64, out: &[TileOut]) -> Option<SampleAllocation> {
        let (w, h) = (settings.width, settings.height);
        if out.len() != tiles(w, h).len() {
            return None;
        }
        let n = w as usize * h as usize;
        let (mut sums, mut squares) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
        for t in out {
            let tile = t.samples.tile;
            for (k, (s, q)) in t.samples.sums.iter().zip(&t.squares).enumerate() {
                let (x, y) = (tile.x0 + k as u32 % tile.w, tile.y0 + k as u32 / tile.w);
                let i = y as usize * w as usize + x as usize;
                sums[i] = s.to_dvec3().as_vec3();
                squares[i] = *q;
            }
        }
        Some(SampleAllocation::from_pilot(w, h, pilot, &sums, &squares, settings.seed))
    }
}

impl<T: PixelIntegrator> Integrator for PerPixel<T> {
    fn adapts_samples(&self) -> bool {
        true
    }

    fn prepare(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<()> {
        self.allocation = None;
        self.estimator.prepare(scene, settings)?;
        self.batch_dims = [0].into_iter().chain(self.estimator.batched_2d_dims()).collect();
        self.direction_dims = self.estimator.batched_direction_dims();
        Ok(())
    }

    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput {
        let s = pass.settings;
        let samples = |out: Vec<TileOut>| PassOutput::Samples(out.into_iter().map(|t| t.samples).collect());
        if s.adaptive && self.allocation.is_none() {
            // The pilot: pass 0, uniform, whose squared samples set the rates of every later pass. A shard or a
            // resumed render that starts later renders it again (the same samples) for the rates only.
            let pilot = PassInfo { index: 0, spp: s.samples_in_pass(0), first_sample: 0, settings: s };
            let out = self.render_tiles(scene, &pilot, cancel, true);
            self.allocation = Self::allocation_from(s, pilot.spp as u64, &out);
            if pass.index == 0 {
                return samples(out);
            }
            if self.allocation.is_none() {
                return PassOutput::Samples(vec![]);
            }
        }
        samples(self.render_tiles(scene, pass, cancel, false))
    }
}
