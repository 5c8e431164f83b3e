//! The `pluecker` kernel of `wide_kernel.rs` made safe to answer for the tree: every number carries a conservative
//! rounding bound, a triangle is a candidate if a ray is inside it within that bound and its distance interval
//! `[lo, hi]` reaches `(0, tmax)`, and a ray whose closest candidate's interval overlaps another's, that passes
//! within the bound of its closest candidate's edge, that grazes a candidate's plane, or whose candidate may be the
//! surface it starts on (an interval reaching 0) is marked unsure,
//! for the one-ray query to trace. A sure ray's hit is the kernel's own (distance and barycentric weights from the
//! side numbers). An experiment, not a Prism accelerator: `cargo bench --bench wide_kernel` prints its numbers beside the
//! other kernels'.
//!
//! Per directed edge `q -> p` (v0 -> v1, v1 -> v2, v2 -> v0) a triangle keeps twice its direction and its moment
//! `(p - q) x (p + q)`; a ray's side of the edge is `m . d - 2 (p - q) . (o x d)`, `o x d` once per ray. A neighbour
//! sharing the edge computes exactly the negated number (fused or not, every operand is negated), so the test has
//! no cracks between triangles.

use glam::Vec3A;
use prism::geometry::Ray;
use prism::primitives::Hit;

/// Rays per block (the lanes of the kernel; sixteen `f32` are one AVX-512 register).
pub const BLOCK: usize = 16;

/// The most triangles a [`PlueckerSet`] holds: every ray of a block is tested against every triangle, which beats a
/// tree's traversal one ray at a time only while the scene is this small (`cargo bench --bench wide_kernel`).
pub const MAX_TRIANGLES: usize = 64;

/// The unit roundoff of `f32`.
const EPS: f32 = f32::EPSILON * 0.5;

/// Rounding-bound factors (derivations in `PlueckerSet::new`'s comments), each several times what the operation
/// counts need.
const SIDE_K: f32 = 64.0 * EPS;
const PLANE_K: f32 = 64.0 * EPS;

/// One triangle as the block kernel reads it.
#[derive(Clone, Copy, Debug)]
struct Tri {
    /// Per directed edge: twice its direction.
    e2: [[f32; 3]; 3],
    /// Per directed edge: its moment `(p - q) x (p + q)`.
    m: [[f32; 3]; 3],
    /// The plane: `n = (v1 - v0) x (v2 - v0)` and `n . v0`.
    n: [f32; 3],
    nv0: f32,
    /// A side number's rounding bound is `|d| (side_a + side_b |o|)`.
    side_a: f32,
    side_b: f32,
    /// The plane offset's (`n . v0 - n . o`) bound is `num_a + num_b |o|`, `n . d`'s is `den_a |d|`.
    num_a: f32,
    num_b: f32,
    den_a: f32,
}

/// The L1 norm (at least the Euclidean one, so `|a . b| <= l1(a) l1(b)`).
fn l1(v: Vec3A) -> f32 {
    v.abs().element_sum()
}

/// The triangles of a tiny scene, prepared for the block kernel; triangle `k` is primitive `k`.
#[derive(Clone, Debug)]
pub struct PlueckerSet {
    tris: Vec<Tri>,
}

impl PlueckerSet {
    /// The set of `tris` (at most [`MAX_TRIANGLES`], or `None`).
    pub fn new(tris: &[[Vec3A; 3]]) -> Option<Self> {
        if tris.len() > MAX_TRIANGLES {
            return None;
        }
        let tris = tris
            .iter()
            .map(|&[a, b, c]| {
                let edges = [(a, b), (b, c), (c, a)];
                let e2 = edges.map(|(q, p)| (2.0 * (p - q)).to_array());
                let m = edges.map(|(q, p)| (p - q).cross(p + q).to_array());
                // A side number `m . d - e2 . (o x d)`: the moment's rounding (its difference, sum and cross
                // product) is within a few ulps of |p - q| |p + q|, o x d's within a few of |o| |d|, and each dot
                // product and the difference add a few more of their terms' magnitudes.
                let (side_a, side_b) = edges.iter().fold((0.0f32, 0.0f32), |(sa, sb), &(q, p)| {
                    (sa.max(SIDE_K * l1(p - q) * l1(p + q)), sb.max(2.0 * SIDE_K * l1(p - q)))
                });
                let (e1, e2v) = (b - a, c - a);
                let n = e1.cross(e2v);
                let longest = l1(b - a).max(l1(c - b)).max(l1(a - c));
                // `n` is rounded, which tilts the plane through `v0` by up to a few ulps of |e1| |e2| over the
                // triangle; the offsets `n . v0` and `n . o` and their difference round within a few ulps of their
                // terms.
                let tilt = l1(e1) * l1(e2v);
                Tri {
                    e2,
                    m,
                    n: n.to_array(),
                    nv0: n.dot(a),
                    side_a,
                    side_b,
                    num_a: PLANE_K * (l1(n) * l1(a) + tilt * longest),
                    num_b: PLANE_K * l1(n),
                    den_a: PLANE_K * (l1(n) + tilt),
                }
            })
            .collect();
        Some(PlueckerSet { tris })
    }

