//! Near-specular parts of a BSDF: lobes (or, for plastic, the coat) so narrow that light sampling alone cannot find
//! what they reflect. A GGX lobe of width 0.001 covers about 1e-6 sr; a light sample lands in it once in a million
//! samples, so an estimator that counts such a lobe by light sampling alone (`envlight(mis: false)`, `ppm`'s
//! visible points and photon gathers) misses it at every practical sample count: on a plastic sphere in a white
//! furnace the coat's whole reflection was lost. Estimators without multiple importance sampling therefore split
//! the BSDF into a near-specular part, counted by BSDF sampling alone (like a delta lobe), and the rest, counted by
//! light sampling and density estimation. Any such split is unbiased (it is multiple importance sampling with
//! weights 0 and 1); the threshold only decides which strategy has less variance.
//!
//! Parameter: [`NEAR_SPECULAR_ALPHA`], the GGX width below which a lobe is near-specular (Phong and the course's
//! Blinn-Phong lobes by their equivalent width `sqrt(2 / (exponent + 2))`). Point, spot and directional lights,
//! which BSDF sampling cannot reach, are still counted by light sampling through the whole BSDF.

use super::lobe::plastic_specular_probability;
use super::microfacet::{ggx_d, ggx_g1, visible_pdf};
use super::{Bsdf, Lobe, TransportMode};
use glam::{Vec3, Vec3A};

/// GGX width below which a lobe is near-specular. Light sampling's relative variance on a lobe of width `alpha`
/// grows like `1 / alpha^2`, BSDF sampling's with the contrast of what the lobe reflects; under the Grace light probe
/// they cross between widths 0.01 and 0.02 (`docs/decisions/0033-near-specular-by-bsdf-sampling.md`).
pub const NEAR_SPECULAR_ALPHA: f32 = 0.01;

/// Which part of the BSDF a lobe number selects (see [`Bsdf::part`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BsdfPart {
    /// A smooth lobe wider than near-specular (or a plastic's base): light sampling and density estimation apply.
    Wide,
    /// A near-specular lobe, or a plastic's near-specular coat: BSDF sampling alone counts it.
    NearSpecular,
    /// A delta lobe.
    Delta,
}

impl Lobe {
    /// Probability that [`Lobe::sample`] draws from the lobe's near-specular part, seen from `wo` (local): 1 for a
    /// near-specular conductor, rough dielectric or Phong lobe, the coat's share for a plastic with a near-specular
    /// coat, 0 otherwise.
    #[inline]
    pub fn near_specular_probability(&self, wo: Vec3A) -> f32 {
        match *self {
            Lobe::Conductor { alpha, .. } | Lobe::RoughDielectric { alpha, .. }
                if alpha > 0.0 && alpha < NEAR_SPECULAR_ALPHA =>
            {
                1.0
            }
            Lobe::Phong { exponent, .. } | Lobe::Blinn6837 { exponent, .. }
                if 2.0 / (exponent + 2.0) < NEAR_SPECULAR_ALPHA * NEAR_SPECULAR_ALPHA =>
            {
                1.0
            }
            Lobe::Plastic { alpha, eta, diffuse, specular, .. } if alpha < NEAR_SPECULAR_ALPHA => {
                plastic_specular_probability(wo, eta, diffuse, specular)
            }
            _ => 0.0,
        }
    }

    /// The near-specular part's value and its density within the lobe (`f`, `pdf` of that part alone, as if it
    /// were sampled with probability 1); zeros for lobes without one.
    #[inline]
    fn near_specular_eval_pdf(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> (Vec3, f32) {
        match *self {
            Lobe::Plastic { alpha, eta, specular, .. } if alpha < NEAR_SPECULAR_ALPHA => {
                if !(wo.z > 0.0 && wi.z > 0.0) {
                    return (Vec3::ZERO, 0.0);
                }
                // The coat is a GGX reflection with a dielectric Fresnel term: its value is the plastic's value
                // minus the base's, its density the visible-normal density of the reflection.
                let h = (wo + wi).normalize();
                let g = ggx_g1(wo, h, alpha) * ggx_g1(wi, h, alpha);
                let fs = crate::math::fresnel_dielectric(wo.dot(h), eta) * ggx_d(h, alpha) * g / (4.0 * wo.z * wi.z);
                (specular * fs, visible_pdf(wo, h, alpha) / (4.0 * wo.dot(h)))
            }
            _ if self.near_specular_probability(wo) > 0.0 => (self.eval(wo, wi, mode), self.pdf(wo, wi)),
            _ => (Vec3::ZERO, 0.0),
        }
    }
}

impl Bsdf {
    /// True when some lobe has a near-specular part.
    #[inline]
    pub fn has_near_specular(&self) -> bool {
        self.lobes().iter().any(|l| l.near_specular_probability(self.wo_local) > 0.0)
    }

