//! The environment light: radiance arriving from infinitely far away, constant or from an [`EnvMap`] rotated by
//! its entity's transform. Next-event estimation and emission draw directions from an [`EnvSampling`] (quad-tree by
//! default), which integrators build in Prepare only when the scene has an environment light.
//!
//! Emitted rays (photons, light paths): a direction `w` towards the environment from the sampler (solid-angle pdf),
//! then an origin uniform on the disk of radius R perpendicular to `w`, centred R beyond the scene centre along `w`;
//! the ray travels along `-w` and carries `L(w)`. Power: `pi R^2 integral L(w) dw`.

use super::{EnvSampling, LeSample, SceneSphere};
use crate::envmap::EnvMap;
use crate::geometry::Ray;
use crate::math::Frame;
use crate::sampling::warp;
use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// The environment light resolved to world space.
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    /// Radiance scale (the constant radiance when there is no map).
    pub radiance: Vec3,
    /// The map, in its own (env) frame; `None`: constant radiance.
    pub map: Option<Arc<EnvMap>>,
    /// Maps world directions into the map's frame (the inverse of the entity's rotation).
    pub env_from_world: Mat3A,
    /// Maps the map's directions into the world (the linear part of the entity's transform).
    pub world_from_env: Mat3A,
    /// `integral L(w) dw` over the sphere (RGB).
    pub integral: Vec3,
}

impl EnvironmentLight {
    /// The light of `radiance` times `map` (constant without one), oriented by the linear part of
    /// `world_from_local`, with its radiance integrated over the sphere.
    pub fn new(radiance: Vec3, map: Option<Arc<EnvMap>>, world_from_local: &Affine3A) -> Self {
        let world_from_env = world_from_local.matrix3;
        let integral = match &map {
            None => radiance * (4.0 * PI),
            Some(m) => radiance * m.integral(),
        };
        EnvironmentLight { radiance, map, env_from_world: world_from_env.inverse(), world_from_env, integral }
    }

    /// Radiance arriving from the unit world direction `dir` (i.e. seen looking along `dir`).
    #[inline]
    pub fn eval(&self, dir: Vec3A) -> Vec3 {
        match &self.map {
            None => self.radiance,
            Some(m) => self.radiance * m.lookup((self.env_from_world * dir).normalize()),
        }
    }

    /// World direction of a direction in the map's frame.
    #[inline]
    pub fn to_world(&self, d: Vec3A) -> Vec3A {
        (self.world_from_env * d).normalize()
    }

    /// Map-frame direction of a world direction.
    #[inline]
    pub fn to_env(&self, d: Vec3A) -> Vec3A {
        (self.env_from_world * d).normalize()
    }

    /// Power entering the scene's bounding sphere: `pi R^2 integral L dw`.
    pub fn power(&self, sphere: &SceneSphere) -> Vec3 {
        self.integral * (PI * sphere.radius * sphere.radius)
    }

    /// An emitted ray: a direction from `sampling` (`u_dir`), an origin on the covering disk (`u_pos`).
    #[inline]
    pub fn sample_le(
        &self,
        sampling: &EnvSampling,
        sphere: &SceneSphere,
        u_pos: Vec2,
        u_dir: Vec2,
    ) -> Option<LeSample> {
        let (w, pdf_dir) = sampling.sample_emission(self, u_dir)?;
        let le = self.eval(w);
        let f = Frame::from_normal(w);
        let d = warp::concentric_disk(u_pos) * sphere.radius;
        let origin = sphere.center + w * sphere.radius + f.s * d.x + f.t * d.y;
        Some(LeSample { ray: Ray::new(origin, -w), le, n: -w, pdf_pos: sphere.disk_pdf(), pdf_dir })
    }

    /// Position (area on the disk) and direction (solid angle) pdfs of an emitted ray travelling along `dir`.
    pub fn pdf_le(&self, sampling: &EnvSampling, sphere: &SceneSphere, dir: Vec3A) -> (f32, f32) {
        (sphere.disk_pdf(), sampling.pdf_emission(self, -dir))
    }
}
