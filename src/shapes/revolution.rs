//! Surface of revolution: a profile curve in the xy-plane (z = 0) revolved about the y axis,
//! `S(s, theta) = (x(s) cos theta, y(s), x(s) sin theta)`, intersected exactly.
//!
//! **Intersection** (object space, f64). The ray walks the profile's ring tree (`profile_tree.rs`) nearest first;
//! in each leaf ring it meets, Newton iteration on `(s, theta, t)` (`newton.rs`) starts from seeds taken from the
//! leaf's chord: the ray meets the cone (cylinder, disc) that the chord sweeps in closed form (a quadratic in
//! `t`), and each such root within the ring's intervals is a seed within the leaf's flatness of the true root;
//! an interval with no chord root (a ray grazing the bulge of the curve beyond its chord) is seeded at its middle.
//! Any converged root with `0 < t < tmax` is a true root and is kept if nearest; since every root lies in the ring
//! interval of its own leaf and leaves are visited nearest first until one starts beyond the best hit, the nearest
//! root is found whenever each leaf's Newton finds its own roots. Roots closer than `4e-10` of the object's size to
//! the ray origin are rejected (a ray starting on the surface does not hit itself).
//!
//! **Surface data.** Parameters `(s, theta)` travel in [`Hit`](crate::primitives::Hit) (`b1`, `b2`); the point is
//! `S(s, theta)` evaluated in f64 and mapped to world space in f64, then rounded to f32, so it lies on the surface
//! up to that rounding: its error bound is `2^-23 |p|` per coordinate plus `1e-9` of the world size (f64 rounding
//! and the iteration's tolerance), the bound secondary rays are offset by. The normal is analytic: the profile's
//! left normal `(-y', x')` revolved, `(-y' cos, x', -y' sin)`, outward for a profile drawn clockwise about the
//! solid (the 6.837 files' convention), defined on the axis too (poles); where the profile's derivative vanishes
//! (a triple control point: a cusp) the one-sided chord over `1e-4` of a segment replaces it. `uv = (theta / 2 pi,
//! s / segments)`: u goes around, v along the profile; `dpdu = 2 pi S_theta`, `dpdv = segments S_s`.

use super::curve::Curve;
use super::newton::{NewtonTol, ParamSurface, other_root_offset, solve};
use super::profile_tree::{Leaf, ProfileTree, RingRay};
use super::strip::Spans;
use super::{AnalyticShape, ShapeHit, ShapePoint};
use crate::geometry::{Bounds, Ray};
use glam::{DAffine3, DVec3, Mat3A, Vec2, Vec3A};
use std::f64::consts::TAU;

/// A surface of revolution with its seeding structure and transform.
#[derive(Clone, Debug)]
pub struct Revolution {
    profile: Curve,
    tree: ProfileTree,
    world_from_object: DAffine3,
    object_from_world: DAffine3,
    /// Linear part of `world_from_object` (for tangents) and its inverse transpose (for normals), f32.
    linear: Mat3A,
    normal_to_world: Mat3A,
    bounds: Bounds,
    /// Size of the profile (largest extent of its control points' box, and the radius).
    size: f64,
    pub material: u32,
    pub light: u32,
}

/// The surface in object space for the Newton iteration.
struct RevSurface<'a> {
    profile: &'a Curve,
    s_max: f64,
}

impl ParamSurface for RevSurface<'_> {
    #[inline]
    fn eval(&self, s: f64, theta: f64) -> (DVec3, DVec3, DVec3) {
        let (i, w) = self.profile.locate(s);
        let seg = &self.profile.bezier_segments()[i];
        let p = super::curve::bezier(seg, w);
        let dp = super::curve::bezier_d1(seg, w);
        let (sn, cs) = theta.sin_cos();
        (
            DVec3::new(p.x * cs, p.y, p.x * sn),
            DVec3::new(dp.x * cs, dp.y, dp.x * sn),
            DVec3::new(-p.x * sn, 0.0, p.x * cs),
        )
    }

    #[inline]
    fn clamp(&self, s: f64, theta: f64) -> (f64, f64) {
        (s.clamp(0.0, self.s_max), theta)
    }

    #[inline]
    fn max_step(&self) -> (f64, f64) {
        (0.5, 1.0)
    }

    fn second(&self, s: f64, theta: f64) -> (DVec3, DVec3, DVec3) {
        let (i, w) = self.profile.locate(s);
        let seg = &self.profile.bezier_segments()[i];
        let p = super::curve::bezier(seg, w);
        let dp = super::curve::bezier_d1(seg, w);
        let ddp = super::curve::bezier_d2(seg, w);
        let (sn, cs) = theta.sin_cos();
        (
            DVec3::new(ddp.x * cs, ddp.y, ddp.x * sn),
            DVec3::new(-dp.x * sn, 0.0, dp.x * cs),
            DVec3::new(-p.x * cs, 0.0, -p.x * sn),
        )
    }
}

