//! Robust spawning of secondary rays (Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
//! Ray Tracing Gems 2019, ch. 6). The hit point is pushed off the surface along the geometric normal by a number
//! of float ULPs proportional to its magnitude (plus a small absolute step near the origin), so the spawned ray
//! cannot re-hit its own surface whatever the scene scale, and no light leaks through closed or thin geometry
//! because the step is only a few ULPs of the coordinates.

use super::Ray;
use glam::Vec3A;

const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

#[inline]
fn offset_component(p: f32, n: f32) -> f32 {
    if p.abs() < ORIGIN {
        return p + FLOAT_SCALE * n;
    }
    let of_i = (INT_SCALE * n) as i32;
    let bits = p.to_bits() as i32;
    let moved = if p < 0.0 {
        bits.wrapping_sub(of_i)
    } else {
        bits.wrapping_add(of_i)
    };
    f32::from_bits(moved as u32)
}

/// `p` moved off its surface to the side of the unit geometric normal `n`.
#[inline]
pub fn offset_ray_origin(p: Vec3A, n: Vec3A) -> Vec3A {
    Vec3A::new(
        offset_component(p.x, n.x),
        offset_component(p.y, n.y),
        offset_component(p.z, n.z),
    )
}

/// A ray leaving surface point `p` (geometric normal `ng`) in direction `dir` (unit).
#[inline]
pub fn spawn_ray(p: Vec3A, ng: Vec3A, dir: Vec3A) -> Ray {
    let n = if dir.dot(ng) >= 0.0 { ng } else { -ng };
    Ray::new(offset_ray_origin(p, n), dir)
}

/// A shadow ray from surface point `p` (normal `ng`) towards point `q` on another surface (normal `nq`, or zero for
/// a point light). Both ends are offset; `tmax` stops just short of the target so the target surface itself never
/// counts as an occluder. Returns the ray and the distance to the target.
#[inline]
pub fn spawn_ray_to(p: Vec3A, ng: Vec3A, q: Vec3A, nq: Vec3A) -> (Ray, f32) {
    let d = q - p;
    let n = if d.dot(ng) >= 0.0 { ng } else { -ng };
    let o = offset_ray_origin(p, n);
    let target = if nq == Vec3A::ZERO {
        q
    } else {
        let m = if (-d).dot(nq) >= 0.0 { nq } else { -nq };
        offset_ray_origin(q, m)
    };
    let to = target - o;
    let dist = to.length();
    (
        Ray::with_tmax(o, to / dist, dist * (1.0 - 1e-4)),
        d.length(),
    )
}
