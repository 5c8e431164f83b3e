//! The parametric interval of a ray inside an axis-aligned box, robust to axis-parallel rays (no `0 * inf` NaN):
//! shared by the grid and the kd-tree, whose traversals start from it.

use crate::geometry::Bounds;
use glam::Vec3A;

/// Per-ray reciprocal direction with axis-parallel components marked: `inv[a]` is 0 where the ray does not move
/// along axis `a` (its direction component is zero or too small for its reciprocal to be finite).
#[derive(Clone, Copy, Debug)]
pub struct RayInv {
    pub inv: Vec3A,
    pub parallel: [bool; 3],
}

impl RayInv {
    #[inline]
    pub fn new(dir: Vec3A) -> Self {
        let mut inv = Vec3A::ZERO;
        let mut parallel = [true; 3];
        for a in 0..3 {
            let r = 1.0 / dir[a];
            if r.is_finite() {
                inv[a] = r;
                parallel[a] = false;
            }
        }
        RayInv { inv, parallel }
    }
}

/// `[t0, t1]` of the ray `origin + t dir` inside `b`, clipped to `[tmin, tmax]`, or `None` if it misses.
#[inline]
pub fn clip_ray(b: &Bounds, origin: Vec3A, ri: &RayInv, tmin: f32, tmax: f32) -> Option<(f32, f32)> {
    let (mut t0, mut t1) = (tmin, tmax);
    for a in 0..3 {
        if ri.parallel[a] {
            if origin[a] < b.min[a] || origin[a] > b.max[a] {
                return None;
            }
            continue;
        }
        let ta = (b.min[a] - origin[a]) * ri.inv[a];
        let tb = (b.max[a] - origin[a]) * ri.inv[a];
        let (lo, hi) = if ta < tb { (ta, tb) } else { (tb, ta) };
        t0 = t0.max(lo);
        t1 = t1.min(hi);
    }
    (t0 <= t1).then_some((t0, t1))
}

/// `b` grown on every side by a margin that covers floating-point error: a relative part of its largest extent
/// and a few ulps of its largest coordinate. A flat box gets a non-zero thickness.
pub fn padded(b: &Bounds) -> Bounds {
    let ext = b.diagonal().max_element().max(0.0);
    let mag = b.min.abs().max(b.max.abs()).max_element();
    let pad = (1e-5 * ext).max(4.0 * f32::EPSILON * mag).max(f32::MIN_POSITIVE);
    Bounds::new(b.min - Vec3A::splat(pad), b.max + Vec3A::splat(pad))
}
