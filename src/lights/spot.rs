//! The spot light (pbrt-v4's model): a point light whose intensity is `I` inside the cone of half-angle
//! `cone_angle - falloff` around its axis, falls off smoothly (smoothstep in the cosine) to 0 at `cone_angle`, and
//! is 0 outside. Power `2 pi I ((1 - cos_start) + (cos_start - cos_end) / 2)` (exact: the smoothstep averages 1/2);
//! emitted rays are uniform inside the outer cone, each carrying `I * falloff(direction)`.

use super::{LeSample, LightSample};
use crate::geometry::Ray;
use crate::math::Frame;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct SpotLight {
    pub position: Vec3A,
    /// Frame whose normal is the cone's axis (the direction the light points to).
    pub frame: Frame,
    /// Intensity on the axis, W/sr.
    pub intensity: Vec3,
    /// Cosine of the angle where the falloff starts (full intensity inside).
    pub cos_start: f32,
    /// Cosine of the cone's half-angle (no light outside).
    pub cos_end: f32,
}

/// Hermite smoothstep of `x` between `a` and `b` (0 below `a`, 1 above `b`).
#[inline]
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl SpotLight {
    /// A spot at `position` pointing along the unit `axis`; angles in degrees, `falloff` <= `cone_angle`.
    pub fn new(position: Vec3A, axis: Vec3A, intensity: Vec3, cone_angle: f32, falloff: f32) -> Self {
        let cos_end = cone_angle.to_radians().cos();
        let cos_start = (cone_angle - falloff).max(0.0).to_radians().cos();
        SpotLight { position, frame: Frame::from_normal(axis), intensity, cos_start, cos_end }
    }

    /// Relative intensity towards the unit direction `w` leaving the light.
    #[inline]
    pub fn falloff(&self, w: Vec3A) -> f32 {
        smoothstep(self.cos_end, self.cos_start, w.dot(self.frame.n))
    }

    /// The light as seen from `p` (a delta in direction); `None` outside the cone.
    #[inline]
    pub fn sample_li(&self, p: Vec3A) -> Option<LightSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let f = self.falloff(-wi);
        (f > 0.0).then(|| LightSample::delta(self.position, wi, dist, self.intensity * (f / dist2)))
    }

    pub fn power(&self) -> Vec3 {
        self.intensity * (2.0 * PI * ((1.0 - self.cos_start) + 0.5 * (self.cos_start - self.cos_end)))
    }

    /// An emitted ray, uniform in the outer cone; `None` only for a degenerate (empty) cone.
    #[inline]
    pub fn sample_le(&self, u_dir: Vec2) -> Option<LeSample> {
        if self.cos_end >= 1.0 {
            return None;
        }
        let dir = self.frame.to_world(warp::uniform_cone(u_dir, self.cos_end));
        Some(LeSample {
            ray: Ray::new(self.position, dir),
            le: self.intensity * self.falloff(dir),
            n: Vec3A::ZERO,
            pdf_pos: 1.0,
            pdf_dir: warp::uniform_cone_pdf(self.cos_end),
        })
    }

    /// Position and direction pdfs of an emitted ray along the unit `dir`.
    pub fn pdf_le(&self, dir: Vec3A) -> (f32, f32) {
        let inside = dir.dot(self.frame.n) >= self.cos_end && self.cos_end < 1.0;
        (1.0, if inside { warp::uniform_cone_pdf(self.cos_end) } else { 0.0 })
    }
}