    /// Each ray's closest hit (`rays`: at most [`BLOCK`]).
    pub fn closest(&self, rays: &[Ray]) -> BlockHits {
        let block = RayBlock::new(rays);
        let mut out = BlockHits {
            prim: [u32::MAX; BLOCK],
            t: [0.0; BLOCK],
            b1: [0.0; BLOCK],
            b2: [0.0; BLOCK],
            unsure: [false; BLOCK],
        };
        closest_dispatched(&self.tris, &block, &mut out);
        out
    }
}

/// The block kernel's closest hit per ray, where it is sure of it: the triangle (`u32::MAX`: none), the distance and
/// the barycentric weights of v1 and v2. Where `unsure`, the ray is to be traced alone.
#[derive(Clone, Copy, Debug)]
pub struct BlockHits {
    pub prim: [u32; BLOCK],
    pub t: [f32; BLOCK],
    pub b1: [f32; BLOCK],
    pub b2: [f32; BLOCK],
    pub unsure: [bool; BLOCK],
}

/// Up to [`BLOCK`] rays with their coordinates across lanes; lanes past them are empty (`tmax` 0: no candidate).
struct RayBlock {
    o: [[f32; BLOCK]; 3],
    d: [[f32; BLOCK]; 3],
    /// `o x d`.
    l: [[f32; BLOCK]; 3],
    o_len: [f32; BLOCK],
    d_len: [f32; BLOCK],
    tmax: [f32; BLOCK],
    leaves: [u32; BLOCK],
}

impl RayBlock {
    fn new(rays: &[Ray]) -> Self {
        debug_assert!(rays.len() <= BLOCK);
        let mut b = RayBlock {
            o: [[0.0; BLOCK]; 3],
            d: [[0.0; BLOCK]; 3],
            l: [[0.0; BLOCK]; 3],
            o_len: [0.0; BLOCK],
            d_len: [0.0; BLOCK],
            tmax: [0.0; BLOCK],
            leaves: [u32::MAX; BLOCK],
        };
        for (k, r) in rays.iter().take(BLOCK).enumerate() {
            let l = r.origin.cross(r.dir);
            for a in 0..3 {
                b.o[a][k] = r.origin[a];
                b.d[a][k] = r.dir[a];
                b.l[a][k] = l[a];
            }
            b.o_len[k] = l1(r.origin);
            b.d_len[k] = l1(r.dir);
            b.tmax[k] = r.tmax;
            b.leaves[k] = r.leaves;
        }
        b
    }
}

/// What the kernel computes for one ray and one triangle.
struct Lane {
    /// The ray is inside the triangle within the side numbers' rounding bound, not along its plane, and its distance
    /// interval `[lo, hi]` reaches `(0, tmax)`.
    candidate: bool,
    /// The ray passes within the rounding bound of one of the triangle's edges.
    on_edge: bool,
    lo: f32,
    hi: f32,
    /// Inside the triangle, but too parallel to its plane for a sure distance.
    grazing: bool,
    /// The distance and the side numbers of edges v0 -> v1 and v2 -> v0 and their sum (the barycentric weights of
    /// v2 and v1 times the sum).
    t: f32,
    s0: f32,
    s2: f32,
    sum: f32,
}

/// `a . b` over three coordinates, fused.
#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[2].mul_add(b[2], a[1].mul_add(b[1], a[0] * b[0]))
}

