//! The seeding structure of a surface of revolution: a binary tree over short, flat pieces ("leaves") of the
//! profile curve, each bounded by a *ring*: the solid of revolution of the rectangle `[r_lo, r_hi] x [y_lo, y_hi]`
//! that contains the piece's Bézier control points in the (radius, height) half-plane. By the convex hull
//! property the piece lies inside its control points' hull, so the band of surface it sweeps lies inside the ring:
//! every root of the ray–surface equation lies in the ray's interval through the ring of the leaf it belongs to.
//! A ring is exact under rotation (no angular tessellation), and a ray meets it in at most two intervals (the
//! slab `y_lo <= y <= y_hi`, inside the outer cylinder, outside the inner one), solved in closed form.
//!
//! Leaves come from de Casteljau subdivision of each Bézier segment at parameter midpoints until the control
//! points lie within [`FLATNESS`] of the profile's size from their chord (at least [`MIN_DEPTH`], at most
//! [`MAX_DEPTH`] levels). Rings are padded by `1e-9` of the profile size against rounding.
//!
//! For the accelerators, a ring is also cut into 8 sectors of 45 degrees, whose boxes are exact (sine and cosine
//! are monotone over each sector), giving conservative box overlap tests and clipped bounds.

use super::curve::{Curve, split_bezier};
use super::strip::Strip;
use crate::geometry::Bounds;
use glam::{DAffine3, DVec3, Vec3A};

/// Subdivide until the inner control points are within this fraction of the profile's size from the chord.
pub const FLATNESS: f64 = 2e-3;
/// Every Bézier segment is cut into at least `2^MIN_DEPTH` leaves.
pub const MIN_DEPTH: u32 = 2;
/// ... and at most `2^MAX_DEPTH`.
pub const MAX_DEPTH: u32 = 10;

/// The solid of revolution of `[r_lo, r_hi] x [y_lo, y_hi]` about the y axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ring {
    /// Inner radius (distance from the y axis), 0 or more.
    pub r_lo: f64,
    /// Outer radius.
    pub r_hi: f64,
    /// Lowest y.
    pub y_lo: f64,
    /// Highest y.
    pub y_hi: f64,
}

impl Ring {
    fn of_points(c: &[DVec3; 4], pad: f64) -> Ring {
        let (mut xlo, mut xhi, mut ylo, mut yhi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for p in c {
            xlo = xlo.min(p.x);
            xhi = xhi.max(p.x);
            ylo = ylo.min(p.y);
            yhi = yhi.max(p.y);
        }
        let r_lo = if xlo > 0.0 {
            xlo
        } else if xhi < 0.0 {
            -xhi
        } else {
            0.0
        };
        Ring { r_lo: (r_lo - pad).max(0.0), r_hi: xlo.abs().max(xhi.abs()) + pad, y_lo: ylo - pad, y_hi: yhi + pad }
    }

    fn union(&self, o: &Ring) -> Ring {
        Ring {
            r_lo: self.r_lo.min(o.r_lo),
            r_hi: self.r_hi.max(o.r_hi),
            y_lo: self.y_lo.min(o.y_lo),
            y_hi: self.y_hi.max(o.y_hi),
        }
    }

    /// The object-space box of sector `k` (angles `k pi/4 .. (k+1) pi/4`, measured from +x towards +z).
    pub fn sector_box(&self, k: usize) -> (DVec3, DVec3) {
        let (a0, a1) = (k as f64 * std::f64::consts::FRAC_PI_4, (k + 1) as f64 * std::f64::consts::FRAC_PI_4);
        let mut lo = DVec3::new(f64::INFINITY, self.y_lo, f64::INFINITY);
        let mut hi = DVec3::new(f64::NEG_INFINITY, self.y_hi, f64::NEG_INFINITY);
        for r in [self.r_lo, self.r_hi] {
            for a in [a0, a1] {
                let (s, c) = a.sin_cos();
                lo.x = lo.x.min(r * c);
                hi.x = hi.x.max(r * c);
                lo.z = lo.z.min(r * s);
                hi.z = hi.z.max(r * s);
            }
        }
        (lo, hi)
    }
}

/// A flat piece of the profile: global parameters `[s0, s1]`, its Bézier control points (z = 0) and its tight
/// oriented bound (`strip.rs`; none for a piece straddling the axis).
#[derive(Clone, Copy, Debug)]
pub struct Leaf {
    /// Global profile parameter where the piece starts.
    pub s0: f64,
    /// Global profile parameter where it ends.
    pub s1: f64,
    /// The piece's cubic Bézier control points, object space (z = 0).
    pub ctrl: [DVec3; 4],
    /// Its revolved chord-aligned rectangle; `None` when the piece straddles the axis.
    pub strip: Option<Strip>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    ring: Ring,
    /// Leaf index (`leaf`) or the index of the second child (the first follows the node).
    index: u32,
    leaf: bool,
}

/// Up to two parameter intervals of a ray inside a ring.
pub type Intervals = ([(f64, f64); 2], usize);

/// The per-ray constants of the ring test. The squared distance from the axis is kept centred on the ray's
/// closest approach to the axis, `rho^2(t) = a (t - tc)^2 + cmin`, with `cmin` computed from that point itself:
/// the expanded form `a t^2 + 2 b t + c` loses everything to cancellation near the axis when the origin is far.
#[derive(Clone, Copy, Debug)]
pub struct RingRay {
    /// Ray origin, object space.
    pub o: DVec3,
    /// Ray direction, object space (any length).
    pub d: DVec3,
    a: f64,
    tc: f64,
    cmin: f64,
}

impl RingRay {
    /// The constants of the object-space ray `o + t d`.
    pub fn new(o: DVec3, d: DVec3) -> Self {
        let a = d.x * d.x + d.z * d.z;
        let tc = if a > 0.0 { -(o.x * d.x + o.z * d.z) / a } else { 0.0 };
        let (px, pz) = (o.x + tc * d.x, o.z + tc * d.z);
        RingRay { o, d, a, tc, cmin: px * px + pz * pz }
    }

