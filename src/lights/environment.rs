//! The environment light: radiance arriving from infinitely far away, constant or from an [`EnvMap`] rotated by
//! its entity's transform. Integrators that importance-sample it build their own sampler in Prepare (the
//! `envlight` plugin's quad-tree), so scenes without an environment pay nothing.

use crate::envmap::EnvMap;
use glam::{Affine3A, Mat3A, Vec3, Vec3A};
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    /// Radiance scale (the constant radiance when there is no map).
    pub radiance: Vec3,
    pub map: Option<Arc<EnvMap>>,
    /// Maps world directions into the map's frame (the inverse of the entity's rotation).
    pub env_from_world: Mat3A,
    pub world_from_env: Mat3A,
}

impl EnvironmentLight {
    pub fn new(radiance: Vec3, map: Option<Arc<EnvMap>>, world_from_local: &Affine3A) -> Self {
        let world_from_env = world_from_local.matrix3;
        EnvironmentLight { radiance, map, env_from_world: world_from_env.inverse(), world_from_env }
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
}
