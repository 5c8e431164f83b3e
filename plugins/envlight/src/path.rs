//! The path tracer: unidirectional path tracing with next-event estimation (one light per vertex, chosen by
//! power: the environment through its sampler, area lights by area/cone sampling, point and directional lights),
//! BSDF sampling (cosine, Phong lobe, mirror, Fresnel dielectric), multiple importance sampling with the power
//! heuristic, and Russian roulette (`prism_core::integrator::roulette`). `max_depth` counts path segments as Mitsuba
//! does (the camera ray is segment 1): 1 shows emitters only, 2 is direct lighting (the single-bounce environment
//! lighting of the seed), -1 is unlimited. Every vertex draws the same seven sampler dimensions in a fixed order —
//! light choice (1D), light point (2D), BSDF lobe (1D), BSDF direction (2D), Russian roulette (1D) — so the
//! low-discrepancy sampler stratifies each of them at every bounce.

use super::EnvlightParams;
use glam::{Vec3, Vec3A};
use prism_core::bsdf::Bsdf;
use prism_core::geometry::Ray;
use prism_core::integrator::PixelIntegrator;
use prism_core::integrator::roulette::survival;
use prism_core::lights::LightSampler;
use prism_core::primitives::{Hit, NO_LIGHT};
use prism_core::sampling::{CAMERA_DIMENSIONS, Sampler, power_heuristic};
use prism_core::scene::Scene;

pub struct PathTracer {
    pub params: EnvlightParams,
    pub lights: LightSampler,
}

/// The previous scattering vertex, for MIS weights of emission found by BSDF sampling.
#[derive(Clone, Copy)]
struct Prev {
    p: Vec3A,
    n: Vec3A,
    pdf: f32,
    delta: bool,
    /// Without MIS: the share of the BSDF's value in the sampled direction held by its near-specular parts, which
    /// light sampling leaves to BSDF sampling (`Bsdf::near_specular_share`; zero when it has none).
    near_specular: Vec3,
}

impl PathTracer {
    /// MIS weight (per RGB channel) of emission reached by a BSDF sample whose light-sampling pdf would have been
    /// `light_pdf`.
    #[inline]
    fn bsdf_weight(&self, prev: &Option<Prev>, light_pdf: f32) -> Vec3 {
        match prev {
            None => Vec3::ONE,
            Some(p) if p.delta => Vec3::ONE,
            Some(p) if self.params.mis => Vec3::splat(power_heuristic(p.pdf, light_pdf)),
            // Without MIS, emission that light sampling can reach is counted by light sampling only, but for the
            // near-specular parts of the BSDF, which light sampling leaves to this sample.
            Some(p) if light_pdf > 0.0 => p.near_specular,
            Some(_) => Vec3::ONE,
        }
    }
}

impl PixelIntegrator for PathTracer {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        self.path(scene, ray, None, sampler)
    }

    fn takes_camera_hits(&self) -> bool {
        true
    }

    #[inline(always)]
    fn radiance_from(&self, scene: &Scene, ray: Ray, hit: Option<Hit>, sampler: &mut Sampler) -> Vec3 {
        self.path(scene, ray, Some(hit), sampler)
    }

    /// The light and BSDF points of the first `BATCHED_VERTICES` vertices (fewer where `max_depth` ends paths
    /// sooner): vertex `v` draws its seven dimensions from `CAMERA_DIMENSIONS + 7 v`, its light point at offset 1
    /// and its BSDF point at offset 4 (see `path`).
    fn batched_2d_dims(&self) -> Vec<u32> {
        let vertices = match self.params.max_depth {
            -1 => BATCHED_VERTICES,
            d => (d as u32).min(BATCHED_VERTICES),
        };
        (0..vertices).flat_map(|v| [CAMERA_DIMENSIONS + 7 * v + 1, CAMERA_DIMENSIONS + 7 * v + 4]).collect()
    }

    /// The BSDF points of `batched_2d_dims` (offset 4 of each vertex's seven dimensions).
    fn batched_direction_dims(&self) -> Vec<u32> {
        self.batched_2d_dims().into_iter().skip(1).step_by(2).collect()
    }
}

/// Path vertices whose Sobol points `PerPixel` may compute ahead for a packet's samples (`batched_2d_dims`; each tile
/// then keeps those most of its paths reach).
const BATCHED_VERTICES: u32 = 6;

