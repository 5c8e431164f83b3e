//! Up to sixteen rays through the wide BVH together: a packet traversal for coherent rays (one pixel's camera rays,
//! which take nearly the same path through the tree). The packet goes down the tree once with a mask of the lanes
//! still active; every box is tested against the sixteen rays lane by lane (one AVX-512 register, or two AVX2
//! ones: the code is written as loops over lanes and compiled for those targets by `multiversion`, with run-time
//! dispatch), and so is every triangle of a leaf, with the watertight kernel's arithmetic in its matrix form (each
//! lane's ray has its own axis permutation, so each maps the vertices by the full rows of
//! [`WatertightRay::coefficients`]; no fused or reassociated arithmetic), which gives the numbers of
//! [`WatertightRay::intersect_soa`]'s shortcut (a product by 0 or 1 and a sum with zero are exact; checked in
//! `tests/geometry.rs`), so each lane computes the same `t` and barycentrics. Lanes whose edge function comes out
//! exactly zero (a ray through an edge or a vertex, where the scalar kernel recomputes in double precision) and
//! analytic primitives go through the scalar code, lane by lane.
//!
//! Every lane gets the closest hit of its ray, as [`WideBvh::intersect`] gives it; the one difference is which of
//! two primitives at exactly the same distance is reported (the first met wins in both, and the packet meets the
//! leaves in its own order). Box tests are the one-ray test's (conservative, so no leaf holding a lane's closest hit
//! is skipped); a node's children are visited nearest first by the smallest entry distance over their lanes.

use super::boxes::RECIP_CLAMP;
use super::leaf::{NO_SLAB, leaf_axis, leaf_packets, moving_away};
use super::{EMPTY, LEAF_BIT, STACK, WIDTH, WideBvh};
use crate::geometry::{Ray, TriSoa, WatertightRay, gamma};
use crate::math::lane_mask16;
use crate::primitives::{Hit, Primitives};
use multiversion::multiversion;

/// Rays in a packet.
pub const PACKET: usize = 16;

type Lanes = [f32; PACKET];

/// The rays of a packet, lane by lane, and the closest hits so far.
struct Packet<'a> {
    rays: &'a [Ray],
    o: [Lanes; 3],
    inv: [Lanes; 3],
    rows: [[Lanes; 3]; 3],
    leaves: [u32; PACKET],
    /// The closest hit's distance so far (the ray's `tmax` before any).
    end: Lanes,
    prim: [u32; PACKET],
    b1: Lanes,
    b2: Lanes,
}

