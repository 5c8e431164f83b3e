//! The bounds of a triangle clipped to a box (Sutherland–Hodgman against the six planes): the "perfect split"
//! bounds of a straddling triangle in a kd-tree child (Havran 2000; Wald & Havran 2006), tighter than cutting its
//! bounding box.

use crate::geometry::Bounds;
use glam::Vec3A;

/// Most vertices a triangle clipped by 6 planes can have (3 + 6).
const MAX_VERTS: usize = 9;

/// Bounds of `tri ∩ b`, or `None` when the triangle misses the box. Each clip keeps the coordinate of the new
/// vertices on the clip plane exact.
pub fn clipped_triangle_bounds(tri: &[Vec3A; 3], b: &Bounds) -> Option<Bounds> {
    let mut poly = [Vec3A::ZERO; MAX_VERTS];
    poly[..3].copy_from_slice(tri);
    let mut n = 3;
    let mut out = [Vec3A::ZERO; MAX_VERTS];
    for axis in 0..3 {
        for (plane, keep_above) in [(b.min[axis], true), (b.max[axis], false)] {
            let inside = |p: Vec3A| if keep_above { p[axis] >= plane } else { p[axis] <= plane };
            let mut m = 0;
            for i in 0..n {
                let (p, q) = (poly[i], poly[(i + 1) % n]);
                let (pin, qin) = (inside(p), inside(q));
                if pin {
                    out[m] = p;
                    m += 1;
                }
                if pin != qin && m < MAX_VERTS {
                    let t = (plane - p[axis]) / (q[axis] - p[axis]);
                    let mut x = p + (q - p) * t;
                    x[axis] = plane;
                    out[m] = x;
                    m += 1;
                }
            }
            n = m;
            if n == 0 {
                return None;
            }
            poly[..n].copy_from_slice(&out[..n]);
        }
    }
    let r = Bounds::from_points(&poly[..n]);
    // Clamp: interpolation may stray a rounding error outside the box along the other axes.
    Some(Bounds::new(r.min.max(b.min), r.max.min(b.max)))
}
