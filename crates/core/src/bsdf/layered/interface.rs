//! The interfaces of a layered BSDF, exactly as pbrt-v4 defines them (`src/pbrt/bxdfs.h`, `bxdfs.cpp`,
//! `util/scattering.h`), so that a pbrt-v4 `coateddiffuse` or `coatedconductor` file renders as pbrt renders it:
//!
//! - the Trowbridge–Reitz (GGX) distribution with pbrt's height-correlated Smith term
//!   `G = 1 / (1 + Lambda(wo) + Lambda(wi))` and its visible-normal sampler (which, unlike the surface lobes' in
//!   `microfacet.rs`, accepts directions from below: the walk meets the coat from inside);
//! - `DielectricBxDF` (smooth when `alpha < 1e-3`, rough otherwise; Fresnel and refraction seen from either side),
//!   `DiffuseBxDF` and `ConductorBxDF` (complex Fresnel), each with pbrt's reflection/transmission sampling flags.
//!
//! Directions are local (z = the layer's normal), `wo` and `wi` both point away from the interface. Values are
//! RGB; `mode` is the transport mode (refraction scales radiance by `1 / eta'^2`).

use crate::bsdf::TransportMode;
use crate::bsdf::fresnel::fresnel_conductor;
use crate::math::fresnel_dielectric;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::{FRAC_1_PI, PI};

/// Which parts of an interface a sample may come from (pbrt's `BxDFReflTransFlags`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Parts {
    All,
    Reflection,
    Transmission,
}

impl Parts {
    fn reflection(self) -> bool {
        self != Parts::Transmission
    }
    fn transmission(self) -> bool {
        self != Parts::Reflection
    }
}

/// A direction drawn from an interface (pbrt's `BSDFSample`).
#[derive(Clone, Copy, Debug)]
pub(super) struct InterfaceSample {
    /// The value `f(wo, wi)` (for specular samples, the delta's weight over `|wi.z|`).
    pub f: Vec3,
    pub wi: Vec3A,
    /// Density (for specular samples, the discrete probability of the branch).
    pub pdf: f32,
    pub specular: bool,
}

impl InterfaceSample {
    pub fn is_transmission(&self, wo: Vec3A) -> bool {
        wo.z * self.wi.z < 0.0
    }
    /// pbrt's test that a sample is usable: a value, a density and a direction off the plane.
    pub fn usable(&self) -> bool {
        self.f.max_element() > 0.0 && self.pdf > 0.0 && self.wi.z != 0.0
    }
}

/// One interface of a layered BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Interface {
    /// pbrt's `DielectricBxDF`: relative index `eta` (below over above), GGX width `alpha`.
    Dielectric { eta: f32, alpha: f32 },
    /// pbrt's `DiffuseBxDF` of reflectance `r`.
    Diffuse { r: Vec3 },
    /// pbrt's `ConductorBxDF`: index `eta + i k` relative to the medium above, GGX width `alpha`.
    Conductor { alpha: f32, eta: Vec3, k: Vec3 },
}

/// pbrt's `EffectivelySmooth`.
#[inline]
fn smooth(alpha: f32) -> bool {
    alpha < 1e-3
}

#[inline]
fn tan2(w: Vec3A) -> f32 {
    (w.x * w.x + w.y * w.y) / (w.z * w.z)
}

/// Trowbridge–Reitz `D(wm)`.
fn tr_d(wm: Vec3A, alpha: f32) -> f32 {
    let t2 = tan2(wm);
    if t2.is_infinite() || t2.is_nan() {
        return 0.0;
    }
    let cos4 = (wm.z * wm.z) * (wm.z * wm.z);
    if cos4 < 1e-16 {
        return 0.0;
    }
    let e = t2 / (alpha * alpha);
    1.0 / (PI * alpha * alpha * cos4 * (1.0 + e) * (1.0 + e))
}

fn tr_lambda(w: Vec3A, alpha: f32) -> f32 {
    let t2 = tan2(w);
    if t2.is_infinite() || t2.is_nan() {
        return 0.0;
    }
    ((1.0 + alpha * alpha * t2).sqrt() - 1.0) / 2.0
}

fn tr_g1(w: Vec3A, alpha: f32) -> f32 {
    1.0 / (1.0 + tr_lambda(w, alpha))
}

fn tr_g(wo: Vec3A, wi: Vec3A, alpha: f32) -> f32 {
    1.0 / (1.0 + tr_lambda(wo, alpha) + tr_lambda(wi, alpha))
}

