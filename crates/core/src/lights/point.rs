//! The isotropic point light: radiant intensity `I` (W/sr) in every direction from one point.
//!
//! Next-event estimation sees irradiance `I cos / (a0 + a1 d + a2 d^2)` with `attenuation = (a0, a1, a2)`, physically
//! `(0, 0, 1)`; other values reproduce 6.837 scenes. Emission (photons, light paths) is always the physical light:
//! uniform directions, power `4 pi I` (a non-physical attenuation has no emitted-ray equivalent).

use super::{LeSample, LightSample};
use crate::geometry::Ray;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

/// A point light resolved to world space.
#[derive(Clone, Debug)]
pub struct PointLight {
    /// Position, world space.
    pub position: Vec3A,
    /// Radiant intensity per RGB channel, W/sr.
    pub intensity: Vec3,
    /// `(a0, a1, a2)` of the fall-off `a0 + a1 d + a2 d^2` next-event estimation divides by; `(0, 0, 1)` physically.
    pub attenuation: Vec3,
}

impl PointLight {
    /// The light as seen from `p` (a delta in direction).
    #[inline]
    pub fn sample_li(&self, p: Vec3A) -> Option<LightSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let falloff = if self.attenuation == Vec3::Z {
            dist2
        } else {
            self.attenuation.x + self.attenuation.y * dist + self.attenuation.z * dist2
        };
        Some(LightSample::delta(self.position, d / dist, dist, self.intensity / falloff))
    }

    /// Total emitted power, `4 pi I`.
    pub fn power(&self) -> Vec3 {
        4.0 * PI * self.intensity
    }

    /// An emitted ray: uniform direction (pdf 1 / 4 pi), delta position.
    #[inline]
    pub fn sample_le(&self, u_dir: Vec2) -> LeSample {
        let dir = warp::uniform_sphere(u_dir);
        LeSample {
            ray: Ray::new(self.position, dir),
            le: self.intensity,
            n: Vec3A::ZERO,
            pdf_pos: 1.0,
            pdf_dir: warp::uniform_sphere_pdf(),
        }
    }

    /// Position and direction pdfs of an emitted ray (position is a delta: 1).
    pub fn pdf_le(&self) -> (f32, f32) {
        (1.0, warp::uniform_sphere_pdf())
    }
}
