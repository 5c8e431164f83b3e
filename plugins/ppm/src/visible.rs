//! The eye pass: one camera sample per pixel (sample index = the iteration, so the low-discrepancy sampler
//! stratifies pixel positions and lens samples over iterations), traced through specular chains — mirrors,
//! dielectrics with the exact Fresnel split — to the first vertex with a smooth BSDF lobe, where the visible point
//! is stored with its path weight. A surface with both smooth and delta lobes is resolved by the BSDF's own lobe
//! choice: the visible point takes the smooth part with weight `1 / P(smooth)`, the chain continues through the
//! delta lobe otherwise, so nothing is lost. Emission seen along the chain (lights, the environment on escape) is
//! added to the pixel; in stochastic mode the visible point also receives next-event estimation of direct light.
//!
//! In stochastic mode near-specular parts (a plastic's coat of GGX width under 0.01, such metals under
//! `glossy: gather`; `prism_core::bsdf::NEAR_SPECULAR_ALPHA`) are split off the same way: light sampling and photons
//! cannot find what so narrow a lobe reflects, so the lobe choice continues the chain through them (weight: the
//! near-specular part's value over its density) and the visible point takes the rest of the BSDF
//! (`Bsdf::eval_wide`) with weight `1 / P(wide)`. Point, spot and directional lights, which the chain cannot hit,
//! still light the visible point through the whole BSDF.
//!
//! Glossy surfaces (smooth lobes, none diffuse: rough metal and glass) are traced through by default
//! (`glossy: trace`, pbrt-v4's rule): the vertex gets next-event estimation weighted by multiple importance
//! sampling (power heuristic) against the BSDF sample that continues the path, whose emission found at the next
//! vertex takes the complementary weight, as in `envlight`; Russian roulette (Mitsuba's rule,
//! `integrator::roulette::mitsuba_survival`) from the `RR_VERTICES`th eye vertex on ends long glossy chains. The
//! visible point then lies on the next diffuse surface, so what a rough surface reflects is as sharp as its BSDF,
//! not blurred over the gather radius. With `glossy: gather` (and in fixed mode) the visible point lies on the
//! glossy surface itself.

use glam::{Vec2, Vec3, Vec3A};
use prism_core::bsdf::{Bsdf, BsdfPart};
use prism_core::lights::LightSampler;
use prism_core::primitives::SurfaceHit;
use prism_core::sampling::{Rng, Sampler, SamplerKind, hash_u64, power_heuristic};
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;

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
    /// Most eye path segments to a visible point or an emitter (`PpmParams::eye_segments`, at most `max_segments`).
    pub eye_segments: u32,
    /// Estimate direct light at the visible point (stochastic mode); fixed mode gets it from photons.
    pub direct_lighting: bool,
    /// Trace the pixel centre (fixed mode's single eye pass) instead of a filtered, jittered position.
    pub pixel_centre: bool,
    /// Trace on through glossy surfaces instead of putting the visible point on them (see the module doc).
    pub trace_glossy: bool,
    /// Continue the chain through near-specular parts and give the visible point the rest (stochastic mode; see
    /// the module doc). Photon gathers then use `Bsdf::eval_wide` too.
    pub split_near_specular: bool,
}

/// The eye vertex from which Russian roulette may end a path traced through glossy surfaces.
const RR_VERTICES: u32 = 5;