/// Density of visible normals `wm` seen from `w` (either side).
fn tr_pdf(w: Vec3A, wm: Vec3A, alpha: f32) -> f32 {
    tr_g1(w, alpha) / w.z.abs() * tr_d(wm, alpha) * w.dot(wm).abs()
}

/// pbrt's `Sample_wm`: a visible normal (upper hemisphere) seen from `w` on either side.
fn tr_sample_wm(w: Vec3A, alpha: f32, u: Vec2) -> Vec3A {
    let mut wh = Vec3A::new(alpha * w.x, alpha * w.y, w.z).normalize();
    if wh.z < 0.0 {
        wh = -wh;
    }
    let t1 = if wh.z < 0.99999 { Vec3A::Z.cross(wh).normalize() } else { Vec3A::X };
    let t2 = wh.cross(t1);
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let (px, mut py) = (r * phi.cos(), r * phi.sin());
    let h = (1.0 - px * px).max(0.0).sqrt();
    let s = (1.0 + wh.z) / 2.0;
    py = (1.0 - s) * h + s * py;
    let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
    let nh = px * t1 + py * t2 + pz * wh;
    Vec3A::new(alpha * nh.x, alpha * nh.y, nh.z.max(1e-6)).normalize()
}

/// pbrt's `FrDielectric`: a negative cosine is light arriving from below (the index is inverted).
pub(super) fn fr_dielectric(cos_i: f32, eta: f32) -> f32 {
    if cos_i < 0.0 { fresnel_dielectric(-cos_i, 1.0 / eta) } else { fresnel_dielectric(cos_i, eta) }
}

/// pbrt's `Refract`: `wi` refracted through the interface of normal `n` (either side), with the relative index
/// along the ray.
fn refract(wi: Vec3A, n: Vec3A, eta: f32) -> Option<(Vec3A, f32)> {
    let (mut n, mut eta) = (n, eta);
    let mut c = n.dot(wi);
    if c < 0.0 {
        eta = 1.0 / eta;
        c = -c;
        n = -n;
    }
    let sin2_t = (1.0 - c * c).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wi / eta + (c / eta - cos_t) * n, eta))
}

#[inline]
fn reflect(w: Vec3A, n: Vec3A) -> Vec3A {
    -w + 2.0 * w.dot(n) * n
}

impl Interface {
    /// True when the interface only scatters into discrete directions.
    pub fn is_specular(&self) -> bool {
        match *self {
            Interface::Dielectric { eta, alpha } => eta == 1.0 || smooth(alpha),
            Interface::Diffuse { .. } => false,
            Interface::Conductor { alpha, .. } => smooth(alpha),
        }
    }

