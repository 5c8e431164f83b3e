//! The BSDF at one surface point: a small fixed array of [`Lobe`]s resolved from the material at the hit
//! (`material::bsdf`), built per hit and returned by value. Every integrator goes through it: evaluation and pdf
//! of the smooth lobes, sampling of every lobe, the delta branches for Whitted recursion, and the ambient
//! reflectance of the Phong model.
//!
//! - A lobe is chosen with probability proportional to its [`Lobe::selection_weight`] (about its albedo). The
//!   smooth lobes form one mixture whose `pdf` is what multiple importance sampling compares with light sampling;
//!   delta lobes have no pdf and their samples are flagged `delta`.
//! - Directions are world space; `wo` points towards the viewer (or, for particles, where the particle came
//!   from). The shading frame faces `wo`: two-sided materials are seen from both sides, one-sided ones lose their
//!   reflection lobes from behind (`material::bsdf`).
//! - A reflection (transmission) is only returned towards the side of the geometric normal where `wo` (not) lies,
//!   whatever the shading normal says.
//! - [`TransportMode`]: with `Radiance` (camera paths) refraction scales radiance by `1/eta^2`; with `Importance`
//!   (photons, light paths) it does not, and every value is multiplied by Veach's shading-normal correction
//!   `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)` (the adjoint BSDF, so that the usual `f |wi.ns| / pdf` throughput is
//!   right for particles; thesis section 5.3). `eval`, `pdf` and `sample` are the radiance versions.
//! - Near-specular parts (`near_specular.rs`): estimators without multiple importance sampling count lobes too
//!   narrow for light sampling by BSDF sampling alone.

pub mod fresnel;
pub mod layered;
mod lobe;
pub mod microfacet;
mod near_specular;
mod rough_dielectric;
pub mod rough_interface;

pub use lobe::{ConductorFresnel, Lobe, LobeSample};
pub use near_specular::{BsdfPart, NEAR_SPECULAR_ALPHA};

use crate::math::Frame;
use crate::sampling::DirectionPoint;
use glam::{Vec2, Vec3, Vec3A};

/// Most lobes one BSDF holds (checked when a material is loaded).
pub const MAX_LOBES: usize = 4;

/// Which quantity a path carries (pbrt's and Mitsuba's `TransportMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TransportMode {
    /// Radiance along camera paths.
    #[default]
    Radiance,
    /// Importance (or photon power) along light paths: the adjoint BSDF.
    Importance,
}

/// A sampled direction and its throughput weight `f |cos| / pdf`.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// The sampled direction, world space, unit length, pointing away from the surface.
    pub wi: Vec3A,
    /// Throughput `f |cos| / pdf` per RGB channel (lobe selection included; for delta samples the lobe's weight
    /// over its selection probability).
    pub weight: Vec3,
    /// Mixture pdf of the smooth lobes in solid angle (0 for delta samples).
    pub pdf: f32,
    /// True when a delta lobe produced the sample: `pdf` is 0 and multiple importance sampling does not apply.
    pub delta: bool,
    /// The relative index of refraction crossed (transmitted side over `wo`'s) when the sample refracted through
    /// a dielectric, 1 otherwise: radiance weights carry `1/eta^2`, which Russian roulette undoes (as Mitsuba's
    /// path tracer does) so a path inside glass is not killed for a factor that cancels on the way out.
    pub eta: f32,
}

/// One branch of a delta lobe for Whitted recursion: direction, throughput, and the lobe's colour (`filter`,
/// for the 6.837 `-weight` rule).
#[derive(Clone, Copy, Debug)]
pub struct DeltaBranch {
    /// The branch's direction, world space, unit length.
    pub wi: Vec3A,
    /// Throughput along it per RGB channel (Fresnel and `1/eta^2` included).
    pub weight: Vec3,
    /// The lobe's colour (reflectance or transmittance filter), without Fresnel.
    pub filter: Vec3,
}

