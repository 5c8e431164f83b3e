//! Bicubic Bézier patch `S(u, v) = sum_ij B_i(v) B_j(u) P[4 i + j]` (the 6.837 file order: four rows of four
//! points, u along a row), intersected exactly.
//!
//! Bézier patches are affine invariant, so the control points are transformed to world space once and the patch
//! is intersected there, with no per-ray transform.
//!
//! **Seeding structure**: a quadtree of sub-patches from de Casteljau subdivision in u and v, refined until each
//! sub-patch's control points lie within [`FLATNESS`] of the patch size from the bilinear patch of its corners (at
//! least [`MIN_DEPTH`], at most [`MAX_DEPTH`] levels). Each node holds the box of its control points (which
//! contains the sub-patch: convex hull property); each leaf also the slab around its central tangent plane that
//! holds its control points, both padded against rounding. Rays walk the boxes nearest first (slab tests in f64);
//! in each leaf they meet, the span inside box and slab is seeded where the ray crosses the central tangent plane
//! (projected on the leaf's parameters), else at its middle, and Newton iteration on `(u, v, t)` (`newton.rs`)
//! runs from there. As for revolutions: a root found well inside the span or at a grazing angle is followed by a
//! seed where the local curvature model puts the other root and one at the span's start; a span where no seed
//! reaches the leaf's own root gets seeds across it. Any converged root with `0 < t < tmax` is a true root; the
//! nearest is kept and boxes starting beyond it are skipped (after Martin et al. 2000, "Practical Ray Tracing of
//! Trimmed NURBS Surfaces", without trimming).
//!
//! **Surface data**: `uv` is the patch parameter; `dpdu = S_u`, `dpdv = S_v`; the normal `S_u x S_v` (at a
//! degenerate point, where that vanishes, the normal a little way towards the patch centre); the point `S(u, v)`
//! in f64 rounded to f32, error bound `2^-23 |p|` plus `1e-9` of the patch size.

use super::curve::{bezier, bezier_d1, split_bezier};
use super::newton::{NewtonTol, ParamSurface, other_root_offset, solve};
use super::{AnalyticShape, ShapeHit, ShapePoint};
use crate::geometry::{Bounds, Ray};
use glam::{DVec3, Vec2, Vec3A};

/// Subdivide until control points are within this fraction of the patch size from the corners' bilinear patch.
pub const FLATNESS: f64 = 2e-3;
/// Fewest subdivision levels of the seeding quadtree (the root alone is never a leaf).
pub const MIN_DEPTH: u32 = 1;
/// Most subdivision levels of the seeding quadtree (up to `4^6` leaves), whatever the flatness.
pub const MAX_DEPTH: u32 = 6;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Children `first..first + count` (count 0: a leaf; `first` is then the leaf index).
    first: u32,
    count: u32,
}

/// A flat sub-patch: its parameter domain, its frame at the centre (point and partial derivatives, for seeds)
/// and the slab `n . p in [lo, hi]` holding its control points (so the sub-patch: convex hull property) around
/// its central tangent plane.
#[derive(Clone, Copy, Debug)]
struct PatchLeaf {
    u0: f64,
    u1: f64,
    v0: f64,
    v1: f64,
    center: DVec3,
    su: DVec3,
    sv: DVec3,
    n: DVec3,
    lo: f64,
    hi: f64,
}

