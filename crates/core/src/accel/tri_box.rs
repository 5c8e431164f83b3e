//! Conservative triangle/box overlap by the separating axis theorem (Akenine-Möller, "Fast 3D Triangle-Box Overlap
//! Testing", JGT 2001): the box's 3 axes, the triangle's normal and the 9 edge cross products. Every comparison
//! carries a small tolerance so a triangle that touches the box within rounding error counts as overlapping: the
//! grid may hold a few extra references, never miss one.

use glam::Vec3A;

/// True if triangle `v` overlaps the box `[bmin, bmax]` (or lies within rounding error of it).
#[inline]
pub fn triangle_overlaps_box(v: &[Vec3A; 3], bmin: Vec3A, bmax: Vec3A) -> bool {
    let c = 0.5 * (bmin + bmax);
    let h = 0.5 * (bmax - bmin);
    let p = [v[0] - c, v[1] - c, v[2] - c];
    // Tolerance: relative to the magnitudes involved.
    let scale = h.max_element().max(p[0].abs().max(p[1].abs()).max(p[2].abs()).max_element());
    let tol = 1e-5 * scale;
    // Box axes.
    let lo = p[0].min(p[1]).min(p[2]);
    let hi = p[0].max(p[1]).max(p[2]);
    if lo.cmpgt(h + Vec3A::splat(tol)).any() || hi.cmplt(-h - Vec3A::splat(tol)).any() {
        return false;
    }
    let e = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
    // Triangle plane.
    let n = e[0].cross(e[1]);
    let r = h.dot(n.abs());
    let s = n.dot(p[0]);
    if s.abs() > r + tol * n.abs().element_sum() {
        return false;
    }
    // Edge x box-axis cross products.
    for edge in e {
        for axis in [Vec3A::X, Vec3A::Y, Vec3A::Z] {
            let a = edge.cross(axis);
            let (d0, d1, d2) = (a.dot(p[0]), a.dot(p[1]), a.dot(p[2]));
            let r = h.dot(a.abs());
            let t = tol * a.abs().element_sum();
            if d0.min(d1).min(d2) > r + t || d0.max(d1).max(d2) < -r - t {
                return false;
            }
        }
    }
    true
}
