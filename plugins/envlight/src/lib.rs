//! `envlight`: the environment-light plugin — HDR environment maps importance-sampled with a quad-tree, and a
//! Monte Carlo path tracer with next-event estimation, BSDF sampling, MIS and Russian roulette. It is Prism's
//! unbiased reference integrator.
//!
//! Parameters: `envlight(max_depth: -1, rr_depth: 1, rr_threshold: 0.5, env_sampling: quadtree, mis: true)`
//! - `max_depth`: path segments (1: emitters only, 2: direct lighting, -1: unlimited);
//! - `rr_depth`: Russian roulette from this many segments on;
//! - `rr_threshold`: a path whose throughput `max(beta) eta^2` (`eta^2` the radiance scaling of the refractions so
//!   far undone: a path inside glass is not a dimmer one) is below it survives with probability throughput /
//!   threshold, one at or above it surely (`prism_core::integrator::roulette`). Mitsuba's rule is close to
//!   `rr_depth: 5, rr_threshold: 1` (it also caps survival at 0.95);
//! - `env_sampling`: `quadtree` | `piecewise` | `uniform` | `cosine` (for comparisons);
//! - `mis`: weight light and BSDF sampling by the power heuristic; `false` uses light sampling alone for what
//!   it can reach (pure strategy comparisons).
//!
//! Light choice and the environment samplers (quad-tree, piecewise-constant) are the core's (`prism_core::lights`); the
//! sampler of the chosen strategy is built in the Prepare stage, only when the scene has an environment light.

mod path;

use path::PathTracer;
use prism_core::error::{PrismError, Result};
use prism_core::integrator::{PerPixel, PixelIntegrator};
use prism_core::lights::{EnvStrategy, LightSampler};
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;
use prism_engine::{App, Plugin};
use serde::Deserialize;

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct EnvlightParams {
    pub max_depth: i32,
    pub rr_depth: i32,
    pub rr_threshold: f32,
    pub env_sampling: EnvStrategy,
    pub mis: bool,
}

impl Default for EnvlightParams {
    fn default() -> Self {
        EnvlightParams {
            max_depth: -1,
            rr_depth: 1,
            rr_threshold: prism_core::integrator::roulette::DEFAULT_THRESHOLD,
            env_sampling: EnvStrategy::Quadtree,
            mis: true,
        }
    }
}

pub struct EnvlightPlugin;

impl Plugin for EnvlightPlugin {
    fn name(&self) -> &str {
        "envlight"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "envlight",
            Box::new(|cfg| {
                let params: EnvlightParams = cfg.parse_params()?;
                if params.max_depth == 0 || params.max_depth < -1 {
                    return Err(PrismError::invalid(format!(
                        "envlight: max_depth must be -1 (unlimited) or at least 1, got {}",
                        params.max_depth
                    )));
                }
                if params.rr_depth < 1 {
                    return Err(PrismError::invalid("envlight: rr_depth must be at least 1"));
                }
                if !(params.rr_threshold > 0.0 && params.rr_threshold.is_finite()) {
                    return Err(PrismError::invalid(format!(
                        "envlight: rr_threshold must be a positive finite number, got {}",
                        params.rr_threshold
                    )));
                }
                Ok(Box::new(PerPixel::new(Envlight { tracer: None, params })))
            }),
        );
    }
}

/// The integrator before Prepare (parameters only) and after (samplers built).
struct Envlight {
    params: EnvlightParams,
    tracer: Option<PathTracer>,
}

impl PixelIntegrator for Envlight {
    fn prepare(&mut self, scene: &Scene, _settings: &RenderSettings) -> Result<()> {
        let lights = LightSampler::new(&scene.lights, &scene.prims, self.params.env_sampling);
        self.tracer = Some(PathTracer { params: self.params, lights });
        Ok(())
    }

    #[inline]
    fn radiance(
        &self,
        scene: &Scene,
        ray: prism_core::geometry::Ray,
        sampler: &mut prism_core::sampling::Sampler,
    ) -> glam::Vec3 {
        self.tracer.as_ref().map_or(glam::Vec3::ZERO, |t| t.radiance(scene, ray, sampler))
    }

    fn takes_camera_hits(&self) -> bool {
        true
    }

    #[inline(always)]
    fn radiance_from(
        &self,
        scene: &Scene,
        ray: prism_core::geometry::Ray,
        hit: Option<prism_core::primitives::Hit>,
        sampler: &mut prism_core::sampling::Sampler,
    ) -> glam::Vec3 {
        // A `match`, not `map_or`: its closure would stay a call of its own, where this one is inlined into the
        // tile loop (`PerPixel`), so a camera sample's path costs no call and no call set-up.
        match &self.tracer {
            Some(t) => t.radiance_from(scene, ray, hit, sampler),
            None => glam::Vec3::ZERO,
        }
    }

    fn batched_2d_dims(&self) -> Vec<u32> {
        self.tracer.as_ref().map_or(Vec::new(), |t| t.batched_2d_dims())
    }

    fn batched_direction_dims(&self) -> Vec<u32> {
        self.tracer.as_ref().map_or(Vec::new(), |t| t.batched_direction_dims())
    }
}
