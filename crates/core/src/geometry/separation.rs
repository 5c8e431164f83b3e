//! Whether two convex polytopes, each given as the convex hull of a few points, are apart by more than a gap:
//! the Gilbert–Johnson–Keerthi distance algorithm (Gilbert, Johnson & Keerthi 1988) on the Minkowski difference
//! `A - B`, in `f64`, with the closest point of each simplex found by trying the faces that hold its newest point
//! (at most 7, for a tetrahedron), after a first try along the line between the centroids. GJK and the centroids
//! only *propose* a direction: the answer is `true` only after the two sets' extents along that direction have
//! been checked to be apart by more than the gap, so an inexact or unconverged iteration can only answer `false`.
//! Used by [`crate::lights::ClearShadows`] to prove that no primitive can block a family of shadow rays; `false`
//! there means "trace them".

use glam::DVec3;

/// The most GJK iterations; an unconverged run answers "not proven apart".
const MAX_ITERATIONS: usize = 48;

/// True when the convex hulls of `a` and `b` (non-empty) are at least `gap` apart along some direction, checked
/// directly on the points: there is a unit `v` with `min(a . v) - max(b . v) > gap` or the same with the roles
/// swapped. The direction from `b`'s centroid to `a`'s is tried first (it settles most of the pairs the shadow
/// proofs ask about, without GJK's iterations), then GJK's. False when they touch, overlap, or neither direction
/// separates them (conservative).
pub fn hulls_apart(a: &[DVec3], b: &[DVec3], gap: f64) -> bool {
    if a.is_empty() || b.is_empty() {
        return false;
    }
    // The direction between the two sets' centroids first: it separates many pairs without GJK's iterations.
    let centre = |p: &[DVec3]| p.iter().copied().sum::<DVec3>() / p.len() as f64;
    let c = centre(a) - centre(b);
    if apart_along(a, b, c, gap) {
        return true;
    }
    match closest_difference(a, b) {
        Some(v) => apart_along(a, b, v, gap) || apart_along(b, a, v, gap),
        None => false,
    }
}

/// True when `a` lies beyond `b` along `v`, by more than `gap` (measured along the unit direction of `v`).
fn apart_along(a: &[DVec3], b: &[DVec3], v: DVec3, gap: f64) -> bool {
    let len = v.length();
    if !(len > 0.0 && len.is_finite()) {
        return false;
    }
    let u = v / len;
    let min_a = a.iter().map(|p| p.dot(u)).fold(f64::INFINITY, f64::min);
    let max_b = b.iter().map(|p| p.dot(u)).fold(f64::NEG_INFINITY, f64::max);
    min_a - max_b > gap
}

/// The point of `pts` furthest along `d`.
fn support(pts: &[DVec3], d: DVec3) -> DVec3 {
    let mut best = pts[0];
    let mut best_dot = best.dot(d);
    for &p in &pts[1..] {
        let x = p.dot(d);
        if x > best_dot {
            best = p;
            best_dot = x;
        }
    }
    best
}

/// A simplex of GJK: up to four points.
#[derive(Clone, Copy)]
struct Simplex {
    points: [DVec3; 4],
    len: usize,
}

/// GJK: the point of the hull of `{a - b}` closest to the origin, if the iteration isolates it from the origin
/// (None when the origin is inside or the run does not settle). The returned vector points from `b` towards `a`.
fn closest_difference(a: &[DVec3], b: &[DVec3]) -> Option<DVec3> {
    let mut v = a[0] - b[0];
    let mut simplex = Simplex { points: [v; 4], len: 1 };
    for _ in 0..MAX_ITERATIONS {
        let vv = v.length_squared();
        if vv <= 0.0 || !vv.is_finite() {
            return None;
        }
        let w = support(a, -v) - support(b, v);
        // No point of the difference is closer along v than v itself (up to rounding): v is the closest point.
        if vv - v.dot(w) <= 1e-12 * vv || simplex.points[..simplex.len].contains(&w) {
            return Some(v);
        }
        simplex.points[simplex.len] = w;
        simplex.len += 1;
        let (closest, kept) = closest_on_simplex(&simplex)?;
        if closest.length_squared() >= vv {
            // No progress: rounding; v is as close as this iteration gets.
            return Some(v);
        }
        simplex = kept;
        v = closest;
        if simplex.len == 4 {
            return None;
        }
    }
    None
}