impl PatchLeaf {
    fn new(c: &[DVec3; 16], dom: (f64, f64, f64, f64), full: &[DVec3; 16], pad: f64) -> PatchLeaf {
        let (uc, vc) = (0.5 * (dom.0 + dom.1), 0.5 * (dom.2 + dom.3));
        let (center, su, sv) = patch_eval(full, uc, vc);
        let mut n = su.cross(sv).normalize_or_zero();
        if n == DVec3::ZERO {
            n = (c[3] - c[0]).cross(c[12] - c[0]).normalize_or_zero();
        }
        if n == DVec3::ZERO {
            n = DVec3::Z;
        }
        let (lo, hi) =
            c.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(n.dot(*p)), b.max(n.dot(*p))));
        PatchLeaf { u0: dom.0, u1: dom.1, v0: dom.2, v1: dom.3, center, su, sv, n, lo: lo - pad, hi: hi + pad }
    }

    /// The part of `[t0, t1]` where the ray is inside the slab.
    #[inline]
    fn clip(&self, o: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let (no, nd) = (self.n.dot(o), self.n.dot(d));
        if nd == 0.0 {
            return (no >= self.lo && no <= self.hi).then_some((t0, t1));
        }
        let (a, b) = ((self.lo - no) / nd, (self.hi - no) / nd);
        let (lo, hi) = (t0.max(a.min(b)), t1.min(a.max(b)));
        (lo <= hi).then_some((lo, hi))
    }

    /// A seed `(u, v, t)` at ray parameter `t`: the ray point projected on the central tangent plane, expressed in
    /// the central partial derivatives, clamped to the leaf.
    #[inline]
    fn seed(&self, o: DVec3, d: DVec3, t: f64) -> (f64, f64, f64) {
        let q = o + d * t - self.center;
        let (e, f, g) = (self.su.dot(self.su), self.su.dot(self.sv), self.sv.dot(self.sv));
        let det = e * g - f * f;
        let (uc, vc) = (0.5 * (self.u0 + self.u1), 0.5 * (self.v0 + self.v1));
        if det <= 0.0 {
            return (uc, vc, t);
        }
        let (p, r) = (q.dot(self.su), q.dot(self.sv));
        let (du, dv) = ((g * p - f * r) / det, (e * r - f * p) / det);
        ((uc + du).clamp(self.u0, self.u1), (vc + dv).clamp(self.v0, self.v1), t)
    }
}

/// A bicubic Bézier patch in world space with its seeding quadtree.
#[derive(Clone, Debug)]
pub struct BezierPatch {
    /// Control points, world space, row-major (`P[4 i + j]`, `j` along u).
    ctrl: [DVec3; 16],
    nodes: Vec<Node>,
    leaves: Vec<PatchLeaf>,
    bounds: Bounds,
    size: f64,
    /// Index into the scene's material table.
    pub material: u32,
    /// Area light slot, or [`crate::primitives::NO_LIGHT`].
    pub light: u32,
}

/// Evaluate a tensor-product patch given as 4 rows of 4 points.
#[inline]
pub fn patch_eval(ctrl: &[DVec3; 16], u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let mut col = [DVec3::ZERO; 4];
    let mut col_du = [DVec3::ZERO; 4];
    for i in 0..4 {
        let row = [ctrl[4 * i], ctrl[4 * i + 1], ctrl[4 * i + 2], ctrl[4 * i + 3]];
        col[i] = bezier(&row, u);
        col_du[i] = bezier_d1(&row, u);
    }
    (bezier(&col, v), bezier(&col_du, v), bezier_d1(&col, v))
}

impl ParamSurface for BezierPatch {
    #[inline]
    fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        patch_eval(&self.ctrl, u, v)
    }

    #[inline]
    fn clamp(&self, u: f64, v: f64) -> (f64, f64) {
        (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
    }

    #[inline]
    fn max_step(&self) -> (f64, f64) {
        (0.25, 0.25)
    }

    fn second(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let c = &self.ctrl;
        let (mut col_uu, mut col_u, mut col) = ([DVec3::ZERO; 4], [DVec3::ZERO; 4], [DVec3::ZERO; 4]);
        for i in 0..4 {
            let row = [c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]];
            col[i] = bezier(&row, u);
            col_u[i] = bezier_d1(&row, u);
            col_uu[i] = super::curve::bezier_d2(&row, u);
        }
        (bezier(&col_uu, v), bezier_d1(&col_u, v), super::curve::bezier_d2(&col, v))
    }
}

