//! Spheres and ellipsoids. A sphere under a similarity (rotation, uniform scale, translation) is stored in world
//! space; under any other transform it keeps its object-space centre and radius with the transform and is
//! intersected in object space (a sphere under a non-uniform scale is an exact ellipsoid). The ray–sphere test is
//! `geometry::intersect_sphere` (Ray Tracing Gems ch. 7); the hit point is reprojected onto the sphere, with the
//! error bound of that reprojection (pbrt-v4 section 6.8.5).
//!
//! `uv` ([`sphere_uv`], Mitsuba's convention): u around +y (`0.5 + atan2(x, z) / 2 pi`), v from the north pole
//! (`acos(y) / pi`); `dpdu`, `dpdv` are the derivatives of the point with respect to them (mapped by the transform
//! for ellipsoids); at the poles, where `dpdu` vanishes, a tangent stands in for `dpdv`.

use super::{AnalyticShape, ShapeHit, ShapePoint};
use crate::geometry::{Bounds, Ray, gamma, intersect_sphere};
use glam::{Affine3A, Mat3A, Vec2, Vec3A};
use std::f32::consts::PI;

/// A sphere primitive: world space, or object space with its transform (an ellipsoid).
#[derive(Clone, Copy, Debug)]
pub struct SphereGeom {
    /// Centre and radius in the sphere's frame (world space when `transform` is `None`).
    pub center: Vec3A,
    /// Radius in the same frame as `center` (positive).
    pub radius: f32,
    /// Present for non-similarity transforms (ellipsoids): intersect in object space.
    pub transform: Option<SphereTransform>,
    /// Index into the scene's material table.
    pub material: u32,
    /// Area light slot, or [`crate::primitives::NO_LIGHT`].
    pub light: u32,
    /// Compute texture coordinates and dp/du, dp/dv at hits (`true` unless the sphere's material never reads
    /// them and it emits no light; see [`crate::material::Material::uses_surface_coordinates`]). Otherwise they
    /// are left zero.
    pub coordinates: bool,
}

/// The transform of an ellipsoid: its sphere's object space to world space and back.
#[derive(Clone, Copy, Debug)]
pub struct SphereTransform {
    /// Object space to world space.
    pub world_from_object: Affine3A,
    /// World space to object space (the inverse of `world_from_object`).
    pub object_from_world: Affine3A,
    /// Inverse transpose of the linear part: maps object normals to world normals (then normalise).
    pub normal_to_world: Mat3A,
}

/// Error bound of the point `c + r n` reprojected onto a sphere, then mapped by `transform` (if any).
#[inline]
pub fn sphere_point_error(center: Vec3A, rn: Vec3A, transform: Option<&SphereTransform>) -> Vec3A {
    let err_o = gamma(6) * (center.abs() + rn.abs());
    match transform {
        None => err_o,
        Some(x) => {
            let m = x.world_from_object.matrix3;
            let abs_m = Mat3A::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
            let po = center + rn;
            (1.0 + gamma(3)) * (abs_m * err_o) + gamma(3) * (abs_m * po.abs() + x.world_from_object.translation.abs())
        }
    }
}

/// Spherical (u, v) in `[0, 1]^2` from a unit object-space normal, and dp/du, dp/dv for radius `r`: u around +y,
/// 0.5 straight ahead along +z and growing towards +x (an image wrapped around the sphere reads left to right
/// seen from outside), v = theta / pi from the north pole (+y, the image's top row) down.
pub fn sphere_uv(n: Vec3A, r: f32) -> (Vec2, Vec3A, Vec3A) {
    let u = 0.5 + n.x.atan2(n.z) / (2.0 * PI);
    let v = n.y.clamp(-1.0, 1.0).acos() / PI;
    let sin_t = (n.x * n.x + n.z * n.z).sqrt();
    let dpdu = 2.0 * PI * r * Vec3A::new(n.z, 0.0, -n.x);
    let dpdv = if sin_t > 1e-6 {
        PI * r * Vec3A::new(n.x * n.y / sin_t, -sin_t, n.z * n.y / sin_t)
    } else {
        // At the poles dp/du vanishes; any tangent orthogonal to the normal will do for dp/dv.
        PI * r * Vec3A::new(0.0, 0.0, if n.y > 0.0 { 1.0 } else { -1.0 })
    };
    (Vec2::new(u, v), dpdu, dpdv)
}

