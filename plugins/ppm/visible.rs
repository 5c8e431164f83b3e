//! The eye pass: one camera sample per pixel (sample index = the iteration, so the low-discrepancy sampler
//! stratifies pixel positions and lens samples over iterations), traced through specular chains — mirrors,
//! dielectrics with the exact Fresnel split — to the first vertex with a smooth BSDF lobe, where the visible point
//! is stored with its path weight. A surface with both smooth and delta lobes is resolved by the BSDF's own lobe
//! choice: the visible point takes the smooth part with weight `1 / P(smooth)`, the chain continues through the
//! delta lobe otherwise, so nothing is lost. Emission seen along the chain (lights, the environment on escape) is
//! added to the pixel; in stochastic mode the visible point also receives next-event estimation of direct light.

use crate::bsdf::Bsdf;
use crate::lights::LightSampler;
use crate::primitives::SurfaceHit;
use crate::sampling::{Rng, Sampler, SamplerKind, hash_u64};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use glam::{Vec2, Vec3, Vec3A};

/// A pixel's visible point for one iteration.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    pub hit: SurfaceHit,
    /// Unit direction back along the eye path.
    pub wo: Vec3A,
    /// Path weight from the camera (specular chain, lobe choice).
    pub beta: Vec3,
    /// Length of the eye path (for the default radius).
    pub path_length: f32,
    /// Specular vertices before it (the eye path to it has `eye_depth + 1` segments).
    pub eye_depth: u32,
}

/// What one eye path produced: emission and direct light reaching the pixel, and the visible point if any.
#[derive(Clone, Copy, Debug, Default)]
pub struct EyeResult {
    pub direct: Vec3,
    pub vp: Option<VisiblePoint>,
}

pub struct EyePass<'a> {
    pub scene: &'a Scene,
    pub lights: &'a LightSampler,
    pub settings: &'a RenderSettings,
    pub sampler: SamplerKind,
    /// Most path segments (`PpmParams::segments`).
    pub max_segments: u32,
    /// Estimate direct light at the visible point (stochastic mode); fixed mode gets it from photons.
    pub direct_lighting: bool,
    /// Trace the pixel centre (fixed mode's single eye pass) instead of a filtered, jittered position.
    pub pixel_centre: bool,
}

impl EyePass<'_> {
    /// Trace pixel (x, y) for `iteration`.
    pub fn trace_pixel(&self, x: u32, y: u32, iteration: u64) -> EyeResult {
        let s = self.settings;
        let scene = self.scene;
        let pixel = y as u64 * s.width as u64 + x as u64;
        let key = hash_u64(s.seed ^ hash_u64(pixel)) as u32;
        let mut sampler = Sampler::new(self.sampler, key, Rng::for_pixel(s.seed, pixel, iteration));
        sampler.start(iteration as u32);
        let u_pixel = sampler.next_2d();
        let u_lens = if scene.camera.has_lens() { sampler.next_2d() } else { Vec2::ZERO };
        let offset = if self.pixel_centre { Vec2::ZERO } else { s.filter.warp(u_pixel) };
        let mut ray = scene.camera.generate_ray_lens(Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset, u_lens);
        let mut out = EyeResult::default();
        let mut beta = Vec3::ONE;
        let mut length = 0.0;
        for depth in 0..self.max_segments {
            let Some(hit) = scene.trace(&ray) else {
                out.direct += beta * scene.escaped(ray.dir);
                break;
            };
            length += hit.t;
            let wo = -ray.dir;
            out.direct += beta * scene.emitted(&hit, wo);
            let Some(bsdf) = scene.bsdf(&hit, wo) else { break };
            let (u_lobe, u_bsdf) = (sampler.next_1d(), sampler.next_2d());
            let (u_choice, u_light) = (sampler.next_1d(), sampler.next_2d());
            let p_smooth = bsdf.smooth_probability();
            if p_smooth > 0.0 && !bsdf.picks_delta(u_lobe) {
                let vp_beta = beta / p_smooth;
                // Direct light adds a segment; a visible point needs room for a photon's two segments at least.
                if self.direct_lighting && depth + 2 <= self.max_segments {
                    out.direct += vp_beta * self.direct(&hit, &bsdf, u_choice, u_light);
                }
                if depth + 2 <= self.max_segments {
                    out.vp = Some(VisiblePoint { hit, wo, beta: vp_beta, path_length: length, eye_depth: depth });
                }
                break;
            }
            let Some(bs) = bsdf.sample(u_lobe, u_bsdf) else { break };
            beta *= bs.weight;
            if !(beta.max_element() > 0.0 && beta.is_finite()) {
                break;
            }
            ray = hit.spawn(bs.wi);
        }
        out
    }

    /// Next-event estimation of direct light at a visible point (light sampling alone: the eye path ends here, so
    /// there is no BSDF-sampled emission to weigh against).
    fn direct(&self, hit: &SurfaceHit, bsdf: &Bsdf, u_choice: f32, u_light: Vec2) -> Vec3 {
        let scene = self.scene;
        let n = bsdf.normal();
        let Some(ls) = self.lights.sample_li(&scene.lights, &scene.prims, hit.p, n, u_choice, u_light) else {
            return Vec3::ZERO;
        };
        // The BSDF is zero on the side it does not scatter to (transmissive lobes scatter to both).
        let f = bsdf.eval(ls.wi);
        let cos = ls.wi.dot(n).abs();
        if f == Vec3::ZERO || ls.pdf <= 0.0 || scene.occluded(&hit.spawn_to(&ls)) {
            return Vec3::ZERO;
        }
        f * ls.li * (cos / ls.pdf)
    }
}