impl<'a> Packet<'a> {
    /// The packet of `rays` (1 to [`PACKET`]; the lanes past them are never active, and hold the numbers of a zero
    /// direction).
    #[inline(always)]
    fn new(rays: &'a [Ray]) -> Self {
        let mut p = Packet {
            rays,
            o: [[0.0; PACKET]; 3],
            inv: [[0.0; PACKET]; 3],
            rows: [[[0.0; PACKET]; 3]; 3],
            leaves: [rays[0].leaves; PACKET],
            end: [rays[0].tmax; PACKET],
            prim: [u32::MAX; PACKET],
            b1: [0.0; PACKET],
            b2: [0.0; PACKET],
        };
        // Each lane's shear rows and reciprocal direction exactly as `WatertightRay::new(ray).coefficients()` and
        // `clamped_recip` compute them (the same axis choice, ties included, and the same operations), but written
        // as selects over lanes, so that all sixteen lanes are computed together: one lane at a time, the set-up had
        // been about a third of a camera packet's time (sixteen scalar divisions, and stores to stack arrays at
        // run-time indices read back at once). The origin needs no permutation: `coefficients` returns it as it is.
        let mut dir = [[0.0f32; PACKET]; 3];
        for (l, ray) in rays.iter().enumerate().take(PACKET) {
            let (o, d) = (ray.origin.to_array(), ray.dir.to_array());
            for a in 0..3 {
                p.o[a][l] = o[a];
                dir[a][l] = d[a];
            }
            p.leaves[l] = ray.leaves;
            p.end[l] = ray.tmax;
        }
        // A loop over lanes that writes each lane of several arrays: the form LLVM vectorizes.
        #[allow(clippy::needless_range_loop)]
        for l in 0..PACKET {
            let d = [dir[0][l], dir[1][l], dir[2][l]];
            let pick = |k: u32| {
                if k == 0 {
                    d[0]
                } else if k == 1 {
                    d[1]
                } else {
                    d[2]
                }
            };
            let (ax, ay, az) = (d[0].abs(), d[1].abs(), d[2].abs());
            let kz: u32 = if ax > ay {
                if ax > az { 0 } else { 2 }
            } else if ay > az {
                1
            } else {
                2
            };
            let (kx, ky) = (if kz == 2 { 0 } else { kz + 1 }, if kz == 0 { 2 } else { kz - 1 });
            let dz = pick(kz);
            let (kx, ky) = if dz < 0.0 { (ky, kx) } else { (kx, ky) };
            let sz = 1.0 / dz;
            let (sx, sy) = (pick(kx) * sz, pick(ky) * sz);
            for c in 0..3u32 {
                let i = c as usize;
                // Entry `c` of the row `e_k - s e_kz`, as `coefficients` writes it.
                let shear_row = |k: u32, s: f32| {
                    if c == k {
                        1.0
                    } else if c == kz {
                        0.0 - s
                    } else {
                        0.0
                    }
                };
                p.rows[0][i][l] = shear_row(kx, sx);
                p.rows[1][i][l] = shear_row(ky, sy);
                p.rows[2][i][l] = if c == kz { sz } else { sz * 0.0 };
                // `clamped_recip`: -0 taken as +0, reciprocals beyond 1e25 clamped to it with the direction's sign.
                let di = d[i] + 0.0;
                let r = 1.0 / di;
                p.inv[i][l] = if r.abs() > RECIP_CLAMP { RECIP_CLAMP.copysign(di) } else { r };
            }
        }
        p
    }

    /// The lanes of `mask` whose ray meets child `c` of `n` before its closest hit so far, and the smallest entry
    /// distance among them (the one-ray box test lane by lane).
    #[inline(always)]
    fn child(&self, n: &super::Node, c: usize, mask: u32) -> (u32, f32) {
        let lo = [n.b[0][c], n.b[1][c], n.b[2][c]];
        let hi = [n.b[3][c], n.b[4][c], n.b[5][c]];
        let mut tn = [0.0f32; PACKET];
        let mut ok = [false; PACKET];
        for l in 0..PACKET {
            let mut t = [0.0f32; 3];
            let mut u = [0.0f32; 3];
            for a in 0..3 {
                let neg = self.inv[a][l] < 0.0;
                let (near, far) = if neg { (hi[a], lo[a]) } else { (lo[a], hi[a]) };
                t[a] = (near - self.o[a][l]) * self.inv[a][l];
                u[a] = (far - self.o[a][l]) * self.inv[a][l];
            }
            let max = |a: f32, b: f32| if a > b { a } else { b };
            let min = |a: f32, b: f32| if a < b { a } else { b };
            let tnear = max(max(t[0], t[1]), max(t[2], 0.0));
            let tfar = min(min(u[0], u[1]), min(u[2], self.end[l])) * (1.0 + 2.0 * gamma(3));
            tn[l] = tnear;
            ok[l] = tnear <= tfar;
        }
        let hit = lane_mask16(|l| ok[l]) & mask;
        let mut first = f32::INFINITY;
        for (l, &t) in tn.iter().enumerate() {
            let t = if hit & (1 << l) != 0 { t } else { f32::INFINITY };
            first = if t < first { t } else { first };
        }
        (hit, first)
    }

