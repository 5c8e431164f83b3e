//! The spot light (pbrt-v4's model): a point light whose intensity is `I` inside the cone of half-angle
//! `cone_angle - falloff` around its axis, falls off smoothly to 0 at `cone_angle`, and is 0 outside. The fall-off
//! is a function of `t = (cos - cos_end) / (cos_start - cos_end)` in [0, 1] ([`SpotProfile`]): pbrt-v4's
//! smoothstep `3t^2 - 2t^3` (the default), pbrt-v3's `t^4`, or glTF's `t^2` (KHR_lights_punctual's reference
//! code). Power `2 pi I ((1 - cos_start) + m (cos_start - cos_end))` with `m` the profile's mean over the cosine
//! (1/2, 1/5, 1/3: exact); emitted rays are uniform inside the outer cone, each carrying `I * falloff(direction)`.

use super::{LeSample, LightSample};
use crate::geometry::Ray;
use crate::math::Frame;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

/// How a spot light's intensity falls from the inner to the outer cone, as a function of
/// `t = (cos - cos_end) / (cos_start - cos_end)`.
#[derive(serde::Deserialize, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SpotProfile {
    /// pbrt-v4: `smoothstep(t) = 3t^2 - 2t^3`.
    #[default]
    Smoothstep,
    /// pbrt-v3: `t^4`.
    Quartic,
    /// glTF (KHR_lights_punctual): `t^2`, i.e. the square of the linear ramp in the cosine.
    Gltf,
}

impl SpotProfile {
    /// The profile at `t` in [0, 1].
    #[inline]
    fn eval(self, t: f32) -> f32 {
        match self {
            SpotProfile::Smoothstep => t * t * (3.0 - 2.0 * t),
            SpotProfile::Quartic => (t * t) * (t * t),
            SpotProfile::Gltf => t * t,
        }
    }

    /// The mean of the profile over `t` in [0, 1] (the fall-off band's share of the power).
    pub fn mean(self) -> f32 {
        match self {
            SpotProfile::Smoothstep => 0.5,
            SpotProfile::Quartic => 0.2,
            SpotProfile::Gltf => 1.0 / 3.0,
        }
    }
}

/// A spot light resolved to world space, its angles as cosines.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Position, world space.
    pub position: Vec3A,
    /// Frame whose normal is the cone's axis (the direction the light points to).
    pub frame: Frame,
    /// Intensity on the axis, W/sr.
    pub intensity: Vec3,
    /// Cosine of the angle where the falloff starts (full intensity inside).
    pub cos_start: f32,
    /// Cosine of the cone's half-angle (no light outside).
    pub cos_end: f32,
    /// The shape of the fall-off between `cos_start` and `cos_end`.
    pub profile: SpotProfile,
}

impl SpotLight {
    /// A spot at `position` pointing along the unit `axis`; angles in degrees, `falloff` <= `cone_angle`.
    pub fn new(
        position: Vec3A,
        axis: Vec3A,
        intensity: Vec3,
        cone_angle: f32,
        falloff: f32,
        profile: SpotProfile,
    ) -> Self {
        let cos_end = cone_angle.to_radians().cos();
        let cos_start = (cone_angle - falloff).max(0.0).to_radians().cos();
        SpotLight { position, frame: Frame::from_normal(axis), intensity, cos_start, cos_end, profile }
    }

    /// Relative intensity towards the unit direction `w` leaving the light.
    #[inline]
    pub fn falloff(&self, w: Vec3A) -> f32 {
        let (a, b, x) = (self.cos_end, self.cos_start, w.dot(self.frame.n));
        if x < a {
            return 0.0;
        }
        if x >= b {
            return 1.0;
        }
        self.profile.eval(((x - a) / (b - a)).clamp(0.0, 1.0))
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

    /// Total emitted power, `2 pi I ((1 - cos_start) + m (cos_start - cos_end))` (`m`: [`SpotProfile::mean`]).
    pub fn power(&self) -> Vec3 {
        self.intensity * (2.0 * PI * ((1.0 - self.cos_start) + self.profile.mean() * (self.cos_start - self.cos_end)))
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