/// The scattering function at one shading point: up to [`MAX_LOBES`] lobes in a shading frame facing `wo`, their
/// selection probabilities, and the Phong model's ambient reflectance.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    /// Shading frame, normal facing `wo` (possibly perturbed by a normal or bump map).
    frame: Frame,
    /// Geometric normal facing `wo`.
    ng: Vec3A,
    wo: Vec3A,
    /// `wo` in the shading frame.
    wo_local: Vec3A,
    lobes: [Lobe; MAX_LOBES],
    /// Cumulative lobe selection probabilities.
    cdf: [f32; MAX_LOBES],
    len: usize,
    smooth: bool,
    ambient: Vec3,
}

impl Bsdf {
    /// An empty BSDF (no lobes yet) seen from `wo`, with shading frame `frame` and geometric normal `ng`, both
    /// facing `wo`. Add lobes with [`Bsdf::push`], then call [`Bsdf::finish`].
    #[inline(always)]
    pub fn new(frame: Frame, ng: Vec3A, wo: Vec3A) -> Self {
        Bsdf {
            frame,
            ng,
            wo,
            wo_local: frame.to_local(wo),
            lobes: [Lobe::Diffuse { albedo: Vec3::ZERO }; MAX_LOBES],
            cdf: [0.0; MAX_LOBES],
            len: 0,
            smooth: false,
            ambient: Vec3::ZERO,
        }
    }

    /// Start over (no lobes, no ambient term) at another surface, keeping the storage: [`Bsdf::new`] in place.
    #[inline(always)]
    pub fn reset(&mut self, frame: Frame, ng: Vec3A, wo: Vec3A) {
        self.frame = frame;
        self.ng = ng;
        self.wo = wo;
        self.wo_local = frame.to_local(wo);
        self.len = 0;
        self.smooth = false;
        self.ambient = Vec3::ZERO;
    }

    /// Make the BSDF one Lambertian lobe of `albedo` (after [`Bsdf::reset`]): what `push` and `prepare` give for
    /// it, without the general lobe selection. False when it reflects nothing (and there is no ambient term).
    #[inline(always)]
    pub fn set_lambert(&mut self, albedo: Vec3) -> bool {
        if crate::math::luminance(albedo) > 0.0 {
            self.lobes[0] = Lobe::Diffuse { albedo };
            self.cdf[0] = 1.0;
            self.len = 1;
            self.smooth = true;
            return true;
        }
        self.len = 0;
        self.ambient != Vec3::ZERO
    }

    /// A BSDF of the given lobes at a surface with normal `n` (shading = geometric) seen from `wo` (for tests and
    /// tools; materials build theirs with [`Bsdf::new`] and [`Bsdf::push`]).
    pub fn from_lobes(n: Vec3A, wo: Vec3A, lobes: &[Lobe]) -> Option<Self> {
        let n = if wo.dot(n) < 0.0 { -n } else { n };
        let mut b = Bsdf::new(Frame::from_normal(n), n, wo);
        for l in lobes {
            b.push(*l);
        }
        b.finish()
    }

    /// Add a lobe (merged into an equal one when possible; ignored beyond [`MAX_LOBES`]).
    #[inline]
    pub fn push(&mut self, lobe: Lobe) {
        for l in &mut self.lobes[..self.len] {
            if l.merge(&lobe) {
                return;
            }
        }
        if self.len < MAX_LOBES {
            self.lobes[self.len] = lobe;
            self.len += 1;
        }
    }

    /// Add to the ambient reflectance (the Phong model's `ambient` times the scene's ambient radiance).
    #[inline]
    pub fn add_ambient(&mut self, a: Vec3) {
        self.ambient += a;
    }

    /// Compute the lobe selection probabilities. `None` when nothing is reflected or transmitted and there is no
    /// ambient term.
    #[inline(always)]
    pub fn finish(mut self) -> Option<Self> {
        if self.prepare() { Some(self) } else { None }
    }

    /// [`Bsdf::finish`] in place: false when the BSDF is empty.
    #[inline(always)]
    pub fn prepare(&mut self) -> bool {
        if self.len == 1 {
            // The common case: one lobe, chosen always.
            if self.lobes[0].selection_weight(self.wo_local) > 0.0 {
                self.cdf[0] = 1.0;
                self.smooth = !self.lobes[0].is_delta();
                return true;
            }
            self.len = 0;
            return self.ambient != Vec3::ZERO;
        }
        let mut total = 0.0;
        let mut kept = 0;
        for i in 0..self.len {
            let w = self.lobes[i].selection_weight(self.wo_local);
            if w > 0.0 {
                self.lobes[kept] = self.lobes[i];
                total += w;
                self.cdf[kept] = total;
                kept += 1;
            }
        }
        self.len = kept;
        if kept == 0 {
            return self.ambient != Vec3::ZERO;
        }
        for c in &mut self.cdf[..kept] {
            *c /= total;
        }
        self.cdf[kept - 1] = 1.0;
        self.smooth = self.lobes[..kept].iter().any(|l| !l.is_delta());
        true
    }