#[inline(always)]
fn test(t: &Tri, b: &RayBlock, k: usize, id: u32) -> Lane {
    let d = [b.d[0][k], b.d[1][k], b.d[2][k]];
    let l = [b.l[0][k], b.l[1][k], b.l[2][k]];
    let o = [b.o[0][k], b.o[1][k], b.o[2][k]];
    // Fused: a neighbour's numbers are still exactly the negated ones, every operand being negated.
    let side = |j: usize| dot(t.m[j], d) - dot(t.e2[j], l);
    let (u, v, w) = (side(0), side(1), side(2));
    let margin = b.d_len[k] * t.side_b.mul_add(b.o_len[k], t.side_a);
    // Plain comparisons, not `f32::min`'s NaN rules: a NaN side number comes from a ray with a non-finite
    // component, whose `den` is NaN too, which marks the ray unsure below.
    let min = |a: f32, b: f32| if a < b { a } else { b };
    let max = |a: f32, b: f32| if a > b { a } else { b };
    let (lo_side, hi_side) = (min(min(u, v), w), max(max(u, v), w));
    let inside = ((lo_side >= -margin) | (hi_side <= margin)) & (id != b.leaves[k]);
    // Within the bound of an edge the ray may pass either side of it: only the one-ray query can tell.
    let on_edge = inside & !((lo_side > margin) | (hi_side < -margin));
    let den = dot(t.n, d);
    let num = t.nv0 - dot(t.n, o);
    // The distance with the sign of `den` moved to `num`.
    let num = f32::from_bits(num.to_bits() ^ (den.to_bits() & 0x8000_0000));
    let den = den.abs();
    let den_err = t.den_a * b.d_len[k];
    let num_err = t.num_b.mul_add(b.o_len[k], t.num_a);
    let inv = 1.0 / den;
    let tp = num * inv;
    let t_err = num_err.mul_add(inv, tp.abs() * den_err.mul_add(inv, 4.0 * EPS));
    let (lo, hi) = (tp - t_err, tp + t_err);
    // Also for NaN, which fails the comparison.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let grazing = inside & !(den > den_err);
    let candidate = inside & !grazing & (hi > 0.0) & (lo < b.tmax[k]);
    Lane { candidate, on_edge, lo, hi, grazing, t: tp, s0: u, s2: w, sum: u + v + w }
}

#[inline(always)]
fn closest(tris: &[Tri], b: &RayBlock, out: &mut BlockHits) {
    let inf = [f32::INFINITY; BLOCK];
    let (mut lo1, mut hi1, mut lo2) = (inf, inf, inf);
    let mut best = [u32::MAX; BLOCK];
    // Whether the best candidate so far is one the ray passes on an edge of (0 / 1 words, as `unsure`).
    let mut edge = [0u32; BLOCK];
    let (mut t_best, mut s0, mut s2, mut sum) = ([0.0f32; BLOCK], [0.0f32; BLOCK], [0.0f32; BLOCK], [1.0f32; BLOCK]);
    // Booleans as 0 / 1 words, which stay in a vector register (a `bool` array is packed to bytes per step).
    let mut unsure = [0u32; BLOCK];
    for (id, t) in tris.iter().enumerate() {
        for k in 0..BLOCK {
            let c = test(t, b, k, id as u32);
            // A candidate whose interval reaches 0 may be the surface the ray starts on: the one-ray query decides.
            let at_origin = c.candidate & (c.lo <= 0.0);
            unsure[k] |= (c.grazing | at_origin) as u32;
            let ahead = c.candidate & !at_origin;
            let first = ahead & (c.lo < lo1[k]);
            let second = ahead & !first & (c.lo < lo2[k]);
            lo2[k] = if first {
                lo1[k]
            } else if second {
                c.lo
            } else {
                lo2[k]
            };
            lo1[k] = if first { c.lo } else { lo1[k] };
            hi1[k] = if first { c.hi } else { hi1[k] };
            best[k] = if first { id as u32 } else { best[k] };
            edge[k] = if first { c.on_edge as u32 } else { edge[k] };
            t_best[k] = if first { c.t } else { t_best[k] };
            s0[k] = if first { c.s0 } else { s0[k] };
            s2[k] = if first { c.s2 } else { s2[k] };
            sum[k] = if first { c.sum } else { sum[k] };
        }
    }
    for k in 0..BLOCK {
        // Another candidate may be as close as the best, or the best as far as `tmax`: the one-ray query decides.
        let found = best[k] != u32::MAX;
        out.unsure[k] = (unsure[k] != 0) | (lo2[k] < hi1[k]) | (found & (hi1[k] >= b.tmax[k])) | (edge[k] != 0);
        out.prim[k] = best[k];
        out.t[k] = t_best[k];
        let inv = 1.0 / sum[k];
        out.b1[k] = s2[k] * inv;
        out.b2[k] = s0[k] * inv;
    }
}

#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2+fma"))]
fn closest_dispatched(tris: &[Tri], b: &RayBlock, out: &mut BlockHits) {
    closest(tris, b, out)
}

/// The closest hits of `rays` (a block query): the kernel's where it is sure, the tree's one-ray query where not.
pub fn intersect_block(set: &PlueckerSet, scene: &prism::scene::Scene, rays: &[Ray], out: &mut [Option<Hit>]) {
    for (rays, out) in rays.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
        let h = set.closest(rays);
        for (k, (ray, o)) in rays.iter().zip(out.iter_mut()).enumerate() {
            *o = if h.unsure[k] {
                scene.intersect(ray)
            } else if h.prim[k] == u32::MAX {
                None
            } else {
                Some(Hit { t: h.t[k], prim: h.prim[k], b1: h.b1[k], b2: h.b2[k] })
            };
        }
    }
}