    /// `(a, tc, cmin)` of `rho^2(t) = a (t - tc)^2 + cmin` (`a = 0`: a ray parallel to the axis, `tc = 0`).
    #[inline]
    pub fn centered(&self) -> (f64, f64, f64) {
        (self.a, self.tc, self.cmin)
    }

    /// Squared distance from the axis at `t`.
    #[inline]
    pub fn rho2(&self, t: f64) -> f64 {
        let u = t - self.tc;
        self.a * u * u + self.cmin
    }

    /// The interval where `rho^2(t) <= r^2` (`None`: never; infinite ends for rays parallel to the axis).
    #[inline]
    fn inside_cylinder(&self, r: f64) -> Option<(f64, f64)> {
        let h = r * r - self.cmin;
        if h < 0.0 {
            return None;
        }
        if self.a == 0.0 {
            return Some((f64::NEG_INFINITY, f64::INFINITY));
        }
        let w = (h / self.a).sqrt();
        Some((self.tc - w, self.tc + w))
    }

    /// The ray's intervals inside `ring`, within `[tmin, tmax]`, in increasing order.
    pub fn intervals(&self, ring: &Ring, tmin: f64, tmax: f64) -> Intervals {
        let none = ([(0.0, 0.0); 2], 0);
        let (mut lo, mut hi) = (tmin, tmax);
        if self.d.y != 0.0 {
            let inv = 1.0 / self.d.y;
            let (t0, t1) = ((ring.y_lo - self.o.y) * inv, (ring.y_hi - self.o.y) * inv);
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        } else if self.o.y < ring.y_lo || self.o.y > ring.y_hi {
            return none;
        }
        if lo > hi {
            return none;
        }
        let Some((c0, c1)) = self.inside_cylinder(ring.r_hi) else {
            return none;
        };
        lo = lo.max(c0);
        hi = hi.min(c1);
        if lo > hi {
            return none;
        }
        if ring.r_lo > 0.0 {
            if self.a == 0.0 {
                if self.cmin < ring.r_lo * ring.r_lo {
                    return none;
                }
            } else if let Some((e0, e1)) = self.inside_cylinder(ring.r_lo) {
                // Remove the open interval (e0, e1) inside the hole.
                let first = (lo, hi.min(e0));
                let second = (lo.max(e1), hi);
                let mut out = none;
                for iv in [first, second] {
                    if iv.0 <= iv.1 {
                        out.0[out.1] = iv;
                        out.1 += 1;
                    }
                }
                return out;
            }
        }
        ([(lo, hi), (0.0, 0.0)], 1)
    }
}

/// The leaves of a profile and the ring tree over them.
#[derive(Clone, Debug)]
pub struct ProfileTree {
    nodes: Vec<Node>,
    /// The flat pieces, in profile order.
    pub leaves: Vec<Leaf>,
}

impl ProfileTree {
    /// Subdivide the profile into flat leaves and build the tree. `size` is the profile's extent.
    pub fn build(curve: &Curve, size: f64) -> ProfileTree {
        let mut leaves = Vec::new();
        let tol = FLATNESS * size;
        let pad = 1e-9 * size + 4.0 * f64::EPSILON * size;
        for (i, seg) in curve.bezier_segments().iter().enumerate() {
            subdivide(seg, i as f64, i as f64 + 1.0, 0, tol, &mut leaves);
        }
        for leaf in leaves.iter_mut() {
            leaf.strip = Strip::new(&leaf.ctrl, pad);
        }
        let mut nodes = Vec::with_capacity(2 * leaves.len());
        build_nodes(&leaves, 0, leaves.len(), pad, &mut nodes);
        ProfileTree { nodes, leaves }
    }

