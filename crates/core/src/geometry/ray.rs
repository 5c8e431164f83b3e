//! A ray `origin + t * dir` for `t` in `(0, tmax)`. Camera and scattered rays have unit directions, so their `t` is
//! a distance; a shadow ray towards a point carries the whole segment as its direction with `tmax` just below 1
//! (`spawn_ray_to`). Accelerators and shape tests take any direction length.

use glam::Vec3A;

/// A ray `origin + t dir`, `t` in `(0, tmax)`, with hints for the accelerators.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Start point, world space (already offset off the surface for spawned rays).
    pub origin: Vec3A,
    /// Direction; unit for camera and scattered rays, any length otherwise (not zero).
    pub dir: Vec3A,
    /// End of the ray's parameter interval (exclusive; `f32::INFINITY` for an unbounded ray).
    pub tmax: f32,
    /// The triangle the ray leaves (rays spawned from a surface), or [`NO_PRIM`]. A ray leaving a plane cannot
    /// meet it again, so an accelerator may skip that triangle's test (the offset origin already keeps the exact
    /// test from hitting it: skipping saves the work, never changes the answer). Analytic shapes are never
    /// skipped (a ray leaving a sphere from inside meets it again).
    pub leaves: u32,
    /// A hint that the ray is one of a coherent set (camera rays: neighbours take nearly the same path through the
    /// scene, as Embree's `RTC_RAY_QUERY_FLAG_COHERENT` says). Accelerators may pick code that is faster for such
    /// rays — the wide BVH then reads a leaf's surviving triangle by a branch on its lane, which coherent rays
    /// predict, instead of a permute, which costs incoherent ones less — never a different answer.
    pub coherent: bool,
}

/// No primitive: [`Ray::leaves`] of camera rays and other rays that start off every surface.
pub const NO_PRIM: u32 = u32::MAX;

impl Ray {
    /// An unbounded ray (`tmax` infinite), leaving no primitive, not coherent.
    #[inline]
    pub fn new(origin: Vec3A, dir: Vec3A) -> Self {
        Ray { origin, dir, tmax: f32::INFINITY, leaves: NO_PRIM, coherent: false }
    }

    /// A ray ending at `tmax`, leaving no primitive, not coherent.
    #[inline]
    pub fn with_tmax(origin: Vec3A, dir: Vec3A, tmax: f32) -> Self {
        Ray { origin, dir, tmax, leaves: NO_PRIM, coherent: false }
    }

    /// This ray, marked as leaving primitive `prim`.
    #[inline]
    pub fn leaving(self, prim: u32) -> Self {
        Ray { leaves: prim, ..self }
    }

    /// This ray, marked as one of a coherent set (see [`Ray::coherent`]).
    #[inline]
    pub fn coherent(self) -> Self {
        Ray { coherent: true, ..self }
    }

    /// The point `origin + t dir`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + self.dir * t
    }
}