/// A glossy vertex the eye path was traced through: the MIS weight of emission its BSDF sample finds.
#[derive(Clone, Copy)]
struct GlossyVertex {
    p: Vec3A,
    n: Vec3A,
    pdf: f32,
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
        // The last vertex if it was glossy and traced through (emission found next is weighted against its NEE).
        let mut glossy: Option<GlossyVertex> = None;
        // Product of eta^2 over the refractions so far (Russian roulette undoes the radiance scaling).
        let mut eta2 = 1.0f32;
        for depth in 0..self.eye_segments.min(self.max_segments) {
            let Some(hit) = scene.trace(&ray) else {
                let w = match (&glossy, &scene.lights.environment) {
                    (Some(g), Some(_)) => power_heuristic(g.pdf, self.lights.pdf_li_env(&scene.lights, g.n, ray.dir)),
                    _ => 1.0,
                };
                out.direct += beta * scene.escaped(ray.dir) * w;
                break;
            };
            length += hit.t;
            let wo = -ray.dir;
            let le = scene.emitted(&hit, wo);
            if le != Vec3::ZERO {
                let w = match &glossy {
                    Some(g) => power_heuristic(
                        g.pdf,
                        self.lights.pdf_li_area(&scene.lights, &scene.prims, hit.light as usize, g.p, &hit),
                    ),
                    None => 1.0,
                };
                out.direct += beta * le * w;
            }
            let Some(bsdf) = scene.bsdf(&hit, wo) else { break };
            let (u_lobe, u_bsdf) = (sampler.next_1d(), sampler.next_2d());
            let (u_choice, u_light) = (sampler.next_1d(), sampler.next_2d());
            if self.trace_glossy && bsdf.has_smooth() && !bsdf.has_diffuse() {
                // Path-trace the glossy vertex: NEE and the BSDF sample, weighted by MIS. Its direct light and
                // the emission found next take one segment more.
                if depth + 2 > self.max_segments {
                    break;
                }
                out.direct += beta * self.lights.direct_light(scene, &hit, &bsdf, u_choice, u_light, true);
                let Some(bs) = bsdf.sample(u_lobe, u_bsdf) else { break };
                beta *= bs.weight;
                eta2 *= bs.eta * bs.eta;
                if !(beta.max_element() > 0.0 && beta.is_finite()) {
                    break;
                }
                glossy = (!bs.delta).then_some(GlossyVertex { p: hit.p, n: bsdf.normal(), pdf: bs.pdf });
                if depth + 1 >= RR_VERTICES {
                    let q = prism_core::integrator::roulette::mitsuba_survival(beta, eta2);
                    if sampler.next_1d() >= q {
                        break;
                    }
                    beta /= q;
                }
                ray = hit.spawn(bs.wi);
                continue;
            }
            glossy = None;
            let split = self.split_near_specular && bsdf.has_near_specular();
            let (p_wide, part) = if split {
                ((bsdf.smooth_probability() - bsdf.near_specular_probability()).max(0.0), bsdf.part(u_lobe))
            } else {
                let delta = bsdf.picks_delta(u_lobe);
                (bsdf.smooth_probability(), if delta { BsdfPart::Delta } else { BsdfPart::Wide })
            };
            if part == BsdfPart::Wide {
                if p_wide <= 0.0 {
                    break;
                }
                let vp_beta = beta / p_wide;
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
            let weight = match part {
                BsdfPart::NearSpecular => {
                    let Some(w) = bsdf.near_specular_weight(bs.wi) else { break };
                    w
                }
                _ => bs.weight,
            };
            beta *= weight;
            eta2 *= bs.eta * bs.eta;
            if !(beta.max_element() > 0.0 && beta.is_finite()) {
                break;
            }
            ray = hit.spawn(bs.wi);
        }
        out
    }

    /// Next-event estimation of direct light at a visible point (light sampling alone: the eye path ends here, so
    /// there is no BSDF-sampled emission to weigh against), through the BSDF without its near-specular parts for
    /// lights the chain can hit when those parts are split off (see the module doc).
    fn direct(&self, hit: &SurfaceHit, bsdf: &Bsdf, u_choice: f32, u_light: Vec2) -> Vec3 {
        let scene = self.scene;
        let n = bsdf.normal();
        let Some((ls, _)) = self.lights.sample_li(&scene.lights, &scene.prims, hit.p, n, u_choice, u_light) else {
            return Vec3::ZERO;
        };
        // The BSDF is zero on the side it does not scatter to (transmissive lobes scatter to both).
        let f = if self.split_near_specular && !ls.delta { bsdf.eval_wide(ls.wi) } else { bsdf.eval(ls.wi) };
        let cos = ls.wi.dot(n).abs();
        if f == Vec3::ZERO || ls.pdf <= 0.0 || scene.occluded(&ls.shadow_ray(hit)) {
            return Vec3::ZERO;
        }
        f * ls.li * (cos / ls.pdf)
    }
}