impl Revolution {
    /// A revolution of `profile` (z = 0 checked by the loader) under `world_from_object`.
    pub fn new(profile: Curve, world_from_object: DAffine3, material: u32, light: u32) -> Revolution {
        let (lo, hi) = profile.hull_bounds();
        let r = lo.x.abs().max(hi.x.abs());
        let size = (hi - lo).max_element().max(r).max(f64::MIN_POSITIVE);
        let tree = ProfileTree::build(&profile, size);
        let ring = tree.root_ring();
        let obj_lo = DVec3::new(-ring.r_hi, ring.y_lo, -ring.r_hi);
        let obj_hi = DVec3::new(ring.r_hi, ring.y_hi, ring.r_hi);
        let bounds = super::profile_tree::world_box(&world_from_object, obj_lo, obj_hi);
        let inv = world_from_object.inverse();
        let linear = Mat3A::from(world_from_object.matrix3.as_mat3());
        let normal_to_world = Mat3A::from(inv.matrix3.transpose().as_mat3());
        Revolution {
            profile,
            tree,
            world_from_object,
            object_from_world: inv,
            linear,
            normal_to_world,
            bounds,
            size,
            material,
            light,
        }
    }

    pub fn profile(&self) -> &Curve {
        &self.profile
    }

    /// Leaves and nodes of the seeding structure (for statistics).
    pub fn seeding_stats(&self) -> (usize, usize) {
        (self.tree.leaves.len(), self.tree.num_nodes())
    }

    pub fn world_from_object(&self) -> &DAffine3 {
        &self.world_from_object
    }

