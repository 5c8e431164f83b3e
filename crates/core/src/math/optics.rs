//! Geometric optics: mirror reflection, Snell refraction and the exact unpolarised Fresnel reflectance of a
//! smooth dielectric interface.

use glam::Vec3A;

/// Mirror `wo` about the unit normal `n` (both pointing away from the surface).
#[inline]
pub fn reflect(wo: Vec3A, n: Vec3A) -> Vec3A {
    2.0 * wo.dot(n) * n - wo
}

/// Refract `wo` (pointing away from the surface, on the side of `n`) through an interface with relative index
/// `eta` = eta_transmitted / eta_incident. Returns `None` on total internal reflection.
#[inline]
pub fn refract(wo: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = wo.dot(n);
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wo / eta + (cos_i / eta - cos_t) * n)
}

/// Exact Fresnel reflectance of a smooth dielectric for unpolarised light. `cos_i` is the cosine of the incident
/// angle on the side the light comes from (>= 0), `eta` = eta_transmitted / eta_incident. 1 on total internal
/// reflection.
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}
