//! A ray `origin + t * dir` for `t` in `(0, tmax)`. The direction is normalised by every constructor Prism uses
//! (camera, scattering, shadow rays), so `t` is a distance; accelerators do not rely on it.

use glam::Vec3A;

#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub tmax: f32,
    /// The triangle the ray leaves (rays spawned from a surface), or [`NO_PRIM`]. A ray leaving a plane cannot
    /// meet it again, so an accelerator may skip that triangle's test (the offset origin already keeps the exact
    /// test from hitting it: skipping saves the work, never changes the answer). Analytic shapes are never
    /// skipped (a ray leaving a sphere from inside meets it again).
    pub leaves: u32,
}

/// No primitive: [`Ray::leaves`] of camera rays and other rays that start off every surface.
pub const NO_PRIM: u32 = u32::MAX;

impl Ray {
    #[inline]
    pub fn new(origin: Vec3A, dir: Vec3A) -> Self {
        Ray { origin, dir, tmax: f32::INFINITY, leaves: NO_PRIM }
    }

    #[inline]
    pub fn with_tmax(origin: Vec3A, dir: Vec3A, tmax: f32) -> Self {
        Ray { origin, dir, tmax, leaves: NO_PRIM }
    }

    /// This ray, marked as leaving primitive `prim`.
    #[inline]
    pub fn leaving(self, prim: u32) -> Self {
        Ray { leaves: prim, ..self }
    }

    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + self.dir * t
    }
}
