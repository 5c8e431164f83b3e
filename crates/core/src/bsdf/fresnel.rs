//! Fresnel reflectance beyond the smooth dielectric of `math::optics`: conductors with a complex index of
//! refraction per RGB channel (exact, unpolarised), Schlick's approximation from a normal-incidence colour, and the
//! diffuse (hemispherically averaged) Fresnel reflectance used by the plastic coat.

use crate::math::fresnel_dielectric;
use glam::Vec3;

/// Exact unpolarised Fresnel reflectance of a conductor with index `eta + i k` (outside index 1) for the incident
/// cosine `cos_i`, one channel (the real form of K. D. Moeller, "Optics", 1988, as in Mitsuba and pbrt).
#[inline]
pub fn fresnel_conductor1(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let (eta2, k2) = (eta * eta, k * k);
    let t0 = eta2 - k2 - s2;
    let a2b2 = (t0 * t0 + 4.0 * eta2 * k2).max(0.0).sqrt();
    let t1 = a2b2 + c2;
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    let f = 0.5 * (rp + rs);
    if f.is_finite() { f.clamp(0.0, 1.0) } else { 1.0 }
}

/// [`fresnel_conductor1`] per RGB channel.
#[inline]
pub fn fresnel_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    Vec3::new(
        fresnel_conductor1(cos_i, eta.x, k.x),
        fresnel_conductor1(cos_i, eta.y, k.y),
        fresnel_conductor1(cos_i, eta.z, k.z),
    )
}

/// Schlick's approximation `r0 + (1 - r0)(1 - cos)^5` from the reflectance at normal incidence.
#[inline]
pub fn fresnel_schlick(cos_i: f32, r0: Vec3) -> Vec3 {
    let m = (1.0 - cos_i.clamp(0.0, 1.0)).powi(5);
    r0 + (Vec3::ONE - r0) * m
}

/// Diffuse Fresnel reflectance `2 int_0^1 F(c, eta) c dc`: the fraction of uniformly diffuse light reflected by a
/// smooth interface of relative index `eta` (midpoint rule, 4096 steps; computed once per material).
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let n = 4096;
    let mut sum = 0.0f64;
    for i in 0..n {
        let c = (i as f64 + 0.5) / n as f64;
        sum += fresnel_dielectric(c as f32, eta) as f64 * c;
    }
    (2.0 * sum / n as f64) as f32
}
