//! Ray–plane intersection for the plane `{x : normal · x = offset}` (unit normal).

use super::Ray;
use glam::Vec3A;

/// Distance along the ray to the plane, if it lies in `(0, ray.tmax)`.
#[inline]
pub fn intersect_plane(normal: Vec3A, offset: f32, ray: &Ray) -> Option<f32> {
    let denom = normal.dot(ray.dir);
    if denom == 0.0 {
        return None;
    }
    let t = (offset - normal.dot(ray.origin)) / denom;
    (t > 0.0 && t < ray.tmax).then_some(t)
}