    /// Test triangle `tri` (primitive `id`) against the lanes of `mask`, keeping each lane's closest hit.
    #[inline(always)]
    fn triangle(&mut self, tri: &TriSoa, id: u32, mask: u32) {
        let v = [tri.xs.to_array(), tri.ys.to_array(), tri.zs.to_array()];
        // Vertex `j`'s coordinate `a` less lane `l`'s origin, and its sheared row `r`.
        let d = |a: usize, j: usize, l: usize| v[a][j] - self.o[a][l];
        let row = |r: usize, j: usize, l: usize| {
            d(0, j, l) * self.rows[r][0][l] + d(1, j, l) * self.rows[r][1][l] + d(2, j, l) * self.rows[r][2][l]
        };
        // First the edge functions of every lane: most triangles a packet meets in a leaf lie beside all of its
        // rays (a pixel's camera rays), and then the rest of the test is not computed.
        let (mut xs, mut ys) = ([[0.0f32; PACKET]; 3], [[0.0f32; PACKET]; 3]);
        let mut uvw = [[0.0f32; PACKET]; 3];
        let mut zero = [false; PACKET];
        let mut mixed = [false; PACKET];
        for l in 0..PACKET {
            let (x, y) = ([row(0, 0, l), row(0, 1, l), row(0, 2, l)], [row(1, 0, l), row(1, 1, l), row(1, 2, l)]);
            let u = x[2] * y[1] - y[2] * x[1];
            let w1 = x[0] * y[2] - y[0] * x[2];
            let w = x[1] * y[0] - y[1] * x[0];
            zero[l] = u == 0.0 || w1 == 0.0 || w == 0.0;
            mixed[l] = (u < 0.0 || w1 < 0.0 || w < 0.0) && (u > 0.0 || w1 > 0.0 || w > 0.0);
            for j in 0..3 {
                (xs[j][l], ys[j][l]) = (x[j], y[j]);
            }
            (uvw[0][l], uvw[1][l], uvw[2][l]) = (u, w1, w);
        }
        let leaving = lane_mask16(|l| self.leaves[l] == id);
        let mask = mask & !leaving;
        if lane_mask16(|l| !mixed[l] || zero[l]) & mask == 0 {
            return;
        }
        let mut hit = [false; PACKET];
        let (mut tt, mut bb1, mut bb2) = ([0.0f32; PACKET], [0.0f32; PACKET], [0.0f32; PACKET]);
        for l in 0..PACKET {
            let (x, y) = ([xs[0][l], xs[1][l], xs[2][l]], [ys[0][l], ys[1][l], ys[2][l]]);
            let (u, w1, w) = (uvw[0][l], uvw[1][l], uvw[2][l]);
            let det = u + w1 + w;
            let z = [row(2, 0, l), row(2, 1, l), row(2, 2, l)];
            let ts = u * z[0] + w1 * z[1] + w * z[2];
            let end = self.end[l];
            let in_range = if det > 0.0 { !(ts <= 0.0 || ts >= end * det) } else { !(ts >= 0.0 || ts <= end * det) };
            let inv = 1.0 / det;
            let t = ts * inv;
            let amax = |a: [f32; 3]| {
                let m = if a[0].abs() > a[1].abs() { a[0].abs() } else { a[1].abs() };
                if m > a[2].abs() { m } else { a[2].abs() }
            };
            let (max_zt, max_xt, max_yt) = (amax(z), amax(x), amax(y));
            let delta_z = gamma(3) * max_zt;
            let delta_x = gamma(5) * (max_xt + max_zt);
            let delta_y = gamma(5) * (max_yt + max_zt);
            let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
            let max_e = amax([u, w1, w]);
            let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
            // As the scalar kernel decides (`t <= delta_t` rejects; a NaN distance is not rejected there either).
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            let far_enough = !(t <= delta_t);
            hit[l] = !mixed[l] && det != 0.0 && in_range && far_enough;
            tt[l] = t;
            bb1[l] = w1 * inv;
            bb2[l] = w * inv;
        }
        let zero = lane_mask16(|l| zero[l]) & mask;
        let mut hits = lane_mask16(|l| hit[l]) & mask & !zero;
        while hits != 0 {
            let l = hits.trailing_zeros() as usize;
            hits &= hits - 1;
            (self.end[l], self.prim[l], self.b1[l], self.b2[l]) = (tt[l], id, bb1[l], bb2[l]);
        }
        // An edge function exactly zero: the scalar kernel, which recomputes it in double precision.
        let mut rest = zero;
        while rest != 0 {
            let l = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            if let Some(h) = WatertightRay::new(&self.rays[l]).intersect_soa(tri, self.end[l]) {
                (self.end[l], self.prim[l], self.b1[l], self.b2[l]) = (h.t, id, h.b1, h.b2);
            }
        }
    }

