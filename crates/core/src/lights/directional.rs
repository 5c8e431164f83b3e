//! The directional (distant) light: irradiance `E` (W/m^2 on a surface facing it) arriving from one direction.
//! Emitted rays start on a disk perpendicular to that direction that covers the scene's bounding sphere, so the
//! power entering the scene is `E pi R^2`.

use super::{LeSample, LightSample, SceneSphere};
use crate::geometry::Ray;
use crate::math::Frame;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

/// A distant light resolved to world space.
#[derive(Clone, Debug)]
pub struct DirectionalLight {
    /// Unit direction towards the light (opposite to the direction the light travels).
    pub to_light: Vec3A,
    /// Irradiance per RGB channel on a surface facing the light, W/m^2.
    pub irradiance: Vec3,
}

impl DirectionalLight {
    /// The light as seen from `p`: a delta in direction `to_light`, at infinite distance (the sample's point lies
    /// 1e30 away along it), carrying the irradiance.
    #[inline]
    pub fn sample_li(&self, p: Vec3A) -> LightSample {
        LightSample {
            dist: f32::INFINITY,
            ..LightSample::delta(p + self.to_light * 1e30, self.to_light, 1.0, self.irradiance)
        }
    }

    /// Power entering the scene's bounding sphere, `E pi R^2`.
    pub fn power(&self, sphere: &SceneSphere) -> Vec3 {
        self.irradiance * (PI * sphere.radius * sphere.radius)
    }

    /// An emitted ray from a uniform point of the disk of radius R, centred R beyond the scene centre towards the
    /// light and perpendicular to it.
    #[inline]
    pub fn sample_le(&self, sphere: &SceneSphere, u_pos: Vec2) -> LeSample {
        let d = warp::concentric_disk(u_pos) * sphere.radius;
        let f = Frame::from_normal(self.to_light);
        let origin = sphere.center + self.to_light * sphere.radius + f.s * d.x + f.t * d.y;
        let dir = -self.to_light;
        LeSample { ray: Ray::new(origin, dir), le: self.irradiance, n: dir, pdf_pos: sphere.disk_pdf(), pdf_dir: 1.0 }
    }

    /// Position (area) and direction pdfs of an emitted ray (direction is a delta: 1).
    pub fn pdf_le(&self, sphere: &SceneSphere) -> (f32, f32) {
        (sphere.disk_pdf(), 1.0)
    }
}