    fn surface_fn(&self) -> RevSurface<'_> {
        RevSurface { profile: &self.profile, s_max: self.profile.num_segments() as f64 }
    }

    /// Nearest root in `(tmin, tmax)` of the object-space ray, `(s, theta, t)`; with `any`, the first one found.
    fn query(&self, o: DVec3, d: DVec3, tmax: f64, any: bool) -> Option<(f64, f64, f64)> {
        let ray = RingRay::new(o, d);
        let surf = self.surface_fn();
        let scale = self.size.max(o.length() * 1e-3);
        let tol = NewtonTol { stop: 1e-13 * scale, accept: 1e-9 * scale, max_iter: 16 };
        let dl = d.length();
        let tmin = 4e-10 * scale / dl;
        // Roots this close to the origin are the surface a ray starts on.
        let self_eps = 1e-6 * scale / dl;
        let mut best: Option<(f64, f64, f64)> = None;
        let mut best_t = tmax;
        let best_cell = std::cell::Cell::new(tmax);
        self.tree.traverse(
            &ray,
            tmin,
            || best_cell.get(),
            |leaf, iv| {
                let spans = match &leaf.strip {
                    Some(strip) => strip.clip(&ray, &iv.0[..iv.1]),
                    None => {
                        let mut s = Spans::EMPTY;
                        s.iv[..iv.1].copy_from_slice(&iv.0[..iv.1]);
                        s.n = iv.1;
                        s
                    }
                };
                let mut roots = [0.0f64; 2];
                let nroots = chord_cone_roots(leaf.ctrl[0], leaf.ctrl[3], &ray, &mut roots);
                // Split the spans where the ray is closest to the axis: on each side the ray's distance from the axis
                // is monotone, so a flat piece is crossed once except near tangency.
                let (qa, tc, _) = ray.centered();
                let tc = if qa > 0.0 { tc } else { f64::NEG_INFINITY };
                let mut pieces = [(0.0f64, 0.0f64); 8];
                let mut np = 0;
                for &(t0, t1) in spans.as_slice() {
                    if tc > t0 && tc < t1 {
                        pieces[np] = (t0, tc);
                        pieces[np + 1] = (tc, t1);
                        np += 2;
                    } else {
                        pieces[np] = (t0, t1);
                        np += 1;
                    }
                }
                for &(t0, t1) in &pieces[..np] {
                    if t0 > best_t {
                        break;
                    }
                    // The root Newton reaches from `t`: kept if nearest; `Some((root, at_origin))` if it is this
                    // leaf's root within the span, usable or at the origin of a ray starting on the surface.
                    let mut try_seed = |t: f64| -> Option<((f64, f64, f64), bool)> {
                        let r = solve(&surf, o, d, seed_at(leaf, &ray, t), &tol);
                        let (s, th, tr) = r?;
                        if tr > tmin && tr < best_t {
                            best_t = tr;
                            best = Some((s, th, tr));
                        }
                        let slack = 1e-9 * (leaf.s1 - leaf.s0);
                        let w = 1e-6 * (t1 - t0) + tol.accept / dl;
                        // The root at the origin of a ray starting on the surface counts for every leaf near it.
                        let at_origin = tr.abs() <= self_eps;
                        (at_origin
                            || (s >= leaf.s0 - slack
                                && s <= leaf.s1 + slack
                                && tr > tmin
                                && tr >= t0 - w
                                && tr <= t1 + w))
                            .then_some(((s, th, tr), at_origin))
                    };
                    // Seeds: the chord's roots in the span, else its middle.
                    let mut own: Option<((f64, f64, f64), bool)> = None;
                    let mut seeded = false;
                    for &t in &roots[..nroots] {
                        if t >= t0 && t <= t1 {
                            let r = try_seed(t);
                            own = own.or(r);
                            seeded = true;
                        }
                    }
                    if !seeded {
                        own = try_seed(0.5 * (t0 + t1));
                    }
                    let w = t1 - t0;
                    match own {
                        // The ray starts on this leaf: it meets it again only where the surface curves back.
                        Some(((s, th, t), true)) => {
                            let (dt, _) = other_root_offset(&surf, s, th, d).unwrap_or((f64::INFINITY, 0.0));
                            let again = dt > 0.0 && t + dt < t1 && try_seed(t + dt).is_some_and(|r| !r.1);
                            // Otherwise look for a crossing beyond the origin in one dimension (thoroughly when the
                            // ray leaves nearly along the band).
                            let from = t0.max(4.0 * self_eps);
                            if !again && from < t1 {
                                let samples = if runs_along(leaf, &ray, from, t1) { 9 } else { 3 };
                                let mut seeds = [0.0f64; 4];
                                let k = isolate_crossings(leaf, &ray, from, t1, samples, &mut seeds);
                                for &t in &seeds[..k] {
                                    try_seed(t);
                                }
                            }
                        }
                        // A root well inside the span may hide a nearer one: a ray cutting through a band twice (try
                        // from the span's start), or grazing it (try where the surface's curvature brings it back).
                        Some(((s, th, t), false)) => {
                            let (dt, cos) = other_root_offset(&surf, s, th, d).unwrap_or((f64::INFINITY, 0.0));
                            if dt < 0.0 && t + dt > t0 {
                                try_seed(t + dt);
                            }
                            if t > t0 + 0.1 * w || cos.abs() < 0.05 {
                                try_seed(t0 + 1e-3 * (t - t0));
                            }
                        }
                        // No seed reached this leaf's root: more seeds across the span.
                        None => {
                            let mut found = false;
                            for f in [0.05, 0.5, 0.95] {
                                if try_seed(t0 + f * w).is_some() {
                                    found = true;
                                    break;
                                }
                            }
                            // Still nothing, and the ray runs along the leaf (grazing the band: two close roots
                            // that seeds far from them miss): isolate its crossings in one dimension.
                            if !found && runs_along(leaf, &ray, t0, t1) {
                                let mut seeds = [0.0f64; 4];
                                let k = isolate_crossings(leaf, &ray, t0, t1, 9, &mut seeds);
                                for &t in &seeds[..k] {
                                    try_seed(t);
                                }
                            }
                        }
                    }
                }
                best_cell.set(best_t);
                !(any && best.is_some())
            },
        );
        best
    }

    fn object_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        let o = self.object_from_world.transform_point3(ray.origin.as_dvec3());
        let d = self.object_from_world.transform_vector3(ray.dir.as_dvec3());
        (o, d)
    }

    /// The profile tangent at `s`; at a zero derivative (a cusp), the one-sided chord.
    fn profile_tangent(&self, s: f64) -> DVec3 {
        let dp = self.profile.derivative(s);
        if dp.length() > 1e-9 * self.size {
            return dp;
        }
        let n = self.profile.num_segments() as f64;
        let h = 1e-4;
        if s + h <= n {
            self.profile.eval(s + h) - self.profile.eval(s)
        } else {
            self.profile.eval(s) - self.profile.eval(s - h)
        }
    }
}