impl SphereGeom {
    /// A sphere under `m`: stored in world space if `m` is a similarity (rotation, uniform scale, translation),
    /// otherwise kept in object space with the transform (an ellipsoid).
    pub fn new(m: &Affine3A, center: Vec3A, radius: f32, material: u32, light: u32) -> SphereGeom {
        let l = m.matrix3;
        let (sx, sy, sz) = (l.x_axis.length(), l.y_axis.length(), l.z_axis.length());
        let orthogonal = l.x_axis.dot(l.y_axis).abs() < 1e-6 * sx * sy
            && l.y_axis.dot(l.z_axis).abs() < 1e-6 * sy * sz
            && l.z_axis.dot(l.x_axis).abs() < 1e-6 * sz * sx;
        let uniform = (sx - sy).abs() <= 1e-6 * sx && (sy - sz).abs() <= 1e-6 * sy;
        if orthogonal && uniform {
            return SphereGeom {
                center: m.transform_point3a(center),
                radius: radius * sx,
                transform: None,
                material,
                light,
                coordinates: true,
            };
        }
        let inv = m.inverse();
        SphereGeom {
            center,
            radius,
            transform: Some(SphereTransform {
                world_from_object: *m,
                object_from_world: inv,
                normal_to_world: inv.matrix3.transpose(),
            }),
            material,
            light,
            coordinates: true,
        }
    }

    /// Texture coordinates and dp/du, dp/dv at unit normal `n` of the sphere's own frame, if they are wanted.
    #[inline]
    fn coordinates_at(&self, n: Vec3A) -> (Vec2, Vec3A, Vec3A) {
        if self.coordinates { sphere_uv(n, self.radius) } else { (Vec2::ZERO, Vec3A::ZERO, Vec3A::ZERO) }
    }

    /// Distance along the ray to the sphere (or ellipsoid) in `(0, ray.tmax)`.
    #[inline]
    pub fn hit_t(&self, ray: &Ray) -> Option<f32> {
        match &self.transform {
            None => intersect_sphere(self.center, self.radius, ray.origin, ray.dir, ray.tmax),
            Some(x) => intersect_sphere(
                self.center,
                self.radius,
                x.object_from_world.transform_point3a(ray.origin),
                x.object_from_world.transform_vector3a(ray.dir),
                ray.tmax,
            ),
        }
    }
}

impl AnalyticShape for SphereGeom {
    fn bounds(&self) -> Bounds {
        let local = Bounds::new(self.center - Vec3A::splat(self.radius), self.center + Vec3A::splat(self.radius));
        match &self.transform {
            None => local,
            Some(t) => local.transformed(&t.world_from_object),
        }
    }

    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        self.hit_t(ray).map(|t| ShapeHit { t, u: 0.0, v: 0.0 })
    }

    /// World spheres: distance from the centre to the box; ellipsoids: their bounds.
    fn overlaps_box(&self, b: &Bounds) -> bool {
        let pb = self.bounds();
        if pb.min.cmpgt(b.max).any() || pb.max.cmplt(b.min).any() {
            return false;
        }
        match self.transform {
            None => {
                let q = self.center.clamp(b.min, b.max);
                let r = self.radius * (1.0 + 1e-5);
                (q - self.center).length_squared() <= r * r
            }
            Some(_) => true,
        }
    }

    fn surface(&self, ray: &Ray, hit: &ShapeHit) -> ShapePoint {
        match &self.transform {
            None => {
                let n = (ray.at(hit.t) - self.center).normalize();
                let (uv, dpdu, dpdv) = self.coordinates_at(n);
                ShapePoint {
                    p: self.center + n * self.radius,
                    p_err: sphere_point_error(self.center, n * self.radius, None),
                    n,
                    uv,
                    dpdu,
                    dpdv,
                }
            }
            Some(x) => {
                let po = x.object_from_world.transform_point3a(ray.origin)
                    + x.object_from_world.transform_vector3a(ray.dir) * hit.t;
                let no = (po - self.center).normalize();
                let p = x.world_from_object.transform_point3a(self.center + no * self.radius);
                let (uv, dpdu, dpdv) = self.coordinates_at(no);
                let m = x.world_from_object.matrix3;
                ShapePoint {
                    p,
                    p_err: sphere_point_error(self.center, no * self.radius, Some(x)),
                    n: (x.normal_to_world * no).normalize(),
                    uv,
                    dpdu: m * dpdu,
                    dpdv: m * dpdv,
                }
            }
        }
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn light(&self) -> u32 {
        self.light
    }
}
