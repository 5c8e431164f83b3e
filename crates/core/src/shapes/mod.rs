//! Analytic shapes: every bounded primitive that is not a triangle (spheres and ellipsoids, surfaces of
//! revolution, bicubic Bézier patches) answers one interface, [`AnalyticShape`], and every accelerator reaches
//! them through one dispatch (`Primitives::intersect_analytic` and friends, a `match` on [`ShapeRef`]), never
//! through a case of its own. Triangles stay the accelerators' fast path.
//!
//! | file | what |
//! |---|---|
//! | `curve.rs` | piecewise cubic Bézier and uniform cubic B-spline curves: evaluation, derivatives, basis conversion, tessellation |
//! | `sphere.rs` | spheres and ellipsoids |
//! | `revolution.rs` | surfaces of revolution (a profile curve revolved about y), exact intersection |
//! | `revolution_seeds.rs` | the revolution's Newton seeds: chord cones, chord projection, crossings along grazing rays |
//! | `profile_tree.rs` | the revolution's seeding structure: rings bounding flat pieces of the profile |
//! | `strip.rs` | a tight bound of one flat piece: its chord-aligned rectangle, revolved |
//! | `patch.rs` | bicubic Bézier patches, exact intersection, seeding quadtree |
//! | `newton.rs` | the Newton iteration both curved surfaces share |
//! | `tessellate.rs` | the same surfaces as triangle meshes at a chosen resolution |
//! | `area_sampling.rs` | sampling points on a curved surface by area, with the exact pdf (area lights) |

pub mod area_sampling;
pub mod curve;
pub mod newton;
pub mod patch;
pub mod profile_tree;
pub mod revolution;
pub mod revolution_seeds;
mod shape;
pub mod sphere;
pub mod strip;
pub mod tessellate;

pub use curve::{Curve, CurveKind};
pub use patch::BezierPatch;
pub use revolution::Revolution;
pub use shape::Shape;
pub use sphere::{SphereGeom, SphereTransform, sphere_point_error, sphere_uv};

use crate::geometry::{Bounds, Ray};
use glam::{Vec2, Vec3A};

/// A hit on an analytic shape: the distance and the two surface parameters (unused by spheres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// First surface parameter (patches: u in `[0, 1]`; revolutions: the profile parameter `s`).
    pub u: f32,
    /// Second surface parameter (patches: v in `[0, 1]`; revolutions: the angle `theta`, radians).
    pub v: f32,
}

/// World-space surface data at a hit.
#[derive(Clone, Copy, Debug)]
pub struct ShapePoint {
    /// The surface point, world space.
    pub p: Vec3A,
    /// Conservative absolute error bound of `p` per coordinate: how far the true surface may be.
    pub p_err: Vec3A,
    /// Unit geometric normal (also the shading normal: the surfaces are smooth).
    pub n: Vec3A,
    /// Texture coordinates of the point.
    pub uv: Vec2,
    /// Partial derivative of the position with respect to u, world space.
    pub dpdu: Vec3A,
    /// Partial derivative of the position with respect to v, world space.
    pub dpdv: Vec3A,
}

/// What every analytic shape answers, in world space.
pub trait AnalyticShape {
    /// Conservative world bounds.
    fn bounds(&self) -> Bounds;
    /// The nearest hit in `(0, ray.tmax)`.
    fn intersect(&self, ray: &Ray) -> Option<ShapeHit>;
    /// Is there any hit in `(0, ray.tmax)`? (May stop at the first one found.)
    fn occludes(&self, ray: &Ray) -> bool {
        self.intersect(ray).is_some()
    }
    /// Might the shape overlap the box? Conservative: never false when it does (grid insertion).
    fn overlaps_box(&self, b: &Bounds) -> bool;
    /// Conservative bounds of the part of the shape inside `voxel`, or `None` if it surely misses it (kd-tree
    /// perfect splits).
    fn clip_bounds(&self, voxel: &Bounds) -> Option<Bounds> {
        let pb = self.bounds();
        let b = Bounds::new(pb.min.max(voxel.min), pb.max.min(voxel.max));
        (!b.is_empty() && self.overlaps_box(voxel)).then_some(b)
    }
    /// Surface data at a hit this shape returned for `ray`.
    fn surface(&self, ray: &Ray, hit: &ShapeHit) -> ShapePoint;
    /// Surface data at the point of texture coordinates `uv` (curved surfaces: area-light sampling).
    fn point_at_uv(&self, _uv: Vec2) -> Option<ShapePoint> {
        None
    }
    /// Index into the scene's material table.
    fn material(&self) -> u32;
    /// Area light slot, or `NO_LIGHT`.
    fn light(&self) -> u32;
}

/// Which analytic shape a primitive id names: the kind and its index in that kind's array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeRef {
    /// Index into `Primitives::spheres`.
    Sphere(u32),
    /// Index into `Primitives::revolutions`.
    Revolution(u32),
    /// Index into `Primitives::patches`.
    Patch(u32),
}