/// The seed `(s, theta, t)` at ray parameter `t` in a leaf: the angle of the ray point, and the profile
/// parameter of its projection onto the leaf's chord.
#[inline]
fn seed_at(leaf: &Leaf, ray: &RingRay, t: f64) -> (f64, f64, f64) {
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
fn invert_cubic(l: &[f64; 4], target: f64) -> f64 {
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
fn runs_along(leaf: &Leaf, ray: &RingRay, t0: f64, t1: f64) -> bool {
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
/// 9); each sign
/// change is bisected to a root, and an interior extremum of `|g|` is searched (golden section) for a dip through
/// zero (two close roots: a grazing ray). Writes up to 4 ray parameters, returns how many.
fn isolate_crossings(leaf: &Leaf, ray: &RingRay, t0: f64, t1: f64, k: usize, out: &mut [f64; 4]) -> usize {
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
        for _ in 0..40 {
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
    for i in 1..k - 1 {
        let (gl, gm, gr) = (gs[i - 1], gs[i], gs[i + 1]);
        let same = (gl > 0.0) == (gm > 0.0) && (gm > 0.0) == (gr > 0.0);
        if same && gm.abs() < gl.abs() && gm.abs() < gr.abs() {
            // Golden-section search for the extremum of |g| between the neighbours.
            let s = if gm > 0.0 { 1.0 } else { -1.0 };
            let (mut lo, mut hi) = (ts[i - 1], ts[i + 1]);
            let r = 0.618_033_988_749_895;
            for _ in 0..30 {
                let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
                if s * g(x1) < s * g(x2) {
                    hi = x2;
                } else {
                    lo = x1;
                }
            }
            let te = 0.5 * (lo + hi);
            if (g(te) > 0.0) != (gm > 0.0) {
                push(bisect(ts[i - 1], te, gl));
                push(bisect(te, ts[i + 1], g(te)));
            }
        }
    }
    n
}

/// Roots `t` of the ray with the surface swept by the segment `a b` of the half-plane (a cone, cylinder or disc).
/// Returns how many were written (0 to 2).
fn chord_cone_roots(a: DVec3, b: DVec3, ray: &RingRay, out: &mut [f64; 2]) -> usize {
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

impl AnalyticShape for Revolution {
    fn bounds(&self) -> Bounds {
        self.bounds
    }

    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.object_ray(ray);
        let (s, th, t) = self.query(o, d, ray.tmax as f64, false)?;
        let t32 = t as f32;
        (t32 < ray.tmax && t32 > 0.0).then(|| ShapeHit { t: t32, u: s as f32, v: th.rem_euclid(TAU) as f32 })
    }

    #[inline]
    fn occludes(&self, ray: &Ray) -> bool {
        let (o, d) = self.object_ray(ray);
        self.query(o, d, ray.tmax as f64, true).is_some_and(|(_, _, t)| (t as f32) < ray.tmax)
    }

    fn overlaps_box(&self, b: &Bounds) -> bool {
        self.tree.overlaps(&self.world_from_object, b)
    }

    fn clip_bounds(&self, voxel: &Bounds) -> Option<Bounds> {
        self.tree.clipped(&self.world_from_object, voxel)
    }

    fn surface(&self, _ray: &Ray, hit: &ShapeHit) -> ShapePoint {
        let (s, theta) = (hit.u as f64, hit.v as f64);
        let (p_obj, s_s, s_theta) = self.surface_fn().eval(s, theta);
        let pw = self.world_from_object.transform_point3(p_obj);
        let p = Vec3A::from(pw.as_vec3());
        let world_size = self.bounds.diagonal().length();
        let p_err = p.abs() * f32::EPSILON + Vec3A::splat(1e-9 * world_size);
        let tan = self.profile_tangent(s);
        let (sn, cs) = theta.sin_cos();
        let n_obj = DVec3::new(-tan.y * cs, tan.x, -tan.y * sn);
        let n = (self.normal_to_world * Vec3A::from(n_obj.as_vec3())).normalize_or(Vec3A::Y);
        let segs = self.profile.num_segments() as f64;
        let dpdu = self.linear * Vec3A::from((s_theta * TAU).as_vec3());
        let dpdv = self.linear * Vec3A::from((s_s * segs).as_vec3());
        ShapePoint { p, p_err, n, uv: Vec2::new((theta / TAU) as f32, (s / segs) as f32), dpdu, dpdv }
    }

    fn point_at_uv(&self, uv: Vec2) -> Option<ShapePoint> {
        let segs = self.profile.num_segments() as f64;
        let hit = ShapeHit { t: 0.0, u: (uv.y as f64 * segs) as f32, v: (uv.x as f64 * TAU) as f32 };
        Some(self.surface(&Ray::new(Vec3A::ZERO, Vec3A::X), &hit))
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn light(&self) -> u32 {
        self.light
    }
}