    /// `f(wo, wi)` (0 for specular interfaces).
    pub fn f(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> Vec3 {
        match *self {
            Interface::Diffuse { r } => {
                if wo.z * wi.z > 0.0 {
                    r * FRAC_1_PI
                } else {
                    Vec3::ZERO
                }
            }
            Interface::Conductor { alpha, eta, k } => {
                if wo.z * wi.z <= 0.0 || smooth(alpha) {
                    return Vec3::ZERO;
                }
                let (co, ci) = (wo.z.abs(), wi.z.abs());
                let wm = wi + wo;
                if co == 0.0 || ci == 0.0 || wm.length_squared() == 0.0 {
                    return Vec3::ZERO;
                }
                let wm = wm.normalize();
                let f = fresnel_conductor(wo.dot(wm).abs(), eta, k);
                f * (tr_d(wm, alpha) * tr_g(wo, wi, alpha) / (4.0 * ci * co))
            }
            Interface::Dielectric { eta, alpha } => Vec3::splat(dielectric_f(eta, alpha, wo, wi, mode)),
        }
    }

    /// The density with which [`Interface::sample`] draws `wi` from `wo` with `parts` (0 for specular ones).
    pub fn pdf(&self, wo: Vec3A, wi: Vec3A, parts: Parts) -> f32 {
        match *self {
            Interface::Diffuse { .. } => {
                if !parts.reflection() || wo.z * wi.z <= 0.0 {
                    0.0
                } else {
                    warp::cosine_hemisphere_pdf(Vec3A::new(wi.x, wi.y, wi.z.abs()))
                }
            }
            Interface::Conductor { alpha, .. } => {
                if !parts.reflection() || wo.z * wi.z <= 0.0 || smooth(alpha) {
                    return 0.0;
                }
                let wm = wo + wi;
                if wm.length_squared() == 0.0 {
                    return 0.0;
                }
                let mut wm = wm.normalize();
                if wm.z < 0.0 {
                    wm = -wm;
                }
                tr_pdf(wo, wm, alpha) / (4.0 * wo.dot(wm).abs())
            }
            Interface::Dielectric { eta, alpha } => dielectric_pdf(eta, alpha, wo, wi, parts),
        }
    }

    /// Draw `wi` from `wo`: `uc` chooses reflection or transmission, `u` the direction.
    pub fn sample(&self, wo: Vec3A, uc: f32, u: Vec2, mode: TransportMode, parts: Parts) -> Option<InterfaceSample> {
        match *self {
            Interface::Diffuse { r } => {
                if !parts.reflection() {
                    return None;
                }
                let mut wi = warp::cosine_hemisphere(u);
                if wo.z < 0.0 {
                    wi.z = -wi.z;
                }
                let pdf = warp::cosine_hemisphere_pdf(Vec3A::new(wi.x, wi.y, wi.z.abs()));
                Some(InterfaceSample { f: r * FRAC_1_PI, wi, pdf, specular: false })
            }
            Interface::Conductor { alpha, eta, k } => {
                if !parts.reflection() {
                    return None;
                }
                if smooth(alpha) {
                    let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
                    let f = fresnel_conductor(wi.z.abs(), eta, k) / wi.z.abs();
                    return Some(InterfaceSample { f, wi, pdf: 1.0, specular: true });
                }
                if wo.z == 0.0 {
                    return None;
                }
                let wm = tr_sample_wm(wo, alpha, u);
                let wi = reflect(wo, wm);
                if wo.z * wi.z <= 0.0 {
                    return None;
                }
                let pdf = tr_pdf(wo, wm, alpha) / (4.0 * wo.dot(wm).abs());
                let (co, ci) = (wo.z.abs(), wi.z.abs());
                if co == 0.0 || ci == 0.0 {
                    return None;
                }
                let f = fresnel_conductor(wo.dot(wm).abs(), eta, k)
                    * (tr_d(wm, alpha) * tr_g(wo, wi, alpha) / (4.0 * ci * co));
                Some(InterfaceSample { f, wi, pdf, specular: false })
            }
            Interface::Dielectric { eta, alpha } => dielectric_sample(eta, alpha, wo, uc, u, mode, parts),
        }
    }
}

fn dielectric_sample(
    eta: f32,
    alpha: f32,
    wo: Vec3A,
    uc: f32,
    u: Vec2,
    mode: TransportMode,
    parts: Parts,
) -> Option<InterfaceSample> {
    let choose = |r: f32| {
        let t = 1.0 - r;
        let pr = if parts.reflection() { r } else { 0.0 };
        let pt = if parts.transmission() { t } else { 0.0 };
        (pr, pt, t)
    };
    if eta == 1.0 || smooth(alpha) {
        let r = fr_dielectric(wo.z, eta);
        let (pr, pt, t) = choose(r);
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        if uc < pr / (pr + pt) {
            let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
            return Some(InterfaceSample { f: Vec3::splat(r / wi.z.abs()), wi, pdf: pr / (pr + pt), specular: true });
        }
        let (wi, etap) = refract(wo, Vec3A::Z, eta)?;
        let mut ft = t / wi.z.abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        return Some(InterfaceSample { f: Vec3::splat(ft), wi, pdf: pt / (pr + pt), specular: true });
    }
    let wm = tr_sample_wm(wo, alpha, u);
    let r = fr_dielectric(wo.dot(wm), eta);
    let (pr, pt, t) = choose(r);
    if pr == 0.0 && pt == 0.0 {
        return None;
    }
    if uc < pr / (pr + pt) {
        let wi = reflect(wo, wm);
        if wo.z * wi.z <= 0.0 {
            return None;
        }
        let pdf = tr_pdf(wo, wm, alpha) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt);
        let f = tr_d(wm, alpha) * tr_g(wo, wi, alpha) * r / (4.0 * wi.z * wo.z);
        return Some(InterfaceSample { f: Vec3::splat(f), wi, pdf, specular: false });
    }
    let (wi, etap) = refract(wo, wm, eta)?;
    if wo.z * wi.z > 0.0 || wi.z == 0.0 {
        return None;
    }
    let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
    let dwm_dwi = wi.dot(wm).abs() / denom;
    let pdf = tr_pdf(wo, wm, alpha) * dwm_dwi * pt / (pr + pt);
    let mut ft = t * tr_d(wm, alpha) * tr_g(wo, wi, alpha) * (wi.dot(wm) * wo.dot(wm) / (wi.z * wo.z * denom)).abs();
    if mode == TransportMode::Radiance {
        ft /= etap * etap;
    }
    (pdf.is_finite() && ft.is_finite()).then_some(InterfaceSample { f: Vec3::splat(ft), wi, pdf, specular: false })
}

