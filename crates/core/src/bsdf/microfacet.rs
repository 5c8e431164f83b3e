//! The GGX (Trowbridge–Reitz) microfacet distribution, isotropic, exactly as Mitsuba 3 evaluates it
//! (`../shared/refs/cornell_rough.md`), in the local shading frame (z = normal):
//!
//! - `D(m) = 1 / (pi a^2 ((m.x^2 + m.y^2) / a^2 + m.z^2)^2)`, normalised so that `int D(m) m.z dm = 1`; `a` (alpha)
//!   is the GGX width, used unmodified (not a "perceptual roughness");
//! - separable Smith shadowing-masking `G(wi, wo, m) = G1(wi, m) G1(wo, m)` with
//!   `G1(v, m) = 2 / (1 + sqrt(1 + a^2 tan^2 theta_v))`, 1 for v along the normal, 0 when `(v.m) v.z <= 0`;
//! - visible-normal sampling (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"): `m` is drawn with
//!   density `D_v(m) = G1(v, m) max(0, v.m) D(m) / v.z`.

use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// `D(m)` for a unit microfacet normal `m` (0 below the surface).
#[inline]
pub fn ggx_d(m: Vec3A, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
    let d = 1.0 / (PI * a2 * t * t);
    if d.is_finite() { d } else { 0.0 }
}

/// Smith's masking term `G1(v, m)` for the unit direction `v`.
#[inline]
pub fn ggx_g1(v: Vec3A, m: Vec3A, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    let xy2 = v.x * v.x + v.y * v.y;
    if xy2 <= 0.0 {
        return 1.0;
    }
    let tan2 = xy2 / (v.z * v.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// Density (solid angle of `m`) with which [`sample_visible`] draws `m` seen from `v` (`v.z > 0`).
#[inline]
pub fn visible_pdf(v: Vec3A, m: Vec3A, alpha: f32) -> f32 {
    if v.z <= 0.0 {
        return 0.0;
    }
    ggx_g1(v, m, alpha) * v.dot(m).max(0.0) * ggx_d(m, alpha) / v.z
}

/// A microfacet normal visible from `v` (`v.z > 0`), with density [`visible_pdf`].
#[inline]
pub fn sample_visible(v: Vec3A, alpha: f32, u: Vec2) -> Vec3A {
    // Stretch the view direction to the configuration of a unit-roughness hemisphere.
    let vh = Vec3A::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { Vec3A::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { Vec3A::X };
    let t2 = vh.cross(t1);
    // A point on the projected disk, warped to the visible half.
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let mut p2 = r * phi.sin();
    let s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    // Unstretch.
    Vec3A::new(alpha * nh.x, alpha * nh.y, nh.z.max(1e-7)).normalize()
}
