//! The light sampling an integrator does, in one place: choose a light in proportion to its power
//! ([`PowerLightSampler`]), then sample it — towards a reference point for next-event estimation (`sample_li`), or an
//! emitted ray for photon and light tracing (`sample_le`). The environment (slot `lights.len()`) is sampled through
//! an [`EnvSampling`] of the integrator's chosen strategy, built only when the scene has an environment light.
//! Integrators build one in Prepare: `LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree)`.

use super::{ClearShadows, EnvSampling, EnvStrategy, LeSample, LightSample, LightSet, PowerLightSampler};
use crate::primitives::{Primitives, SurfaceHit};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// An integrator's light sampling: the choice of a light, the environment's direction sampler, and the shadow
/// rays proven clear.
#[derive(Clone, Debug)]
pub struct LightSampler {
    /// Which light slot a sample goes to, by power.
    pub choice: PowerLightSampler,
    /// The environment's direction sampler (present when the scene has an environment light).
    pub env: Option<EnvSampling>,
    /// Shadow rays proven clear without tracing them (scenes and lights it covers; see [`ClearShadows`]).
    pub clear: Option<Arc<ClearShadows>>,
}

impl LightSampler {
    /// Light sampling over `lights`, the environment's directions drawn by `strategy`; the shadow proofs are
    /// built here (where the scene and its lights allow them).
    pub fn new(lights: &LightSet, prims: &Primitives, strategy: EnvStrategy) -> Self {
        LightSampler {
            choice: PowerLightSampler::new(lights, prims),
            env: lights.environment.as_ref().map(|e| EnvSampling::new(e, strategy)),
            clear: ClearShadows::new(lights, prims).map(Arc::new),
        }
    }

    /// True when the shadow ray from `s` to a point of light `slot` is known to be clear without tracing it.
    #[inline(always)]
    pub fn proven_clear(&self, s: &SurfaceHit, slot: usize) -> bool {
        self.clear.as_ref().is_some_and(|c| c.proven_clear(s, slot))
    }

    /// True when the scene has no light to sample.
    pub fn is_empty(&self) -> bool {
        self.choice.is_empty()
    }

    /// True when `sample_li` reads its light-choice number (more than one light, counting the environment).
    #[inline]
    pub fn uses_choice_number(&self) -> bool {
        self.choice.len() > 1
    }

    /// True when some light emits (non-zero total power).
    pub fn has_power(&self) -> bool {
        self.choice.has_power
    }

    /// Next-event estimation from point `p` (shading normal `n`, used by the cosine environment strategy): one light
    /// chosen by power with `u_choice`, sampled with `u`; the sample and the slot of the light chosen. The returned
    /// pdf includes the choice probability.
    #[inline(always)]
    pub fn sample_li(
        &self,
        lights: &LightSet,
        prims: &Primitives,
        p: Vec3A,
        n: Vec3A,
        u_choice: f32,
        u: Vec2,
    ) -> Option<(LightSample, usize)> {
        if self.choice.is_empty() {
            return None;
        }
        let (slot, prob) = self.choice.choose(u_choice);
        if slot == lights.len() {
            let (env, es) = (lights.environment.as_ref()?, self.env.as_ref()?);
            let (wi, pdf) = es.sample(env, n, u)?;
            let ls = LightSample {
                p: p + wi * 1e30,
                p_err: Vec3A::ZERO,
                n: Vec3A::ZERO,
                wi,
                dist: f32::INFINITY,
                li: env.eval(wi),
                pdf: prob * pdf,
                delta: false,
            };
            return Some((ls, slot));
        }
        let mut ls = lights.sample_li(slot, prims, p, u)?;
        ls.pdf *= prob;
        Some((ls, slot))
    }

    /// The pdf `sample_li` from `p` gives the point `s` of area light `slot` (for MIS weights of emission that BSDF
    /// sampling found).
    #[inline]
    pub fn pdf_li_area(&self, lights: &LightSet, prims: &Primitives, slot: usize, p: Vec3A, s: &SurfaceHit) -> f32 {
        self.choice.prob(slot) * lights.pdf_li(slot, prims, p, s)
    }

    /// The pdf `sample_li` at a point with shading normal `n` gives the world direction `dir` towards the
    /// environment.
    #[inline]
    pub fn pdf_li_env(&self, lights: &LightSet, n: Vec3A, dir: Vec3A) -> f32 {
        match (&lights.environment, &self.env) {
            (Some(env), Some(es)) => self.choice.prob(lights.len()) * es.pdf(env, n, dir),
            _ => 0.0,
        }
    }

    /// An emitted ray of a light chosen by power with `u_choice`; returns the sample and the choice probability (the
    /// photon's power is `sample.flux() / prob`). `None` when the chosen light emits nothing this way.
    #[inline]
    pub fn sample_le(
        &self,
        lights: &LightSet,
        prims: &Primitives,
        u_choice: f32,
        u_pos: Vec2,
        u_dir: Vec2,
    ) -> Option<(LeSample, f32)> {
        if self.choice.is_empty() || !self.choice.has_power {
            return None;
        }
        let (slot, prob) = self.choice.choose(u_choice);
        let le = if slot == lights.len() {
            let (env, es) = (lights.environment.as_ref()?, self.env.as_ref()?);
            env.sample_le(es, &lights.sphere, u_pos, u_dir)?
        } else {
            lights.sample_le(slot, prims, u_pos, u_dir)?
        };
        (le.pdf_pos > 0.0 && le.pdf_dir > 0.0).then_some((le, prob))
    }
}