/// Split a patch in u (`true`) or v at the middle.
fn split_patch(c: &[DVec3; 16], in_u: bool) -> ([DVec3; 16], [DVec3; 16]) {
    let (mut a, mut b) = ([DVec3::ZERO; 16], [DVec3::ZERO; 16]);
    for k in 0..4 {
        let idx = |m: usize| if in_u { 4 * k + m } else { 4 * m + k };
        let curve = [c[idx(0)], c[idx(1)], c[idx(2)], c[idx(3)]];
        let (l, r) = split_bezier(&curve, 0.5);
        for m in 0..4 {
            a[idx(m)] = l[m];
            b[idx(m)] = r[m];
        }
    }
    (a, b)
}

fn is_flat(c: &[DVec3; 16], tol: f64) -> bool {
    let (p00, p03, p30, p33) = (c[0], c[3], c[12], c[15]);
    (0..16).all(|k| {
        let (i, j) = (k / 4, k % 4);
        let (u, v) = (j as f64 / 3.0, i as f64 / 3.0);
        let bil = (p00 * (1.0 - u) + p03 * u) * (1.0 - v) + (p30 * (1.0 - u) + p33 * u) * v;
        (c[k] - bil).length() <= tol
    })
}

fn ctrl_box(c: &[DVec3; 16], pad: f64) -> (DVec3, DVec3) {
    let lo = c.iter().fold(DVec3::splat(f64::INFINITY), |m, p| m.min(*p));
    let hi = c.iter().fold(DVec3::splat(f64::NEG_INFINITY), |m, p| m.max(*p));
    (lo - pad, hi + pad)
}

impl BezierPatch {
    /// A patch from 16 world-space control points (finite: checked by the loader).
    pub fn new(ctrl: [DVec3; 16], material: u32, light: u32) -> BezierPatch {
        let (lo, hi) = ctrl_box(&ctrl, 0.0);
        let size = (hi - lo).max_element().max(f64::MIN_POSITIVE);
        let pad = 1e-9 * size + 8.0 * f64::EPSILON * lo.abs().max(hi.abs()).max_element();
        let mut p =
            BezierPatch { ctrl, nodes: Vec::new(), leaves: Vec::new(), bounds: Bounds::EMPTY, size, material, light };
        p.nodes.push(Node { lo, hi, first: 0, count: 0 });
        p.build(0, &ctrl, (0.0, 1.0, 0.0, 1.0), 0, FLATNESS * size, pad);
        let root = p.nodes[0];
        let wpad = (root.lo.abs().max(root.hi.abs())) * 1e-6;
        p.bounds = Bounds::new(Vec3A::from((root.lo - wpad).as_vec3()), Vec3A::from((root.hi + wpad).as_vec3()));
        p
    }