    /// Probability that [`Bsdf::sample`] draws from a near-specular part.
    pub fn near_specular_probability(&self) -> f32 {
        (0..self.len).map(|i| self.lobe_probability(i) * self.lobes[i].near_specular_probability(self.wo_local)).sum()
    }

    /// The part of the BSDF that `sample(u_lobe, ..)` draws from (it depends on `u_lobe` only).
    pub fn part(&self, u_lobe: f32) -> BsdfPart {
        if self.len == 0 {
            return BsdfPart::Wide;
        }
        // The lobe and the number within it, as `sample` computes them (a plastic draws its coat when the number
        // is below the coat's probability, a layered lobe with a smooth coat its mirror reflection).
        let (i, uc) = self.pick(u_lobe);
        let lobe = &self.lobes[i];
        if lobe.is_delta() || uc < lobe.delta_probability(self.wo_local) {
            return BsdfPart::Delta;
        }
        if uc < lobe.near_specular_probability(self.wo_local) { BsdfPart::NearSpecular } else { BsdfPart::Wide }
    }

    /// The near-specular part's value `f_ns(wo, wi)` (radiance) and the density with which [`Bsdf::sample`] draws
    /// `wi` through a near-specular part (lobe choice included).
    pub fn eval_near_specular(&self, wi: Vec3A) -> (Vec3, f32) {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return (Vec3::ZERO, 0.0);
        }
        let (mut f, mut pdf) = (Vec3::ZERO, 0.0);
        for (i, l) in self.lobes().iter().enumerate() {
            let q = l.near_specular_probability(self.wo_local);
            if q > 0.0 {
                let (fl, pl) = l.near_specular_eval_pdf(self.wo_local, wl, TransportMode::Radiance);
                f += fl;
                pdf += self.lobe_probability(i) * q * pl;
            }
        }
        (f, pdf)
    }

    /// The BSDF without its near-specular parts (radiance): what light sampling and density estimation count when
    /// BSDF sampling alone counts the near-specular parts. [`Bsdf::eval`] when there are none.
    pub fn eval_wide(&self, wi: Vec3A) -> Vec3 {
        let f = self.eval(wi);
        if f == Vec3::ZERO || !self.has_near_specular() {
            return f;
        }
        (f - self.eval_near_specular(wi).0).max(Vec3::ZERO)
    }

    /// The throughput `f_ns |cos| / pdf_ns` of a direction `wi` drawn by [`Bsdf::sample`] from a near-specular part
    /// ([`Bsdf::part`] said so): the estimate of the near-specular part alone, which with the wide part's estimate
    /// (chosen with the complementary probability) makes the whole BSDF's. `None` when it carries nothing.
    pub fn near_specular_weight(&self, wi: Vec3A) -> Option<Vec3> {
        let (f, pdf) = self.eval_near_specular(wi);
        let w = f * (self.frame.to_local(wi).z.abs() / pdf);
        (pdf > 0.0 && w.is_finite() && w.max_element() > 0.0).then_some(w)
    }

    /// Per RGB channel, the share `f_ns(wi) / f(wi)` of the BSDF's value in direction `wi` that its near-specular
    /// parts hold (0 where the BSDF is 0): the weight of emission found by a BSDF sample when light sampling counts
    /// only the rest.
    pub fn near_specular_share(&self, wi: Vec3A) -> Vec3 {
        let f = self.eval(wi);
        let ns = self.eval_near_specular(wi).0;
        Vec3::select(f.cmpgt(Vec3::ZERO), (ns / f).min(Vec3::ONE), Vec3::ZERO)
    }
}
