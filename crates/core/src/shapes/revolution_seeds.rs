//! Seeds for the Newton iteration on a surface of revolution, per leaf of its profile tree (`revolution.rs`):
//! - [`chord_cone_roots`]: where the ray meets the cone (cylinder, disc) the leaf's chord sweeps, in closed form;
//! - [`seed_at`]: the parameters `(s, theta)` of the ray's point at a given `t`, the profile parameter found by
//!   inverting the leaf's projection onto its chord ([`invert_cubic`]: near repeated control points the
//!   parametrisation is far from uniform);
//! - [`runs_along`] and [`isolate_crossings`]: for a ray that runs along a band (grazing it), its crossings of the
//!   leaf found in one dimension, where seeds far from two close roots would miss them.

use super::profile_tree::{Leaf, RingRay};
use glam::DVec3;

/// The seed `(s, theta, t)` at ray parameter `t` in a leaf: the angle of the ray point, and the profile
/// parameter of its projection onto the leaf's chord.
#[inline]
pub fn seed_at(leaf: &Leaf, ray: &RingRay, t: f64) -> (f64, f64, f64) {
    let (a, b) = (leaf.ctrl[0], leaf.ctrl[3]);
    let e = b - a;
    let len2 = e.x * e.x + e.y * e.y;
    let p = ray.o + ray.d * t;
    let neg = a.x + b.x < 0.0;
    let w = if len2 == 0.0 {
        0.5
    } else {
        let rho = ray.rho2(t).max(0.0).sqrt();
        // Points with negative profile x sit at radius -x.
        let x = if neg { -rho } else { rho };
        let target = (x - a.x) * e.x + (p.y - a.y) * e.y;
        // The leaf's parameter whose point projects there: the projection of the Bézier onto the chord is a
        // cubic in the leaf's parameter, far from linear near repeated control points (poles, cusps).
        let l = leaf.ctrl.map(|c| (c.x - a.x) * e.x + (c.y - a.y) * e.y);
        invert_cubic(&l, target)
    };
    let theta = if neg { (-p.z).atan2(-p.x) } else { p.z.atan2(p.x) };
    (leaf.s0 + w * (leaf.s1 - leaf.s0), theta, t)
}