    /// The ring of the whole profile.
    pub fn root_ring(&self) -> Ring {
        self.nodes[0].ring
    }

    /// Number of tree nodes (for statistics).
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Visit, nearest first, every leaf whose ring the ray meets before `best()`; `visit(leaf, intervals)` returns
    /// false to stop (occlusion found).
    #[inline]
    pub fn traverse(
        &self,
        ray: &RingRay,
        tmin: f64,
        mut best: impl FnMut() -> f64,
        mut visit: impl FnMut(&Leaf, &Intervals) -> bool,
    ) {
        let root = ray.intervals(&self.nodes[0].ring, tmin, best());
        if root.1 == 0 {
            return;
        }
        let mut stack: [(u32, Intervals); 64] = [(0, root); 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (ni, iv) = stack[sp];
            if iv.0[0].0 > best() {
                continue;
            }
            let n = &self.nodes[ni as usize];
            if n.leaf {
                if !visit(&self.leaves[n.index as usize], &iv) {
                    return;
                }
                continue;
            }
            let limit = best();
            let (l, r) = (ni + 1, n.index);
            let il = ray.intervals(&self.nodes[l as usize].ring, tmin, limit);
            let ir = ray.intervals(&self.nodes[r as usize].ring, tmin, limit);
            let mut push = |node: u32, iv: Intervals| {
                if iv.1 > 0 && sp < stack.len() {
                    stack[sp] = (node, iv);
                    sp += 1;
                }
            };
            // Push the farther child first so the nearer one is popped next.
            if il.1 > 0 && ir.1 > 0 && il.0[0].0 <= ir.0[0].0 {
                push(r, ir);
                push(l, il);
            } else {
                push(l, il);
                push(r, ir);
            }
        }
    }

    /// Call `visit` with the world box of every sector of every node whose sector boxes overlap `query`, leaves
    /// last (`visit(box, is_leaf)`); stops when `visit` returns true.
    fn any_sector(&self, m: &DAffine3, query: &Bounds, mut visit: impl FnMut(Bounds, bool) -> bool) -> bool {
        let mut stack = vec![0u32];
        while let Some(ni) = stack.pop() {
            let n = &self.nodes[ni as usize];
            let mut hit = false;
            for k in 0..8 {
                let (lo, hi) = n.ring.sector_box(k);
                let wb = world_box(m, lo, hi);
                if overlap(&wb, query) {
                    hit = true;
                    if n.leaf && visit(wb, true) {
                        return true;
                    }
                }
            }
            if hit && !n.leaf {
                stack.push(ni + 1);
                stack.push(n.index);
            }
        }
        false
    }

    /// Does some leaf sector (mapped by `m` to world space) overlap `query`? Conservative.
    pub fn overlaps(&self, m: &DAffine3, query: &Bounds) -> bool {
        self.any_sector(m, query, |_, _| true)
    }

