//! Small math helpers shared by geometry, materials and integrators: orthonormal frames, optics (reflection,
//! refraction, Fresnel), colour luminance.

mod frame;
mod optics;

pub use frame::Frame;
pub use optics::{fresnel_dielectric, reflect, refract};

use glam::Vec3;

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
