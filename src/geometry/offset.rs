//! Robust spawning of secondary rays with conservative floating-point error bounds (pbrt-v4, "Robust Spawned Ray
//! Origins", Pharr, Jakob & Humphreys, 4th ed. section 6.8.6). Each surface hit carries an absolute error bound
//! `p_err` per coordinate, derived from how the point was computed (barycentric interpolation for triangles,
//! reprojection for spheres and planes); the origin is pushed along the geometric normal just past that error
//! box and rounded one ULP further out. The offset is therefore proportional to the actual rounding error: it
//! is right for a 1 mm object at the origin and for a stadium 10^5 units away, never re-hits the surface
//! (no shadow acne) and never crosses geometry thicker than the error bound (no light leaking).

use super::Ray;
use glam::Vec3A;

/// The bound gamma(n) = n u / (1 - n u) on the relative error of n chained floating-point operations, u = 2^-24.
#[inline]
pub const fn gamma(n: i32) -> f32 {
    let u = f32::EPSILON * 0.5;
    (n as f32 * u) / (1.0 - n as f32 * u)
}

#[inline]
fn next_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    f32::from_bits(if v >= 0.0 { bits + 1 } else { bits - 1 })
}

#[inline]
fn next_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    f32::from_bits(if v > 0.0 { bits - 1 } else { bits + 1 })
}

/// `p` (with absolute error bound `p_err`) moved off its surface along the unit geometric normal `n`, towards the
/// side of `w`.
#[inline]
pub fn offset_ray_origin(p: Vec3A, p_err: Vec3A, n: Vec3A, w: Vec3A) -> Vec3A {
    let d = n.abs().dot(p_err);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    let round = |v: f32, o: f32| {
        if o > 0.0 {
            next_up(v)
        } else if o < 0.0 {
            next_down(v)
        } else {
            v
        }
    };
    Vec3A::new(round(po.x, offset.x), round(po.y, offset.y), round(po.z, offset.z))
}

/// A ray leaving surface point `p` (error `p_err`, geometric normal `ng`) in unit direction `dir`.
#[inline]
pub fn spawn_ray(p: Vec3A, p_err: Vec3A, ng: Vec3A, dir: Vec3A) -> Ray {
    Ray::new(offset_ray_origin(p, p_err, ng, dir), dir)
}

/// A shadow ray from `p` (error `p_err`, normal `ng`) towards `q` (error `q_err`, normal `nq`; zero normal and
/// error for a point light). Both ends are offset off their surfaces. As in pbrt-v4's `SpawnRayTo`, the direction
/// is the whole segment between the offset ends, not a unit vector, and `tmax` is `1 - 1e-4`, so the ray stops
/// just short of the target and the target surface never counts as an occluder. For occlusion queries only (every
/// accelerator and shape test takes any direction length): no square root and division on the way to the query.
#[inline(always)]
pub fn spawn_ray_to(p: Vec3A, p_err: Vec3A, ng: Vec3A, q: Vec3A, q_err: Vec3A, nq: Vec3A) -> Ray {
    let o = offset_ray_origin(p, p_err, ng, q - p);
    let target = if nq == Vec3A::ZERO { q } else { offset_ray_origin(q, q_err, nq, o - q) };
    Ray::with_tmax(o, target - o, 1.0 - 1e-4)
}