/// The closest point to the origin of the simplex `s` (1-4 points, the last the support point just added) and the
/// smallest face of it that contains that point, by trying every face that holds the new point: the affine closest
/// point of each, kept when its barycentric weights are all non-negative. The faces without it are faces of the
/// simplex before, none of them closer than the point GJK had (the caller stops unless the new one is closer), so
/// they are skipped: 7 faces of a tetrahedron instead of 15. None when the origin is inside a tetrahedron (or the
/// faces are all degenerate).
fn closest_on_simplex(s: &Simplex) -> Option<(DVec3, Simplex)> {
    let n = s.len;
    let newest = 1u32 << (n - 1);
    let mut best: Option<(f64, DVec3, u32)> = None;
    for mask in (1u32..(1 << n)).filter(|m| m & newest != 0) {
        let mut face = Simplex { points: [DVec3::ZERO; 4], len: 0 };
        for i in (0..n).filter(|i| mask & (1 << i) != 0) {
            face.points[face.len] = s.points[i];
            face.len += 1;
        }
        let Some(p) = affine_closest(&face.points[..face.len]) else { continue };
        let d = p.length_squared();
        if best.is_none_or(|(bd, _, bm)| d < bd || (d == bd && mask.count_ones() < bm.count_ones())) {
            best = Some((d, p, mask));
        }
    }
    let (d, p, mask) = best?;
    if n == 4 && mask == 0b1111 && d == 0.0 {
        return None;
    }
    let mut kept = Simplex { points: [DVec3::ZERO; 4], len: 0 };
    for i in (0..n).filter(|i| mask & (1 << i) != 0) {
        kept.points[kept.len] = s.points[i];
        kept.len += 1;
    }
    Some((p, kept))
}

/// The point of the affine hull of `face` (1-4 points) closest to the origin, if its barycentric weights are all
/// non-negative (it lies in the face); for a tetrahedron, the origin itself when it lies inside.
fn affine_closest(face: &[DVec3]) -> Option<DVec3> {
    match face {
        [p] => Some(*p),
        [p, q] => {
            let e = *q - *p;
            let ee = e.length_squared();
            if ee <= 0.0 {
                return None;
            }
            let t = -p.dot(e) / ee;
            (0.0..=1.0).contains(&t).then(|| *p + e * t)
        }
        [p, q, r] => {
            let (e1, e2) = (*q - *p, *r - *p);
            let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
            let (b1, b2) = (-p.dot(e1), -p.dot(e2));
            let det = a11 * a22 - a12 * a12;
            if det <= 1e-18 * a11 * a22 {
                return None;
            }
            let s = (b1 * a22 - b2 * a12) / det;
            let t = (a11 * b2 - a12 * b1) / det;
            (s >= 0.0 && t >= 0.0 && s + t <= 1.0).then(|| *p + e1 * s + e2 * t)
        }
        [p, q, r, w] => {
            // The origin inside the tetrahedron: every face's plane has the origin on the side of the fourth point.
            let inside = [(p, q, r, w), (p, q, w, r), (p, r, w, q), (q, r, w, p)].iter().all(|(a, b, c, d)| {
                let n = (**b - **a).cross(**c - **a);
                let side_d = n.dot(**d - **a);
                let side_o = n.dot(-**a);
                side_d != 0.0 && side_o * side_d >= 0.0
            });
            inside.then_some(DVec3::ZERO)
        }
        _ => None,
    }
}
