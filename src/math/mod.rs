//! Small math helpers shared by geometry, materials and integrators: orthonormal frames, optics (reflection,
//! refraction, Fresnel), colour luminance.

mod frame;
mod optics;

pub use frame::Frame;
pub use optics::{fresnel_dielectric, reflect, refract};

use glam::Vec3;

/// `v / |v|` computed in double precision, so vectors as short as 1e-38 or as long as 1e38 (whose squared length
/// underflows or overflows in `f32`) normalise exactly; `None` for zero or non-finite vectors.
pub fn unit_vector(v: Vec3) -> Option<Vec3> {
    let d = v.as_dvec3();
    let len = d.length();
    (len > 0.0 && len.is_finite()).then(|| (d / len).as_vec3())
}

/// Rec. 709 luminance of a linear RGB colour.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// True when every component is finite.
#[inline]
pub fn is_finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}
