//! The integrator interface plugins implement.
//!
//! - [`Integrator`]: one progressive pass at a time, with whatever state it keeps between passes (a photon
//!   mapper implements this directly). It is called once per pass, so its dynamic dispatch never sits in a hot loop.
//! - [`PixelIntegrator`]: the common case, an estimator of the radiance along one camera ray. Wrap it in
//!   [`PerPixel`] to get an `Integrator` that renders tiles in parallel with per-pixel deterministic random numbers
//!   from the chosen [`Sampler`], the pixel filter and the camera's lens; `radiance` is then called statically, not
//!   through a vtable. An estimator draws every random number from the sampler (`next_1d`/`next_2d`) in a fixed
//!   order per path vertex, so the low-discrepancy sampler stratifies every dimension of the path.
//! - [`IntegratorRegistry`]: names to factories; plugins register theirs in `Plugin::build`.

mod adaptive;
mod next_event;
mod per_pixel;
mod registry;
pub mod roulette;

pub use crate::film::{PassOutput, TILE_SIZE, Tile, TileSamples, tiles};
pub use adaptive::{MAX_RATE, MIN_ADAPTIVE_PIXELS, MIN_RATE, SampleAllocation};
pub use per_pixel::{PerPixel, lens_sample_index};
pub use registry::{IntegratorFactory, IntegratorRegistry};

use crate::error::Result;
pub use crate::film::ShardAxis;
use crate::geometry::Ray;
use crate::primitives::Hit;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::Vec3;
use std::sync::atomic::AtomicBool;

/// What a pass is asked to do.
#[derive(Clone, Copy, Debug)]
pub struct PassInfo<'a> {
    /// 0-based pass number (also seeds the pass's random numbers).
    pub index: u32,
    /// Camera samples per pixel in this pass.
    pub spp: u32,
    /// Samples per pixel rendered in earlier passes (index of this pass's first sample).
    pub first_sample: u64,
    /// The render's settings (sampler, pattern, filter, seed, adaptive sampling).
    pub settings: &'a RenderSettings,
}

/// A rendering method that advances the image one progressive pass at a time.
pub trait Integrator: Send + Sync {
    /// One-time set-up after the scene and lights are built (Prepare stage).
    fn prepare(&mut self, _scene: &Scene, _settings: &RenderSettings) -> Result<()> {
        Ok(())
    }

    /// Render one pass. Must stop early (returning what it has) when `cancel` becomes true.
    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput;

    /// A short progress note for the progress bar and the render summary (e.g. photons traced).
    fn status(&self) -> Option<String> {
        None
    }

    /// How `--shard K/N` splits this integrator's work: by passes (the default: independent sample sums add up) or
    /// by pixel rows (for methods whose passes depend on each other, such as progressive photon mapping).
    fn shard_axis(&self) -> ShardAxis {
        ShardAxis::Passes
    }

    /// Samples a pass holds when the render's budget is time alone (`planned`: the settings' choice). The pass the
    /// budget ends is cut short and does not count; an integrator whose samples build on each other (photon
    /// mapping's iterations, whose cut pass is dropped whole) takes one per pass, so the budget loses at most one.
    fn samples_per_timed_pass(&self, planned: u32) -> u32 {
        planned
    }

    /// Whether `adaptive` settings change how this integrator distributes samples (per-pixel estimators do; a
    /// render asking for it with another integrator is warned that it has no effect).
    fn adapts_samples(&self) -> bool {
        false
    }

    /// The image's estimated relMSE from the integrator's own statistics, for noise targets, where the film cannot
    /// tell (methods whose film holds an estimate, not sums of samples: `Film::relative_error` covers the others).
    /// `None` by default and before there is an estimate.
    fn relative_error(&self) -> Option<f64> {
        None
    }

    /// The state a resumed render needs besides the film (saved in `.prism-film` files); empty by default.
    fn save_state(&self) -> Vec<u8> {
        Vec::new()
    }

    /// Restore what `save_state` saved (after `prepare`).
    fn load_state(&mut self, state: &[u8]) -> Result<()> {
        if state.is_empty() {
            Ok(())
        } else {
            Err(crate::error::PrismError::invalid("this integrator keeps no state, but the film file has some"))
        }
    }
}

/// An estimator of the radiance arriving along a camera ray.
pub trait PixelIntegrator: Send + Sync {
    /// One-time set-up after the scene and lights are built (Prepare stage), as [`Integrator::prepare`].
    fn prepare(&mut self, _scene: &Scene, _settings: &RenderSettings) -> Result<()> {
        Ok(())
    }

    /// Radiance along `ray` (towards its origin), drawing every random decision from `sampler` (its camera
    /// dimensions are already used: the next request is the integrator's first).
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3;

    /// Whether [`PixelIntegrator::radiance_from`] uses the camera ray's hit it is given: `PerPixel` then traces a
    /// pixel's camera rays together, sixteen at a time ([`Scene::intersect_packet`]), before their paths.
    fn takes_camera_hits(&self) -> bool {
        false
    }

    /// [`PixelIntegrator::radiance`] with the closest hit of `ray` already found (`hit`: what [`Scene::intersect`]
    /// gives, or a surface at exactly the same distance). By default the hit is not used.
    fn radiance_from(&self, scene: &Scene, ray: Ray, _hit: Option<Hit>, sampler: &mut Sampler) -> Vec3 {
        self.radiance(scene, ray, sampler)
    }

    /// The dimensions of the 2D requests most of its paths make, ascending (the order it makes them): where `PerPixel`
    /// traces camera rays in packets it computes these Sobol points for the packet's samples together
    /// ([`crate::sampling::SobolBatch`]; the same numbers, fewer instructions). By default none.
    fn batched_2d_dims(&self) -> Vec<u32> {
        Vec::new()
    }

    /// Those of [`PixelIntegrator::batched_2d_dims`] that it asks for as BSDF directions
    /// ([`Sampler::next_direction_2d`]): the batch computes their cosine-weighted hemisphere directions too. By
    /// default none.
    fn batched_direction_dims(&self) -> Vec<u32> {
        Vec::new()
    }
}
