//! Ray-surface interactions (pbrt's `interaction.h`): the closest hit an accelerator reports, the surface record an
//! integrator shades, and the rays it spawns from it, offset off the surface by the point's error bound.

use super::{Ray, spawn_ray, spawn_ray_to};
use glam::{Vec2, Vec3A};

/// A closest hit found by an accelerator. For triangles `b1`, `b2` are the barycentric weights of vertices 1 and
/// 2; for curved surfaces their two parameters (`ShapeHit` in `crate::shapes`); unused otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, in `(0, tmax)` (a distance for unit directions).
    pub t: f32,
    /// Primitive id (see `crate::primitives` for the id ranges).
    pub prim: u32,
    /// Barycentric weight of vertex 1 (triangles), or the shape's first surface parameter.
    pub b1: f32,
    /// Barycentric weight of vertex 2 (triangles), or the shape's second surface parameter.
    pub b2: f32,
}

/// Everything an integrator needs to know about a surface point.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// The hit point, world space.
    pub p: Vec3A,
    /// Conservative absolute floating-point error bound of `p`, per coordinate (for robust ray spawning).
    pub p_err: Vec3A,
    /// Geometric normal (unit), oriented by the primitive (triangle winding, sphere outward, plane normal).
    pub ng: Vec3A,
    /// Shading normal (unit), on the same side as `ng`.
    pub ns: Vec3A,
    /// Surface parameterisation at the point (texture coordinates).
    pub uv: Vec2,
    /// Partial derivatives of the position with respect to u and v (world space, not normalised): from the
    /// triangle's uvs, the sphere's and the plane's parameterisations. Texturing and normal mapping use them.
    pub dpdu: Vec3A,
    /// Partial derivative of the position with respect to v (see `dpdu`).
    pub dpdv: Vec3A,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Id of the primitive hit (see `crate::primitives` for the id ranges).
    pub prim: u32,
    /// Index into the scene's material table.
    pub material: u32,
    /// Index of the area light the primitive belongs to, or [`crate::primitives::NO_LIGHT`].
    pub light: u32,
}

impl SurfaceHit {
    /// A ray leaving this point in unit direction `dir`, offset off the surface.
    #[inline]
    pub fn spawn(&self, dir: Vec3A) -> Ray {
        spawn_ray(self.p, self.p_err, self.ng, dir).leaving(self.prim)
    }

    /// A ray from this point to the point `p` (error bound `p_err`, surface normal `n`, zero for a point that lies
    /// on no surface), both ends offset off their surfaces: `tmax` stops it short of `p`.
    #[inline(always)]
    pub fn spawn_to(&self, p: Vec3A, p_err: Vec3A, n: Vec3A) -> Ray {
        spawn_ray_to(self.p, self.p_err, self.ng, p, p_err, n).leaving(self.prim)
    }
}