    /// Fill node `me` for the sub-patch `c` over `dom = (u0, u1, v0, v1)`.
    fn build(&mut self, me: usize, c: &[DVec3; 16], dom: (f64, f64, f64, f64), depth: u32, tol: f64, pad: f64) {
        let (lo, hi) = ctrl_box(c, pad);
        if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && is_flat(c, tol)) {
            self.nodes[me] = Node { lo, hi, first: self.leaves.len() as u32, count: 0 };
            let full = self.ctrl;
            self.leaves.push(PatchLeaf::new(c, dom, &full, pad));
            return;
        }
        let (um, vm) = (0.5 * (dom.0 + dom.1), 0.5 * (dom.2 + dom.3));
        let (left, right) = split_patch(c, true);
        let (ll, lr) = split_patch(&left, false);
        let (rl, rr) = split_patch(&right, false);
        let first = self.nodes.len();
        self.nodes[me] = Node { lo, hi, first: first as u32, count: 4 };
        for _ in 0..4 {
            self.nodes.push(Node { lo, hi, first: 0, count: 0 });
        }
        self.build(first, &ll, (dom.0, um, dom.2, vm), depth + 1, tol, pad);
        self.build(first + 1, &lr, (dom.0, um, vm, dom.3), depth + 1, tol, pad);
        self.build(first + 2, &rl, (um, dom.1, dom.2, vm), depth + 1, tol, pad);
        self.build(first + 3, &rr, (um, dom.1, vm, dom.3), depth + 1, tol, pad);
    }

    /// Control points (world space).
    pub fn control_points(&self) -> &[DVec3; 16] {
        &self.ctrl
    }

    /// Leaves and nodes of the seeding structure (for statistics).
    pub fn seeding_stats(&self) -> (usize, usize) {
        (self.leaves.len(), self.nodes.len())
    }

    /// Nearest root `(u, v, t)` in `(tmin, tmax)`; with `any`, the first one found.
    fn query(&self, o: DVec3, d: DVec3, tmax: f64, any: bool) -> Option<(f64, f64, f64)> {
        let scale = self.size.max((o - self.ctrl[0]).length() * 1e-3);
        let tol = NewtonTol { stop: 1e-13 * scale, accept: 1e-9 * scale, max_iter: 16 };
        let dl = d.length();
        let tmin = 4e-10 * scale / dl;
        let inv = DVec3::ONE / d;
        let slab = |n: &Node, limit: f64| -> Option<(f64, f64)> {
            let ta = (n.lo - o) * inv;
            let tb = (n.hi - o) * inv;
            // NaN (0 * inf on a box face) counts as inside: min/max ignore NaN operands.
            let near = ta.min(tb).max_element().max(tmin);
            let far = ta.max(tb).min_element().min(limit);
            (near <= far).then_some((near, far))
        };
        let mut best: Option<(f64, f64, f64)> = None;
        let mut best_t = tmax;
        let root = slab(&self.nodes[0], best_t)?;
        let mut stack = [(0u32, 0.0f64, 0.0f64); 64];
        stack[0] = (0, root.0, root.1);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (ni, t0, t1) = stack[sp];
            if t0 > best_t {
                continue;
            }
            let n = self.nodes[ni as usize];
            if n.count == 0 {
                let leaf = &self.leaves[n.first as usize];
                let Some((t0, t1)) = leaf.clip(o, d, t0, t1.min(best_t)) else { continue };
                // The root Newton reaches from the seed at `t`: kept if nearest; `Some(root)` if it is this
                // leaf's own root within the span.
                let mut try_seed = |t: f64| -> Option<(f64, f64, f64)> {
                    let (u, v, tr) = solve(self, o, d, leaf.seed(o, d, t), &tol)?;
                    if tr > tmin && tr < best_t {
                        best_t = tr;
                        best = Some((u, v, tr));
                    }
                    let (su, sv) = (1e-9 * (leaf.u1 - leaf.u0), 1e-9 * (leaf.v1 - leaf.v0));
                    let w = 1e-6 * (t1 - t0) + tol.accept / dl;
                    let inside = u >= leaf.u0 - su && u <= leaf.u1 + su && v >= leaf.v0 - sv && v <= leaf.v1 + sv;
                    (tr > tmin && inside && tr >= t0 - w && tr <= t1 + w).then_some((u, v, tr))
                };
                // Seed where the ray crosses the central tangent plane (a flat leaf is close to it), else the
                // middle of the span.
                let nd = leaf.n.dot(d);
                let t_plane = if nd != 0.0 { (leaf.n.dot(leaf.center) - leaf.n.dot(o)) / nd } else { f64::NAN };
                let t_seed = if t_plane >= t0 && t_plane <= t1 { t_plane } else { 0.5 * (t0 + t1) };
                let w = t1 - t0;
                match try_seed(t_seed) {
                    // A root well inside the span, or a grazing one, may hide a nearer root.
                    Some((u, v, t)) => {
                        let (dt, cos) = other_root_offset(self, u, v, d).unwrap_or((f64::INFINITY, 0.0));
                        if dt < 0.0 && t + dt > t0 {
                            try_seed(t + dt);
                        }
                        if t > t0 + 0.1 * w || cos.abs() < 0.05 {
                            try_seed(t0 + 1e-3 * (t - t0));
                        }
                    }
                    // No own root yet: more seeds across the span.
                    None => {
                        for f in [0.05, 0.5, 0.95] {
                            if try_seed(t0 + f * w).is_some() {
                                break;
                            }
                        }
                    }
                }
                if any && best.is_some() {
                    return best;
                }
                continue;
            }
            let mut kids = [(0u32, 0.0f64, 0.0f64); 4];
            let mut k = 0;
            for c in n.first..n.first + n.count {
                if let Some((a, b)) = slab(&self.nodes[c as usize], best_t) {
                    kids[k] = (c, a, b);
                    k += 1;
                }
            }
            kids[..k].sort_unstable_by(|x, y| y.1.total_cmp(&x.1));
            for &kid in &kids[..k] {
                if sp < stack.len() {
                    stack[sp] = kid;
                    sp += 1;
                }
            }
        }
        best
    }

    /// Visit the boxes of leaves overlapping `query`; stops when `visit` returns true.
    fn any_leaf_box(&self, query: &Bounds, mut visit: impl FnMut(DVec3, DVec3) -> bool) -> bool {
        let (qlo, qhi) = (query.min.as_dvec3(), query.max.as_dvec3());
        let mut stack = vec![0u32];
        while let Some(ni) = stack.pop() {
            let n = self.nodes[ni as usize];
            if n.lo.cmpgt(qhi).any() || n.hi.cmplt(qlo).any() {
                continue;
            }
            if n.count == 0 {
                if visit(n.lo, n.hi) {
                    return true;
                }
            } else {
                stack.extend(n.first..n.first + n.count);
            }
        }
        false
    }
}