/// The generalized half vector of a rough dielectric pair, facing +z, with `eta'`; `None` where pbrt's value is 0.
fn dielectric_half(eta: f32, wo: Vec3A, wi: Vec3A) -> Option<(Vec3A, f32, bool)> {
    let (co, ci) = (wo.z, wi.z);
    let reflect = co * ci > 0.0;
    let etap = if reflect {
        1.0
    } else if co > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let wm = wi * etap + wo;
    if ci == 0.0 || co == 0.0 || wm.length_squared() == 0.0 {
        return None;
    }
    let mut wm = wm.normalize();
    if wm.z < 0.0 {
        wm = -wm;
    }
    // Back-facing microfacets.
    if wm.dot(wi) * ci < 0.0 || wm.dot(wo) * co < 0.0 {
        return None;
    }
    Some((wm, etap, reflect))
}

fn dielectric_f(eta: f32, alpha: f32, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> f32 {
    if eta == 1.0 || smooth(alpha) {
        return 0.0;
    }
    let Some((wm, etap, reflect)) = dielectric_half(eta, wo, wi) else { return 0.0 };
    let f = fr_dielectric(wo.dot(wm), eta);
    if reflect {
        return tr_d(wm, alpha) * tr_g(wo, wi, alpha) * f / (4.0 * wi.z * wo.z).abs();
    }
    let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * wi.z * wo.z;
    let mut ft = tr_d(wm, alpha) * (1.0 - f) * tr_g(wo, wi, alpha) * (wi.dot(wm) * wo.dot(wm) / denom).abs();
    if mode == TransportMode::Radiance {
        ft /= etap * etap;
    }
    if ft.is_finite() { ft } else { 0.0 }
}

fn dielectric_pdf(eta: f32, alpha: f32, wo: Vec3A, wi: Vec3A, parts: Parts) -> f32 {
    if eta == 1.0 || smooth(alpha) {
        return 0.0;
    }
    let Some((wm, etap, reflect)) = dielectric_half(eta, wo, wi) else { return 0.0 };
    let r = fr_dielectric(wo.dot(wm), eta);
    let t = 1.0 - r;
    let pr = if parts.reflection() { r } else { 0.0 };
    let pt = if parts.transmission() { t } else { 0.0 };
    if pr == 0.0 && pt == 0.0 {
        return 0.0;
    }
    let pdf = if reflect {
        tr_pdf(wo, wm, alpha) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt)
    } else {
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        tr_pdf(wo, wm, alpha) * (wi.dot(wm).abs() / denom) * pt / (pr + pt)
    };
    if pdf.is_finite() { pdf } else { 0.0 }
}

/// The Henyey–Greenstein phase function `p(cos)` (pbrt's convention: `cos` between `wo` and `wi`, both pointing
/// away from the scattering point; `g` clamped to `[-0.99, 0.99]`).
pub(super) fn henyey_greenstein(cos: f32, g: f32) -> f32 {
    let g = g.clamp(-0.99, 0.99);
    let denom = 1.0 + g * g + 2.0 * g * cos;
    (1.0 - g * g) / (4.0 * PI * denom * denom.max(0.0).sqrt())
}

/// pbrt's `SampleHenyeyGreenstein`: a direction `wi` for `wo` and its density.
pub(super) fn sample_henyey_greenstein(wo: Vec3A, g: f32, u: Vec2) -> (Vec3A, f32) {
    let g = g.clamp(-0.99, 0.99);
    let cos = if g.abs() < 1e-3 {
        1.0 - 2.0 * u.x
    } else {
        -1.0 / (2.0 * g) * (1.0 + g * g - ((1.0 - g * g) / (1.0 + g - 2.0 * g * u.x)).powi(2))
    };
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let frame = crate::math::Frame::from_normal(wo);
    let wi = frame.to_world(Vec3A::new(sin * phi.cos(), sin * phi.sin(), cos));
    (wi, henyey_greenstein(cos, g))
}
