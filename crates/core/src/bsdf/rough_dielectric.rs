//! The GGX rough dielectric's value and density (Walter et al. 2007, "Microfacet Models for Refraction through
//! Rough Surfaces"): reflection `F D G / (4 |wo.z wi.z|)` about the half vector, transmission
//! `(1 - F) D G |wo.m| |wi.m| / (|wo.z wi.z| (wo.m + eta wi.m)^2)` about the generalised half vector (times `eta^2`
//! for importance), sampled through the visible normals of `wo`. Used by [`super::Lobe::RoughDielectric`].

use super::TransportMode;
use super::microfacet::{ggx_d, ggx_g1, visible_pdf};
use crate::math::fresnel_dielectric;
use glam::{Vec3, Vec3A};

/// Half vector of a refraction pair, oriented to +z.
#[inline]
fn half_transmit(wo: Vec3A, wi: Vec3A, eta: f32) -> Option<Vec3A> {
    let m = (wo + eta * wi).normalize_or_zero();
    if m == Vec3A::ZERO {
        return None;
    }
    Some(if m.z < 0.0 { -m } else { m })
}

/// Refract `w` (on the side `m` points to) through the microsurface `m` with relative index `eta`.
#[inline]
pub(super) fn refract_about(w: Vec3A, m: Vec3A, eta: f32) -> Option<Vec3A> {
    crate::math::refract(w, m, eta).map(|t| t.normalize())
}

pub(super) fn rough_dielectric_eval(
    alpha: f32,
    r: Vec3,
    t: Vec3,
    eta: f32,
    wo: Vec3A,
    wi: Vec3A,
    mode: TransportMode,
) -> Vec3 {
    if wo.z == 0.0 || wi.z == 0.0 {
        return Vec3::ZERO;
    }
    if wo.z * wi.z > 0.0 {
        let mut m = (wo + wi).normalize();
        if m.z < 0.0 {
            m = -m;
        }
        let f = fresnel_dielectric(wo.dot(m).abs(), eta);
        let g = ggx_g1(wo, m, alpha) * ggx_g1(wi, m, alpha);
        return r * (f * ggx_d(m, alpha) * g / (4.0 * (wo.z * wi.z).abs()));
    }
    let Some(m) = half_transmit(wo, wi, eta) else { return Vec3::ZERO };
    let (om, im) = (wo.dot(m), wi.dot(m));
    let g = ggx_g1(wo, m, alpha) * ggx_g1(wi, m, alpha);
    if g == 0.0 {
        return Vec3::ZERO;
    }
    let f = fresnel_dielectric(om.abs(), eta);
    let denom = om + eta * im;
    let mut v = (1.0 - f) * ggx_d(m, alpha) * g * (om * im).abs() / ((wo.z * wi.z).abs() * denom * denom);
    if mode == TransportMode::Importance {
        v *= eta * eta;
    }
    if v.is_finite() { t * v } else { Vec3::ZERO }
}

pub(super) fn rough_dielectric_pdf(alpha: f32, eta: f32, wo: Vec3A, wi: Vec3A) -> f32 {
    if wo.z <= 0.0 || wi.z == 0.0 {
        return 0.0;
    }
    if wi.z > 0.0 {
        let m = (wo + wi).normalize();
        let f = fresnel_dielectric(wo.dot(m), eta);
        return f * visible_pdf(wo, m, alpha) / (4.0 * wo.dot(m).abs());
    }
    let Some(m) = half_transmit(wo, wi, eta) else { return 0.0 };
    let (om, im) = (wo.dot(m), wi.dot(m));
    if om <= 0.0 || im >= 0.0 {
        return 0.0;
    }
    let f = fresnel_dielectric(om, eta);
    let denom = om + eta * im;
    let p = (1.0 - f) * visible_pdf(wo, m, alpha) * eta * eta * im.abs() / (denom * denom);
    if p.is_finite() { p } else { 0.0 }
}

/// `(rough_dielectric_eval, rough_dielectric_pdf)` with the half vector, `D` and `G1(wo)` computed once: the same
/// operations in the same order as the two functions, so the same values bit for bit.
#[allow(clippy::too_many_arguments)]
pub(super) fn rough_dielectric_eval_pdf(
    alpha: f32,
    r: Vec3,
    t: Vec3,
    eta: f32,
    wo: Vec3A,
    wi: Vec3A,
    mode: TransportMode,
) -> (Vec3, f32) {
    if wo.z <= 0.0 || wi.z == 0.0 {
        // The pdf is 0 there (directions are only sampled from above).
        return (rough_dielectric_eval(alpha, r, t, eta, wo, wi, mode), 0.0);
    }
    if wi.z > 0.0 {
        // Reflection: both above, so the half vector is too (eval's flip to +z does nothing).
        let m = (wo + wi).normalize();
        let c = wo.dot(m);
        let f_eval = fresnel_dielectric(c.abs(), eta);
        let f_pdf = if c >= 0.0 { f_eval } else { fresnel_dielectric(c, eta) };
        let (g1o, d) = (ggx_g1(wo, m, alpha), ggx_d(m, alpha));
        let g = g1o * ggx_g1(wi, m, alpha);
        let value = r * (f_eval * d * g / (4.0 * (wo.z * wi.z).abs()));
        let pdf = f_pdf * (g1o * c.max(0.0) * d / wo.z) / (4.0 * c.abs());
        return (value, pdf);
    }
    let Some(m) = half_transmit(wo, wi, eta) else { return (Vec3::ZERO, 0.0) };
    let (om, im) = (wo.dot(m), wi.dot(m));
    let (g1o, d) = (ggx_g1(wo, m, alpha), ggx_d(m, alpha));
    let g = g1o * ggx_g1(wi, m, alpha);
    let f_eval = fresnel_dielectric(om.abs(), eta);
    let denom = om + eta * im;
    let value = if g == 0.0 {
        Vec3::ZERO
    } else {
        let mut v = (1.0 - f_eval) * d * g * (om * im).abs() / ((wo.z * wi.z).abs() * denom * denom);
        if mode == TransportMode::Importance {
            v *= eta * eta;
        }
        if v.is_finite() { t * v } else { Vec3::ZERO }
    };
    let pdf = if om <= 0.0 || im >= 0.0 {
        0.0
    } else {
        // om > 0: the same Fresnel term as the value's.
        let p = (1.0 - f_eval) * (g1o * om.max(0.0) * d / wo.z) * eta * eta * im.abs() / (denom * denom);
        if p.is_finite() { p } else { 0.0 }
    };
    (value, pdf)
}
