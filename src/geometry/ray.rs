//! A ray `origin + t * dir` for `t` in `(0, tmax)`. The direction is normalised by every constructor Prism uses
//! (camera, scattering, shadow rays), so `t` is a distance; accelerators do not rely on it.

use glam::Vec3A;

#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub tmax: f32,
}

impl Ray {
    #[inline]
    pub fn new(origin: Vec3A, dir: Vec3A) -> Self {
        Ray { origin, dir, tmax: f32::INFINITY }
    }

    #[inline]
    pub fn with_tmax(origin: Vec3A, dir: Vec3A, tmax: f32) -> Self {
        Ray { origin, dir, tmax }
    }

    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + self.dir * t
    }
}