    /// The union of the leaf sectors' world boxes clipped to `voxel`.
    pub fn clipped(&self, m: &DAffine3, voxel: &Bounds) -> Option<Bounds> {
        let mut out = Bounds::EMPTY;
        self.any_sector(m, voxel, |b, _| {
            out = out.union(Bounds::new(b.min.max(voxel.min), b.max.min(voxel.max)));
            false
        });
        (!out.is_empty()).then_some(out)
    }
}

fn overlap(a: &Bounds, b: &Bounds) -> bool {
    a.min.cmple(b.max).all() && a.max.cmpge(b.min).all()
}

/// The f32 world box of an object-space box under `m`, rounded outwards.
pub fn world_box(m: &DAffine3, lo: DVec3, hi: DVec3) -> Bounds {
    let mut wlo = DVec3::splat(f64::INFINITY);
    let mut whi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let w = m.transform_point3(c);
        wlo = wlo.min(w);
        whi = whi.max(w);
    }
    let pad = (wlo.abs().max(whi.abs())) * 1e-6;
    Bounds::new(Vec3A::from((wlo - pad).as_vec3()), Vec3A::from((whi + pad).as_vec3()))
}

fn subdivide(c: &[DVec3; 4], s0: f64, s1: f64, depth: u32, tol: f64, out: &mut Vec<Leaf>) {
    // A piece whose radius changes sign (the profile crosses the axis) is cut where it does, so every leaf lies on
    // one side of the axis and gets a strip.
    if depth < MAX_DEPTH
        && let Some(w) = axis_crossing(c)
    {
        let (l, r) = split_bezier(c, w);
        let mid = s0 + w * (s1 - s0);
        subdivide(&l, s0, mid, depth + 1, tol, out);
        subdivide(&r, mid, s1, depth + 1, tol, out);
        return;
    }
    let flat = {
        let (a, b) = (c[0], c[3]);
        let e = b - a;
        let len2 = e.length_squared();
        let dist = |p: DVec3| {
            if len2 == 0.0 {
                (p - a).length()
            } else {
                let w = (p - a).dot(e) / len2;
                (p - (a + e * w)).length()
            }
        };
        dist(c[1]).max(dist(c[2])) <= tol
    };
    if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && flat) {
        out.push(Leaf { s0, s1, ctrl: *c, strip: None });
        return;
    }
    let (l, r) = split_bezier(c, 0.5);
    let mid = 0.5 * (s0 + s1);
    subdivide(&l, s0, mid, depth + 1, tol, out);
    subdivide(&r, mid, s1, depth + 1, tol, out);
}

/// The parameter strictly inside `(0, 1)` where the piece's x changes sign, if its control points straddle the
/// axis and the ends have opposite signs (bisection); `None` otherwise.
fn axis_crossing(c: &[DVec3; 4]) -> Option<f64> {
    let straddles = c.iter().any(|p| p.x > 0.0) && c.iter().any(|p| p.x < 0.0);
    if !straddles || c[0].x * c[3].x >= 0.0 {
        return None;
    }
    let x = |w: f64| super::curve::bezier(c, w).x;
    let (mut lo, mut hi) = (0.0, 1.0);
    let positive_at_lo = c[0].x > 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (x(mid) > 0.0) == positive_at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let w = 0.5 * (lo + hi);
    (w > 1e-9 && w < 1.0 - 1e-9).then_some(w)
}

/// Nodes over `leaves[lo..hi]` in depth-first order; returns the ring of the subtree.
fn build_nodes(leaves: &[Leaf], lo: usize, hi: usize, pad: f64, nodes: &mut Vec<Node>) -> Ring {
    let me = nodes.len();
    nodes.push(Node { ring: Ring { r_lo: 0.0, r_hi: 0.0, y_lo: 0.0, y_hi: 0.0 }, index: lo as u32, leaf: true });
    if hi - lo == 1 {
        let ring = Ring::of_points(&leaves[lo].ctrl, pad);
        nodes[me].ring = ring;
        return ring;
    }
    let mid = (lo + hi) / 2;
    let a = build_nodes(leaves, lo, mid, pad, nodes);
    let second = nodes.len() as u32;
    let b = build_nodes(leaves, mid, hi, pad, nodes);
    let ring = a.union(&b);
    nodes[me] = Node { ring, index: second, leaf: false };
    ring
}