    /// Test the leaf of child word `word` (without `LEAF_BIT`) against the lanes of `mask`.
    #[inline(always)]
    fn leaf(&mut self, bvh: &WideBvh, prims: &Primitives, word: u32, mut mask: u32) {
        let packets = leaf_packets(word);
        let axis = leaf_axis(word);
        if axis != NO_SLAB {
            let slab = bvh.slabs[packets.start];
            let rays = self.rays;
            mask &= !lane_mask16(|l| l < rays.len() && moving_away(&rays[l], axis, slab));
            if mask == 0 {
                return;
            }
        }
        for p in &bvh.packets[packets] {
            let mut tris = p.tri_lanes as u32;
            while tris != 0 {
                let k = tris.trailing_zeros() as usize;
                tris &= tris - 1;
                self.triangle(&p.tris.lane(k), p.ids[k], mask);
            }
            let mut others = p.other_lanes as u32;
            while others != 0 {
                let k = others.trailing_zeros() as usize;
                others &= others - 1;
                let mut lanes = mask;
                while lanes != 0 {
                    let l = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    let ray = Ray { tmax: self.end[l], ..self.rays[l] };
                    if let Some(h) = prims.intersect_bounded(p.ids[k], &ray, &WatertightRay::new(&ray)) {
                        (self.end[l], self.prim[l], self.b1[l], self.b2[l]) = (h.t, h.prim, h.b1, h.b2);
                    }
                }
            }
        }
    }
}

/// The closest hit of each of `rays` (at most [`PACKET`]) into `out`; see the module notes.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512bw+avx512dq", "x86_64+avx2+fma"))]
pub(super) fn intersect_packet(bvh: &WideBvh, prims: &Primitives, rays: &[Ray], out: &mut [Option<Hit>]) {
    debug_assert!(rays.len() <= PACKET && out.len() == rays.len());
    if rays.is_empty() {
        return;
    }
    if bvh.root == EMPTY || (WIDTH - 1) * bvh.depth + 4 > STACK {
        // No tree, or one too deep for the packet's stack (degenerate input): one ray at a time.
        for (o, r) in out.iter_mut().zip(rays) {
            *o = if bvh.root == EMPTY { None } else { super::Accelerator::intersect(bvh, prims, r) };
        }
        return;
    }
    let mut p = Packet::new(rays);
    let all = if rays.len() == PACKET { u32::MAX >> (32 - PACKET) } else { (1u32 << rays.len()) - 1 };
    let mut stack = [(0u32, 0u32, 0f32); STACK];
    let mut sp = 0usize;
    let (mut cur, mut mask) = (bvh.root, all);
    loop {
        if cur & LEAF_BIT != 0 {
            p.leaf(bvh, prims, cur & !LEAF_BIT, mask);
        } else {
            let n = &bvh.nodes[cur as usize];
            let mut kids = [(0u32, 0u32, 0f32); WIDTH];
            let mut count = 0;
            for c in 0..WIDTH {
                if n.child[c] == EMPTY {
                    continue;
                }
                let (m, t) = p.child(n, c, mask);
                if m != 0 {
                    // Insertion by entry distance, farthest first.
                    let mut i = count;
                    while i > 0 && kids[i - 1].2 < t {
                        kids[i] = kids[i - 1];
                        i -= 1;
                    }
                    kids[i] = (n.child[c], m, t);
                    count += 1;
                }
            }
            if count > 0 {
                stack[sp..sp + count - 1].copy_from_slice(&kids[..count - 1]);
                sp += count - 1;
                (cur, mask) = (kids[count - 1].0, kids[count - 1].1);
                continue;
            }
        }
        // Next: the nearest pending child, with the lanes whose closest hit so far is not before it.
        loop {
            if sp == 0 {
                for (l, o) in out.iter_mut().enumerate() {
                    *o =
                        (p.prim[l] != u32::MAX).then(|| Hit { t: p.end[l], prim: p.prim[l], b1: p.b1[l], b2: p.b2[l] });
                }
                return;
            }
            sp -= 1;
            let (c, m, t) = stack[sp];
            let m = m & lane_mask16(|l| t <= p.end[l]);
            if m != 0 {
                (cur, mask) = (c, m);
                break;
            }
        }
    }
}