/// The `w` in `[0, 1]` where the Bernstein cubic with coefficients `l` takes the value `target` (the
/// coefficients of a flat leaf increase, so the cubic is monotone): Newton steps kept inside a shrinking
/// bisection bracket, clamped to the ends.
pub fn invert_cubic(l: &[f64; 4], target: f64) -> f64 {
    let f = |w: f64| {
        let m = 1.0 - w;
        l[0] * m * m * m + 3.0 * l[1] * m * m * w + 3.0 * l[2] * m * w * w + l[3] * w * w * w - target
    };
    let df = |w: f64| {
        let m = 1.0 - w;
        3.0 * ((l[1] - l[0]) * m * m + 2.0 * (l[2] - l[1]) * m * w + (l[3] - l[2]) * w * w)
    };
    let increasing = l[3] >= l[0];
    let below = |v: f64| if increasing { v < 0.0 } else { v > 0.0 };
    if !below(f(0.0)) {
        return 0.0;
    }
    if below(f(1.0)) {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut w = (target - l[0]) / (l[3] - l[0]);
    for _ in 0..40 {
        if !(w > lo && w < hi) {
            w = 0.5 * (lo + hi);
        }
        let v = f(w);
        if below(v) {
            lo = w;
        } else {
            hi = w;
        }
        let dv = df(w);
        let next = if dv != 0.0 { w - v / dv } else { 0.5 * (lo + hi) };
        if (next - w).abs() < 1e-12 || hi - lo < 1e-12 {
            w = next;
            break;
        }
        w = next;
    }
    w.clamp(lo, hi)
}

/// Does the ray, over `[t0, t1]`, travel along the leaf's chord more than 4 times the leaf's thickness (the
/// spread of its control points across the chord)? A ray crossing the band transversally does not: one seed
/// finds its root.
pub fn runs_along(leaf: &Leaf, ray: &RingRay, t0: f64, t1: f64) -> bool {
    let (a, b) = (leaf.ctrl[0], leaf.ctrl[3]);
    let sx = if a.x + b.x < 0.0 { -1.0 } else { 1.0 };
    let (ex, ey) = (sx * (b.x - a.x), b.y - a.y);
    let len = (ex * ex + ey * ey).sqrt();
    if len == 0.0 {
        return true;
    }
    let (e, m) = ((ex / len, ey / len), (-ey / len, ex / len));
    let mu = leaf.ctrl.map(|c| (sx * (c.x - a.x)) * m.0 + (c.y - a.y) * m.1);
    let h = mu.iter().fold(f64::NEG_INFINITY, |x, &y| x.max(y)) - mu.iter().fold(f64::INFINITY, |x, &y| x.min(y));
    let along = |t: f64| {
        let rho = ray.rho2(t).max(0.0).sqrt();
        rho * e.0 + (ray.o.y + t * ray.d.y) * e.1
    };
    (along(t1) - along(t0)).abs() > 4.0 * h
}

/// Where along `[t0, t1]` the ray crosses the leaf, found in one dimension: in the chord's frame the leaf is a
/// graph `mu = phi(lambda)` (flat leaves are monotone along their chord), so `g(t) = mu(t) - phi(lambda(t))`
/// changes sign where the ray's point in the half-plane crosses the curve. `g` is sampled at `k` points (at most
/// 9); each sign change is bisected to a root, and around each sample where `|g|` is locally smallest (the ends
/// included) a golden-section search looks for a dip through zero (two close roots: a grazing ray). Writes up to
/// 4 ray parameters, returns how many.
pub fn isolate_crossings(leaf: &Leaf, ray: &RingRay, t0: f64, t1: f64, k: usize, out: &mut [f64; 4]) -> usize {
    let (a, b) = (leaf.ctrl[0], leaf.ctrl[3]);
    let neg = a.x + b.x < 0.0;
    let sx = if neg { -1.0 } else { 1.0 };
    let (ax, ay) = (sx * a.x, a.y);
    let (ex, ey) = (sx * b.x - ax, b.y - ay);
    let len = (ex * ex + ey * ey).sqrt();
    if len == 0.0 || t1 <= t0 || t1.is_nan() || t0.is_nan() {
        return 0;
    }
    let (e, m) = ((ex / len, ey / len), (-ey / len, ex / len));
    let l = leaf.ctrl.map(|c| (sx * c.x - ax) * e.0 + (c.y - ay) * e.1);
    let mu = leaf.ctrl.map(|c| (sx * c.x - ax) * m.0 + (c.y - ay) * m.1);
    let bern = |c: &[f64; 4], w: f64| {
        let v = 1.0 - w;
        c[0] * v * v * v + 3.0 * c[1] * v * v * w + 3.0 * c[2] * v * w * w + c[3] * w * w * w
    };
    let g = |t: f64| {
        let rho = ray.rho2(t).max(0.0).sqrt();
        let y = ray.o.y + t * ray.d.y;
        let (px, py) = (rho - ax, y - ay);
        let lt = px * e.0 + py * e.1;
        let mt = px * m.0 + py * m.1;
        mt - bern(&mu, invert_cubic(&l, lt))
    };
    let bisect = |mut lo: f64, mut hi: f64, glo: f64| {
        for _ in 0..24 {
            let mid = 0.5 * (lo + hi);
            if (g(mid) > 0.0) == (glo > 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    const MAX: usize = 9;
    let k = k.clamp(2, MAX);
    let ts: [f64; MAX] = std::array::from_fn(|i| t0 + (t1 - t0) * i.min(k - 1) as f64 / (k - 1) as f64);
    let gs: [f64; MAX] = ts.map(g);
    let mut n = 0;
    let mut push = |t: f64| {
        if n < out.len() {
            out[n] = t;
            n += 1;
        }
    };
    for i in 0..k - 1 {
        if (gs[i] > 0.0) != (gs[i + 1] > 0.0) {
            push(bisect(ts[i], ts[i + 1], gs[i]));
        }
    }
    // Local minima of |g| among the samples (the ends included: a dip may lie in the last interval) with no sign
    // change beside them: search the neighbouring intervals for a dip through zero.
    for i in 0..k {
        let gm = gs[i];
        let (l, r) = (i.saturating_sub(1), (i + 1).min(k - 1));
        let side = |j: usize| (gs[j] > 0.0) == (gm > 0.0) && gm.abs() <= gs[j].abs();
        if !(side(l) && side(r)) {
            continue;
        }
        // Golden-section search for the extremum of g towards zero over [t_l, t_r].
        let s = if gm > 0.0 { 1.0 } else { -1.0 };
        let (mut lo, mut hi) = (ts[l], ts[r]);
        let ratio = 0.618_033_988_749_895;
        for _ in 0..30 {
            let (x1, x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
            if s * g(x1) < s * g(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        let te = 0.5 * (lo + hi);
        let ge = g(te);
        if (ge > 0.0) != (gm > 0.0) {
            push(bisect(ts[l], te, gs[l]));
            push(bisect(te, ts[r], ge));
        }
    }
    n
}

/// Roots `t` of the ray with the surface swept by the segment `a b` of the half-plane (a cone, cylinder or disc).
/// Returns how many were written (0 to 2).
pub fn chord_cone_roots(a: DVec3, b: DVec3, ray: &RingRay, out: &mut [f64; 2]) -> usize {
    let e = b - a;
    // Line m . (rho, y) = k with m normal to e.
    let (mx, my) = (-e.y, e.x);
    if mx == 0.0 && my == 0.0 {
        return 0;
    }
    let k = mx * a.x + my * a.y;
    let (o, d) = (ray.o, ray.d);
    // mx^2 rho^2(t) = (K - L t)^2 with K = k - my oy, L = my dy; in tau = t - tc, rho^2 = ra tau^2 + cmin.
    let (ra, tc, cmin) = ray.centered();
    let kk = k - my * o.y - my * d.y * tc;
    let ll = my * d.y;
    let qa = mx * mx * ra - ll * ll;
    let qb = kk * ll;
    let qc = mx * mx * cmin - kk * kk;
    let mut n = 0;
    let mut push = |tau: f64| {
        let t = tau + tc;
        // Keep roots on the chord's side of the axis and within the chord (with a margin).
        let y = o.y + t * d.y;
        let rho = ray.rho2(t).max(0.0).sqrt();
        let x = if a.x + b.x < 0.0 { -rho } else { rho };
        let len2 = e.x * e.x + e.y * e.y;
        let lambda = ((x - a.x) * e.x + (y - a.y) * e.y) / len2;
        // The other nappe of a double cone solves the squared equation too: keep points on the chord's line.
        let off_line = ((x - a.x) * mx + (y - a.y) * my).abs() > 0.1 * len2;
        if t.is_finite() && (-0.25..=1.25).contains(&lambda) && !off_line && n < 2 {
            out[n] = t;
            n += 1;
        }
    };
    if qa.abs() <= 1e-12 * (qb.abs() + qc.abs()).max(f64::MIN_POSITIVE) {
        if qb != 0.0 {
            push(-qc / (2.0 * qb));
        }
        return n;
    }
    let mut disc = qb * qb - qa * qc;
    if disc < 0.0 && disc > -1e-12 * (qb * qb + (qa * qc).abs()) {
        disc = 0.0;
    }
    if disc < 0.0 {
        return 0;
    }
    let q = -(qb + disc.sqrt().copysign(qb));
    if q == 0.0 {
        push(0.0);
        return n;
    }
    let (t0, t1) = (q / qa, qc / q);
    push(t0.min(t1));
    push(t0.max(t1));
    n
}
