//! The path tracer: unidirectional path tracing with next-event estimation (one light per vertex, chosen by
//! power: the environment through its sampler, area lights by area/cone sampling, point and directional lights),
//! BSDF sampling (cosine, Phong lobe, mirror, Fresnel dielectric), multiple importance sampling with the power
//! heuristic, and Russian roulette. `max_depth` counts path segments as Mitsuba does (the camera ray is segment 1):
//! 1 shows emitters only, 2 is direct lighting (the single-bounce environment lighting of the seed), -1 is
//! unlimited. The first vertex's light and BSDF samples are stratified across the pixel's samples (Owen-scrambled
//! Sobol points, see `PixelSample`).

use super::EnvlightParams;
use super::env_sampling::EnvSampling;
use super::light_choice::LightChoice;
use crate::bsdf::Bsdf;
use crate::geometry::Ray;
use crate::integrator::{PixelIntegrator, PixelSample};
use crate::primitives::{NO_LIGHT, SurfaceHit};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::{Vec3, Vec3A};

pub struct PathTracer {
    pub params: EnvlightParams,
    pub env: Option<EnvSampling>,
    pub choice: LightChoice,
}

/// The previous scattering vertex, for MIS weights of emission found by BSDF sampling.
#[derive(Clone, Copy)]
struct Prev {
    p: Vec3A,
    n: Vec3A,
    pdf: f32,
    delta: bool,
}

#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 == 0.0 { 0.0 } else { a2 / (a2 + b2) }
}

impl PathTracer {
    /// MIS weight of emission reached by a BSDF sample whose light-sampling pdf would have been `light_pdf`.
    #[inline]
    fn bsdf_weight(&self, prev: &Option<Prev>, light_pdf: f32) -> f32 {
        match prev {
            None => 1.0,
            Some(p) if p.delta => 1.0,
            Some(p) if self.params.mis => power_heuristic(p.pdf, light_pdf),
            // Without MIS, emission that light sampling can reach is counted by light sampling only.
            Some(_) if light_pdf > 0.0 => 0.0,
            Some(_) => 1.0,
        }
    }

    /// Next-event estimation at `s`: one light chosen by power.
    #[inline]
    fn sample_light(&self, scene: &Scene, s: &SurfaceHit, bsdf: &Bsdf, u_choice: f32, u: glam::Vec2) -> Vec3 {
        let (slot, p_choice) = self.choice.choose(u_choice);
        let lights = &scene.lights;
        let n = bsdf.normal();
        if slot == lights.len() {
            let (Some(env), Some(es)) = (&lights.environment, &self.env) else { return Vec3::ZERO };
            let Some((wi, pdf)) = es.sample(env, n, u) else { return Vec3::ZERO };
            let f = bsdf.eval(wi);
            let cos = wi.dot(n).abs();
            if f == Vec3::ZERO || scene.occluded(&s.spawn(wi)) {
                return Vec3::ZERO;
            }
            let light_pdf = p_choice * pdf;
            let w = if self.params.mis { power_heuristic(light_pdf, bsdf.pdf(wi)) } else { 1.0 };
            return f * env.eval(wi) * (cos * w / light_pdf);
        }
        let Some(ls) = lights.sample(slot, &scene.prims, s.p, u) else { return Vec3::ZERO };
        let f = bsdf.eval(ls.wi);
        let cos = ls.wi.dot(n).abs();
        if f == Vec3::ZERO || scene.occluded(&s.spawn_to(&ls)) {
            return Vec3::ZERO;
        }
        let light_pdf = p_choice * ls.pdf;
        let w = if ls.delta || !self.params.mis { 1.0 } else { power_heuristic(light_pdf, bsdf.pdf(ls.wi)) };
        f * ls.li * (cos * w / light_pdf)
    }
}

impl PixelIntegrator for PathTracer {
    fn radiance(&self, scene: &Scene, ray: Ray, rng: &mut Rng) -> Vec3 {
        self.radiance_stratified(scene, ray, &PixelSample::independent(), rng)
    }

    fn radiance_stratified(&self, scene: &Scene, mut ray: Ray, sample: &PixelSample, rng: &mut Rng) -> Vec3 {
        let max_depth = self.params.max_depth;
        let mut l = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut prev: Option<Prev> = None;
        let mut depth: i32 = 0;
        loop {
            let Some(s) = scene.trace(&ray) else {
                if let Some(env) = &scene.lights.environment {
                    let le = env.eval(ray.dir);
                    let light_pdf = match (&self.env, &prev) {
                        (Some(es), Some(p)) => self.choice.prob(scene.lights.len()) * es.pdf(env, p.n, ray.dir),
                        _ => 0.0,
                    };
                    l += beta * le * self.bsdf_weight(&prev, light_pdf);
                } else {
                    l += beta * scene.globals.background;
                }
                break;
            };
            let wo = -ray.dir;
            if s.light != NO_LIGHT {
                let le = scene.emitted(&s, wo);
                if le != Vec3::ZERO {
                    let light_pdf = match &prev {
                        Some(p) if !p.delta => {
                            self.choice.prob(s.light as usize)
                                * scene.lights.pdf(s.light as usize, &scene.prims, p.p, &s)
                        }
                        _ => 0.0,
                    };
                    l += beta * le * self.bsdf_weight(&prev, light_pdf);
                }
            }
            if max_depth >= 0 && depth + 1 >= max_depth {
                break;
            }
            let Some(bsdf) = scene.bsdf(&s, wo) else { break };
            // The first vertex draws stratified light and BSDF samples (dimensions 0 and 1 of the pixel sample).
            let (u_light, u_bsdf) = if depth == 0 {
                (sample.stratified_2d(0, rng), sample.stratified_2d(1, rng))
            } else {
                (rng.next_2d(), rng.next_2d())
            };
            if bsdf.has_smooth() && !self.choice.is_empty() {
                l += beta * self.sample_light(scene, &s, &bsdf, rng.next_f32(), u_light);
            }
            let Some(bs) = bsdf.sample(rng.next_f32(), u_bsdf) else { break };
            beta *= bs.weight;
            if beta.max_element() <= 0.0 {
                break;
            }
            prev = Some(Prev { p: s.p, n: bsdf.normal(), pdf: bs.pdf, delta: bs.delta });
            depth += 1;
            if depth >= self.params.rr_depth {
                let q = beta.max_element().min(0.95);
                if rng.next_f32() >= q {
                    break;
                }
                beta /= q;
            }
            ray = s.spawn(bs.wi);
        }
        l
    }
}