impl AnalyticShape for BezierPatch {
    fn bounds(&self) -> Bounds {
        self.bounds
    }

    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let (u, v, t) = self.query(o, d, ray.tmax as f64, false)?;
        let t32 = t as f32;
        (t32 < ray.tmax && t32 > 0.0).then_some(ShapeHit { t: t32, u: u as f32, v: v as f32 })
    }

    #[inline]
    fn occludes(&self, ray: &Ray) -> bool {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        self.query(o, d, ray.tmax as f64, true).is_some_and(|(_, _, t)| (t as f32) < ray.tmax)
    }

    fn overlaps_box(&self, b: &Bounds) -> bool {
        self.any_leaf_box(b, |_, _| true)
    }

    fn clip_bounds(&self, voxel: &Bounds) -> Option<Bounds> {
        let mut out = Bounds::EMPTY;
        self.any_leaf_box(voxel, |lo, hi| {
            let b = Bounds::new(Vec3A::from(lo.as_vec3()), Vec3A::from(hi.as_vec3()));
            let pad = b.min.abs().max(b.max.abs()) * 1e-6;
            out = out.union(Bounds::new((b.min - pad).max(voxel.min), (b.max + pad).min(voxel.max)));
            false
        });
        (!out.is_empty()).then_some(out)
    }

    fn surface(&self, _ray: &Ray, hit: &ShapeHit) -> ShapePoint {
        let (u, v) = (hit.u as f64, hit.v as f64);
        let (s, su, sv) = self.eval(u, v);
        let mut n = su.cross(sv);
        if n.length() <= 1e-12 * self.size * self.size {
            let (u2, v2) = (u + (0.5 - u) * 1e-3, v + (0.5 - v) * 1e-3);
            let (_, su2, sv2) = self.eval(u2, v2);
            n = su2.cross(sv2);
        }
        let p = Vec3A::from(s.as_vec3());
        let p_err = p.abs() * f32::EPSILON + Vec3A::splat((1e-9 * self.size) as f32);
        ShapePoint {
            p,
            p_err,
            n: Vec3A::from(n.normalize_or(DVec3::Y).as_vec3()),
            uv: Vec2::new(hit.u, hit.v),
            dpdu: Vec3A::from(su.as_vec3()),
            dpdv: Vec3A::from(sv.as_vec3()),
        }
    }

    fn point_at_uv(&self, uv: Vec2) -> Option<ShapePoint> {
        Some(self.surface(&Ray::new(Vec3A::ZERO, Vec3A::X), &ShapeHit { t: 0.0, u: uv.x, v: uv.y }))
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn light(&self) -> u32 {
        self.light
    }
}
