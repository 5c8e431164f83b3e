//! Tile-parallel rendering of a [`PixelIntegrator`]: rayon over 16x16 tiles, each pixel's random numbers seeded
//! from (seed, pixel, pass) and its sampler's scramble from (seed, pixel), so the image does not depend on the number
//! of threads or the order tiles run in.
//!
//! Per camera sample: the sampler's dimensions 0-1 place the sample in the pixel (or an explicit pattern does),
//! warped by the pixel filter around the pixel centre; dimensions 2-3 are the lens sample (drawn only for a thin
//! lens, skipped otherwise so the integrator's dimensions do not move); the integrator continues from dimension 4.

use super::{Integrator, PassInfo, PassOutput, PixelIntegrator, Tile, TileSamples};
use crate::error::Result;
use crate::sampling::{Rng, Sampler, hash_u64};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

pub const TILE_SIZE: u32 = 16;

/// The image cut into `TILE_SIZE` tiles, row by row.
pub fn tiles(width: u32, height: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(TILE_SIZE as usize) {
        for x0 in (0..width).step_by(TILE_SIZE as usize) {
            out.push(Tile { x0, y0, w: TILE_SIZE.min(width - x0), h: TILE_SIZE.min(height - y0) });
        }
    }
    out
}

/// Adapts a per-ray estimator to the pass-based [`Integrator`] interface.
pub struct PerPixel<T>(pub T);

impl<T: PixelIntegrator> PerPixel<T> {
    /// One tile of the pass; `None` when `cancel` was set while it was rendered (a tile cut short is not kept:
    /// cancellation is checked after every sample, so a tile of heavy pixels stops within one sample).
    fn render_tile(&self, scene: &Scene, pass: &PassInfo, tile: Tile, cancel: &AtomicBool) -> Option<TileSamples> {
        let s = pass.settings;
        let pattern = s.pixel_pattern();
        let camera = &scene.camera;
        let mut sums = Vec::with_capacity((tile.w * tile.h) as usize);
        let mut nonfinite = 0;
        for y in tile.y0..tile.y0 + tile.h {
            for x in tile.x0..tile.x0 + tile.w {
                let pixel = y as u64 * s.width as u64 + x as u64;
                let pixel_key = hash_u64(s.seed ^ hash_u64(pixel)) as u32;
                let mut sampler = Sampler::new(s.sampler, pixel_key, Rng::for_pixel(s.seed, pixel, pass.index as u64));
                // With a known total, a pattern stratifies pixel positions over the whole render (the pixel's key is
                // the same in every pass, each pass takes the next sample indices); otherwise within the pass.
                let (base, total, key) = match s.spp {
                    Some(n) => (pass.first_sample as u32, n, pixel_key),
                    None => (0, pass.spp, sampler.rng().next_u32()),
                };
                let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let mut sum = Vec3::ZERO;
                for i in 0..pass.spp {
                    sampler.start(pass.first_sample as u32 + i);
                    let u_pixel = match pattern {
                        Some(p) => {
                            sampler.skip_2d();
                            p.offset(base + i, total, key, sampler.rng())
                        }
                        None => sampler.next_2d(),
                    };
                    let u_lens = if camera.has_lens() {
                        sampler.next_2d()
                    } else {
                        sampler.skip_2d();
                        Vec2::ZERO
                    };
                    let ray = camera.generate_ray_lens(centre + s.filter.warp(u_pixel), u_lens);
                    let l = self.0.radiance(scene, ray, &mut sampler);
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    if l.is_finite() {
                        sum += l;
                    } else {
                        nonfinite += 1;
                    }
                }
                sums.push(sum);
            }
        }
        Some(TileSamples { tile, spp: pass.spp, sums, nonfinite })
    }
}

impl<T: PixelIntegrator> Integrator for PerPixel<T> {
    fn prepare(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<()> {
        self.0.prepare(scene, settings)
    }

    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput {
        let this = &*self;
        let done: Vec<Option<TileSamples>> = tiles(pass.settings.width, pass.settings.height)
            .into_par_iter()
            .map(|tile| if cancel.load(Ordering::Relaxed) { None } else { this.render_tile(scene, pass, tile, cancel) })
            .collect();
        PassOutput::Samples(done.into_iter().flatten().collect())
    }
}