impl PathTracer {
    /// The path from camera ray `ray`, whose closest hit is `first` if already traced.
    #[inline(always)]
    fn path(&self, scene: &Scene, mut ray: Ray, mut first: Option<Option<Hit>>, sampler: &mut Sampler) -> Vec3 {
        let max_depth = self.params.max_depth;
        let mut l = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut prev: Option<Prev> = None;
        let mut depth: i32 = 0;
        // Product of eta^2 over the refractions so far (1 again once a path has left every dielectric).
        let mut eta2 = 1.0f32;
        // One BSDF for the whole path, rebuilt in place at every hit.
        let mut bsdf = Bsdf::new(prism_core::math::Frame::from_normal(Vec3A::Z), Vec3A::Z, Vec3A::Z);
        loop {
            // The vertex's dimensions in their fixed order, drawn before its ray is traced: they do not depend on
            // what the ray hits, so the hashing of the two 2D points overlaps the traversal instead of following it
            // (2-3% on the box scenes, 1% on `env_sphere`, where more paths end in the sky and draw them for nothing;
            // the same numbers, so the same images). The 1D numbers are computed only if used.
            let (u_choice, u_light) = (sampler.defer_1d(), sampler.next_2d());
            let (u_lobe, u_bsdf) = (sampler.defer_1d(), sampler.next_direction_2d());
            let u_rr = sampler.defer_1d();
            // One copy of the hit record's construction for the camera's hit and every later one (inlined here,
            // where `Scene::trace` would build it out of line and move it).
            let hit = match first.take() {
                Some(hit) => hit,
                None => scene.intersect(&ray),
            };
            // A `match`, not `Option::map`: LLVM folds the map's closure into `Scene::trace`'s identical one and
            // calls it out of line.
            #[allow(clippy::manual_map)]
            let traced = match hit {
                Some(h) => Some(scene.prims.surface(&ray, &h)),
                None => None,
            };
            let Some(s) = traced else {
                if let Some(env) = &scene.lights.environment {
                    let le = env.eval(ray.dir);
                    let light_pdf = match &prev {
                        Some(p) => self.lights.pdf_li_env(&scene.lights, p.n, ray.dir),
                        None => 0.0,
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
                            self.lights.pdf_li_area(&scene.lights, &scene.prims, s.light as usize, p.p, &s)
                        }
                        _ => 0.0,
                    };
                    l += beta * le * self.bsdf_weight(&prev, light_pdf);
                }
            }
            if max_depth >= 0 && depth + 1 >= max_depth {
                break;
            }
            if !scene.bsdf_into(&s, wo, &mut bsdf) {
                break;
            }
            if bsdf.has_smooth() && !self.lights.is_empty() {
                let uc = if self.lights.uses_choice_number() { sampler.get_1d(u_choice) } else { 0.0 };
                l += beta * self.lights.direct_light(scene, &s, &bsdf, uc, u_light, self.params.mis);
            }
            let ul = if bsdf.uses_lobe_number() { sampler.get_1d(u_lobe) } else { 0.0 };
            let Some(bs) = bsdf.sample_point(ul, u_bsdf) else { break };
            beta *= bs.weight;
            eta2 *= bs.eta * bs.eta;
            if beta.max_element() <= 0.0 {
                break;
            }
            let near_specular = if self.params.mis || bs.delta || !bsdf.has_near_specular() {
                Vec3::ZERO
            } else {
                bsdf.near_specular_share(bs.wi)
            };
            prev = Some(Prev { p: s.p, n: bsdf.normal(), pdf: bs.pdf, delta: bs.delta, near_specular });
            depth += 1;
            if depth >= self.params.rr_depth {
                // Survival by throughput against a threshold, the radiance scaling of refractions undone (a path
                // inside glass carries 1/eta^2 that its exit restores, so it is not a dimmer path).
                // A path that survives surely (`q` = 1: most bright paths) reads no roulette number; its dimension
                // stays reserved, so the sequence does not shift. The image is the same bit for bit, since a number
                // in [0, 1) is never at least 1 and dividing by 1 is exact.
                let q = survival(beta, eta2, self.params.rr_threshold, depth);
                if q < 1.0 {
                    if sampler.get_1d(u_rr) >= q {
                        break;
                    }
                    beta /= q;
                }
            }
            ray = s.spawn(bs.wi);
        }
        l
    }
}