    /// True when [`Bsdf::sample`] reads its lobe number `u_lobe`: several lobes to choose from, or one that splits
    /// by it (reflection or refraction of a dielectric, coat or base of plastic). Estimators may skip drawing it
    /// otherwise.
    #[inline]
    pub fn uses_lobe_number(&self) -> bool {
        self.len > 1
            || (self.len == 1
                && matches!(
                    self.lobes[0],
                    Lobe::Dielectric { .. }
                        | Lobe::RoughDielectric { .. }
                        | Lobe::Plastic { .. }
                        | Lobe::Layered { .. }
                        | Lobe::DiffuseTransmission { .. }
                        | Lobe::ThinDielectric { .. }
                ))
    }

    /// Shading normal facing `wo`.
    #[inline]
    pub fn normal(&self) -> Vec3A {
        self.frame.n
    }

    /// Geometric normal facing `wo`.
    #[inline]
    pub fn geometric_normal(&self) -> Vec3A {
        self.ng
    }

    /// The lobes (selection order).
    #[inline]
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes[..self.len]
    }

    /// Reflectance for the scene's ambient radiance (Phong model; 0 for physically based materials).
    #[inline]
    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// True when the BSDF has a smooth (non-delta) lobe that light sampling can illuminate.
    #[inline]
    pub fn has_smooth(&self) -> bool {
        self.smooth
    }

    /// True when a lobe scatters diffusely: a Lambertian lobe, a plastic's diffuse substrate, or a layered lobe
    /// with a diffuse base or a scattering medium. A BSDF with smooth lobes but none of these is glossy (rough
    /// conductors and dielectrics, lone Phong lobes), whose reflection of its surroundings a density estimate on the
    /// surface would blur (see `ppm`'s eye pass).
    #[inline]
    pub fn has_diffuse(&self) -> bool {
        self.lobes().iter().any(|l| match l {
            Lobe::Diffuse { .. } | Lobe::Plastic { .. } | Lobe::DiffuseTransmission { .. } => true,
            Lobe::Layered { spec, albedo, .. } => {
                spec.base == layered::LayerBase::Diffuse || albedo.max_element() > 0.0
            }
            _ => false,
        })
    }

    /// True when a lobe transmits diffusely (a diffuse transmitter): light arriving on either side scatters to
    /// both, so a density estimate counts particles that arrived on the other side.
    #[inline]
    pub fn transmits_diffusely(&self) -> bool {
        self.lobes().iter().any(|l| matches!(l, Lobe::DiffuseTransmission { .. }))
    }

    /// True when the BSDF has a delta lobe (mirror, smooth dielectric or conductor).
    #[inline]
    pub fn has_delta(&self) -> bool {
        self.lobes().iter().any(Lobe::is_delta)
    }

    /// Probability that `sample` returns a smooth (non-delta) direction: 1 for purely smooth materials, 0 for
    /// purely specular ones (a layered lobe with a smooth coat counts its mirror reflection as delta).
    #[inline]
    pub fn smooth_probability(&self) -> f32 {
        (0..self.len).map(|i| self.lobe_probability(i) * (1.0 - self.lobes[i].delta_probability(self.wo_local))).sum()
    }

    /// True when `sample(u_lobe, ..)` returns a delta direction (the choice depends on `u_lobe` only).
    #[inline]
    pub fn picks_delta(&self, u_lobe: f32) -> bool {
        if self.len == 0 {
            return false;
        }
        let (i, uc) = self.pick(u_lobe);
        self.lobes[i].is_delta() || uc < self.lobes[i].delta_probability(self.wo_local)
    }

    /// The lobe `sample(u_lobe, ..)` draws from, and the number within it (`len > 0`).
    #[inline]
    fn pick(&self, u_lobe: f32) -> (usize, f32) {
        let i = self.cdf[..self.len].iter().position(|&c| u_lobe < c).unwrap_or(self.len - 1);
        let p = self.lobe_probability(i);
        let lo = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        (i, if p > 0.0 { ((u_lobe - lo) / p).clamp(0.0, 0.99999994) } else { 0.5 })
    }

    /// Probability of choosing lobe `i`.
    #[inline]
    fn lobe_probability(&self, i: usize) -> f32 {
        self.cdf[i] - if i == 0 { 0.0 } else { self.cdf[i - 1] }
    }

    /// True when a local direction and its world direction agree about the side of the surface.
    #[inline]
    fn consistent(&self, wi: Vec3A, wi_local: Vec3A) -> bool {
        (wi_local.z > 0.0) == (wi.dot(self.ng) > 0.0) && wi_local.z != 0.0
    }

    /// Veach's shading-normal correction for importance transport (1 for radiance).
    #[inline]
    fn correction(&self, wi: Vec3A, mode: TransportMode) -> f32 {
        if mode == TransportMode::Radiance {
            return 1.0;
        }
        let num = self.wo_local.z.abs() * wi.dot(self.ng).abs();
        let den = self.wo.dot(self.ng).abs() * self.frame.to_local(wi).z.abs();
        if den > 0.0 { num / den } else { 0.0 }
    }

    /// The smooth part of the BSDF, `f(wo, wi)` (radiance); 0 where it does not scatter towards `wi`.
    #[inline]
    pub fn eval(&self, wi: Vec3A) -> Vec3 {
        self.eval_mode(wi, TransportMode::Radiance)
    }

    /// `f(wo, wi)` for the given transport mode (see the module doc).
    #[inline]
    pub fn eval_mode(&self, wi: Vec3A, mode: TransportMode) -> Vec3 {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return Vec3::ZERO;
        }
        self.eval_local(wl, mode) * self.correction(wi, mode)
    }

    #[inline]
    fn eval_local(&self, wl: Vec3A, mode: TransportMode) -> Vec3 {
        if self.len == 1 {
            return self.lobes[0].eval(self.wo_local, wl, mode);
        }
        let mut f = Vec3::ZERO;
        for l in self.lobes() {
            f += l.eval(self.wo_local, wl, mode);
        }
        f
    }

    /// `eval` and `pdf` of one direction together (one change of frame): what next-event estimation with MIS needs.
    /// A lone Lambertian lobe is evaluated inline in the caller (next-event estimation), every other BSDF out of
    /// line.
    #[inline(always)]
    pub fn eval_pdf(&self, wi: Vec3A) -> (Vec3, f32) {
        if self.len == 1
            && self.smooth
            && let Lobe::Diffuse { .. } = self.lobes[0]
        {
            let wl = self.frame.to_local(wi);
            if !self.consistent(wi, wl) {
                return (Vec3::ZERO, 0.0);
            }
            return self.lobes[0].eval_pdf(self.wo_local, wl, TransportMode::Radiance);
        }
        self.eval_pdf_general(wi)
    }

    /// [`Bsdf::eval_pdf`] for every BSDF but a lone Lambertian lobe.
    #[inline(never)]
    fn eval_pdf_general(&self, wi: Vec3A) -> (Vec3, f32) {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return (Vec3::ZERO, 0.0);
        }
        self.eval_pdf_local(wl, TransportMode::Radiance)
    }

    /// `eval_local` and `pdf_local` together (a lone lobe shares their common factors: [`Lobe::eval_pdf`]).
    #[inline]
    fn eval_pdf_local(&self, wl: Vec3A, mode: TransportMode) -> (Vec3, f32) {
        if self.len == 1 {
            return self.lobes[0].eval_pdf(self.wo_local, wl, mode);
        }
        (self.eval_local(wl, mode), self.pdf_local(wl))
    }

    /// Mixture pdf (solid angle) with which `sample` produces `wi` through a smooth lobe.
    #[inline]
    pub fn pdf(&self, wi: Vec3A) -> f32 {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return 0.0;
        }
        self.pdf_local(wl)
    }

    #[inline]
    fn pdf_local(&self, wl: Vec3A) -> f32 {
        if self.len == 1 {
            return self.lobes[0].pdf(self.wo_local, wl);
        }
        let mut pdf = 0.0;
        for (i, l) in self.lobes().iter().enumerate() {
            if !l.is_delta() {
                pdf += self.lobe_probability(i) * l.pdf(self.wo_local, wl);
            }
        }
        pdf
    }

    /// The reverse density: with which a BSDF at this point seen from `wi` would sample `wo` through a smooth lobe
    /// (solid angle), its lobes chosen by their weights seen from `wi`. Bidirectional methods need it for the MIS
    /// weights of the strategies that would have built a path the other way. A refraction seen from the other side
    /// crosses the inverse index of refraction. 0 for delta lobes and where the BSDF does not scatter `wi` to `wo`.
    pub fn pdf_rev(&self, wi: Vec3A) -> f32 {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return 0.0;
        }
        self.pdf_rev_local(wl)
    }

    /// `f(wo, wi)` for `mode`, the forward density [`Bsdf::pdf`] and the reverse density [`Bsdf::pdf_rev`] of one
    /// direction together (one change of frame, a lone lobe's common factors shared as in [`Bsdf::eval_pdf`]): what
    /// a bidirectional connection or merge needs.
    #[inline]
    pub fn eval_pdfs(&self, wi: Vec3A, mode: TransportMode) -> (Vec3, f32, f32) {
        let wl = self.frame.to_local(wi);
        if !self.smooth || !self.consistent(wi, wl) {
            return (Vec3::ZERO, 0.0, 0.0);
        }
        let (f, pdf) = self.eval_pdf_local(wl, mode);
        (f * self.correction(wi, mode), pdf, self.pdf_rev_local(wl))
    }

    /// [`Bsdf::pdf_rev`] of a consistent local direction.
    #[inline]
    fn pdf_rev_local(&self, wl: Vec3A) -> f32 {
        // The reverse BSDF's frame faces `wi`: from below, both directions are mirrored through the surface.
        let below = wl.z < 0.0;
        let side = |v: Vec3A| if below { Vec3A::new(v.x, v.y, -v.z) } else { v };
        let (from, to) = (side(wl), side(self.wo_local));
        if self.len == 1 && !matches!(self.lobes[0], Lobe::Dielectric { .. } | Lobe::RoughDielectric { .. }) {
            // A lone lobe is chosen with probability 1 whenever it can be chosen at all.
            let l = &self.lobes[0];
            let pdf = if l.is_delta() || l.selection_weight(from) <= 0.0 { 0.0 } else { l.pdf(from, to) };
            return if pdf.is_finite() { pdf } else { 0.0 };
        }
        let (mut total, mut pdf) = (0.0f32, 0.0f32);
        for l in self.lobes() {
            let l = match *l {
                Lobe::RoughDielectric { alpha, r, t, eta } if below => {
                    Lobe::RoughDielectric { alpha, r, t, eta: 1.0 / eta }
                }
                Lobe::Dielectric { r, t, eta } if below => Lobe::Dielectric { r, t, eta: 1.0 / eta },
                other => other,
            };
            let w = l.selection_weight(from);
            total += w;
            if w > 0.0 && !l.is_delta() {
                pdf += w * l.pdf(from, to);
            }
        }
        if total > 0.0 && pdf.is_finite() { pdf / total } else { 0.0 }
    }

    /// Sample a direction (radiance): `u_lobe` picks the lobe (and is reused within it), `u` the direction.
    ///
    /// A lone Lambertian lobe is sampled inline in the caller (the path loop); every other BSDF through the general
    /// code, kept out of line.
    #[inline(always)]
    pub fn sample(&self, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.sample_mode(u_lobe, u, TransportMode::Radiance)
    }

    /// [`Bsdf::sample`] with the direction's point as the sampler gave it: a lone Lambertian lobe takes its
    /// cosine-weighted direction from it, computed ahead where it was (the same direction either way).
    #[inline(always)]
    pub fn sample_point(&self, u_lobe: f32, p: DirectionPoint) -> Option<BsdfSample> {
        if self.len == 1
            && let Lobe::Diffuse { albedo } = self.lobes[0]
        {
            return self.sample_lambert_from(albedo, p.cosine_hemisphere(), TransportMode::Radiance);
        }
        self.sample_general(u_lobe, p.u, TransportMode::Radiance)
    }

    /// The common case, a lone Lambertian lobe of `albedo`: cosine sampling, weight = albedo exactly.
    #[inline(always)]
    fn sample_lambert(&self, albedo: Vec3, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        self.sample_lambert_from(albedo, crate::sampling::warp::cosine_hemisphere(u), mode)
    }

    /// [`Bsdf::sample_lambert`] with the local direction `wl = cosine_hemisphere(u)` given.
    #[inline(always)]
    fn sample_lambert_from(&self, albedo: Vec3, wl: Vec3A, mode: TransportMode) -> Option<BsdfSample> {
        if self.wo_local.z <= 0.0 {
            return None;
        }
        let wi = self.frame.to_world(wl);
        if !self.consistent(wi, wl) {
            return None;
        }
        let pdf = crate::sampling::warp::cosine_hemisphere_pdf(wl);
        if pdf <= 0.0 {
            return None;
        }
        let weight = albedo * self.correction(wi, mode);
        Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 })
    }

    /// Sample a direction for the given transport mode.
    #[inline(always)]
    pub fn sample_mode(&self, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if self.len == 1
            && let Lobe::Diffuse { albedo } = self.lobes[0]
        {
            return self.sample_lambert(albedo, u, mode);
        }
        self.sample_general(u_lobe, u, mode)
    }

    /// [`Bsdf::sample_mode`] for every BSDF but a lone Lambertian lobe.
    #[inline(never)]
    fn sample_general(&self, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if self.len == 0 {
            return None;
        }
        let (i, uc) = self.pick(u_lobe);
        let p = self.lobe_probability(i);
        let lobe = &self.lobes[i];
        let s = lobe.sample(self.wo_local, uc, u, mode)?;
        let wi = self.frame.to_world(s.wi);
        if !self.consistent(wi, s.wi) {
            return None;
        }
        if s.delta {
            let weight = s.weight * (self.correction(wi, mode) / p);
            let eta = if s.wi.z * self.wo_local.z < 0.0 { lobe.radiance_eta() } else { 1.0 };
            return Some(BsdfSample { wi, weight, pdf: 0.0, delta: true, eta });
        }
        if s.weighted || (self.len > 1 && self.lobes().iter().any(|l| matches!(l, Lobe::Layered { .. }))) {
            // A layered walk's value and density at `wi` are estimates, not what drew it: the walk's own
            // throughput is the estimate, one lobe at a time (no mixture); the mixture's estimated density is
            // for multiple importance sampling only.
            let weight = if s.weighted {
                s.weight
            } else {
                let (f, pdf) = lobe.eval_pdf(self.wo_local, s.wi, mode);
                if pdf <= 0.0 || !pdf.is_finite() {
                    return None;
                }
                f * (s.wi.z.abs() / pdf)
            };
            let weight = weight * (self.correction(wi, mode) / p);
            let pdf = self.pdf_local(s.wi);
            if pdf <= 0.0 || !pdf.is_finite() || !weight.is_finite() {
                return None;
            }
            return Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 });
        }
        let (f, pdf) = self.eval_pdf_local(s.wi, mode);
        if pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        let weight = f * (s.wi.z.abs() * self.correction(wi, mode) / pdf);
        if !weight.is_finite() {
            return None;
        }
        let eta = if s.wi.z * self.wo_local.z < 0.0 { lobe.radiance_eta() } else { 1.0 };
        Some(BsdfSample { wi, weight, pdf, delta: false, eta })
    }

    /// Every branch of the delta lobes, in lobe order (radiance): mirror reflection, Fresnel reflection and
    /// refraction of smooth dielectrics (`1/eta^2` included), the course's refraction, smooth conductors. Whitted
    /// ray tracing follows each one deterministically.
    pub fn delta_branches(&self, mut f: impl FnMut(DeltaBranch)) {
        for l in self.lobes() {
            if !l.is_delta() {
                continue;
            }
            l.delta_branches(self.wo_local, |wl, weight, filter| {
                let wi = self.frame.to_world(wl).normalize();
                if self.consistent(wi, wl) {
                    f(DeltaBranch { wi, weight, filter });
                }
            });
        }
    }
}
