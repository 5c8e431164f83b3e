//! Next-event estimation at a path vertex, shared by the integrators that weigh it against BSDF sampling: one
//! light chosen by power and sampled towards the vertex ([`LightSampler::sample_li`]), its shadow ray traced, and
//! the contribution `f Li |cos| w / pdf` with `w` the power heuristic against the BSDF's density for the same
//! direction (1 for delta lights, which BSDF sampling cannot reach, and when MIS is off). Without MIS, light
//! sampling of area and environment lights counts the BSDF without its near-specular parts, which BSDF sampling
//! alone counts ([`Bsdf::eval_wide`]).

use crate::bsdf::Bsdf;
use crate::lights::LightSampler;
use crate::primitives::SurfaceHit;
use crate::sampling::power_heuristic;
use crate::scene::Scene;
use glam::{Vec2, Vec3};

impl LightSampler {
    /// Direct light at `s` (BSDF `bsdf`) from one light sample drawn with `u_choice` and `u`, weighted by the power
    /// heuristic against BSDF sampling when `mis` (light sampling alone counts it otherwise, but for the BSDF's
    /// near-specular parts, which the caller's BSDF sample counts: [`Bsdf::near_specular_share`]); 0 when the light is
    /// occluded, the BSDF does not scatter that way, or the sample has no density.
    #[inline(always)]
    pub fn direct_light(&self, scene: &Scene, s: &SurfaceHit, bsdf: &Bsdf, u_choice: f32, u: Vec2, mis: bool) -> Vec3 {
        let n = bsdf.normal();
        let Some((ls, slot)) = self.sample_li(&scene.lights, &scene.prims, s.p, n, u_choice, u) else {
            return Vec3::ZERO;
        };
        let (f, bsdf_pdf) = if mis || ls.delta { bsdf.eval_pdf(ls.wi) } else { (bsdf.eval_wide(ls.wi), 0.0) };
        if f == Vec3::ZERO || ls.pdf <= 0.0 || (!self.proven_clear(s, slot) && scene.occluded(&ls.shadow_ray(s))) {
            return Vec3::ZERO;
        }
        let w = if ls.delta || !mis { 1.0 } else { power_heuristic(ls.pdf, bsdf_pdf) };
        f * ls.li * (ls.wi.dot(n).abs() * w / ls.pdf)
    }
}
