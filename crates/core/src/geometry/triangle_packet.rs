//! Four triangles tested against one ray at once: a conservative SIMD pre-filter for the watertight test.
//!
//! [`TriPacket`] holds four triangles with each vertex coordinate in the four lanes of one `Vec4` (one triangle a
//! lane). [`WatertightRay::packet_candidates`] evaluates the watertight test's three edge functions for all four
//! lanes with exactly the operations, in exactly the order, of [`WatertightRay::intersect_soa`], so a lane it
//! rejects (edge functions of both signs, none zero) is one the exact test rejects too. The surviving lanes (the
//! triangles whose edges enclose the ray's line) are then tested one at a time with the exact kernel, which
//! decides `t`, the barycentrics and every tie: the packet changes how fast, never what is hit.
//!
//! Accelerators with leaves of several triangles (the kd-tree) use it: most triangles in a leaf the ray passes
//! through are rejected by the edge test, four per SIMD pass.
//!
//! [`WatertightRay::intersect_packet`] goes further: the whole watertight test for four lanes at once — edge
//! functions, determinant, scaled distance, range test and the rounding-error bound on `t` — with, lane by lane,
//! exactly the operations of the scalar kernel in the same order (no fused or reassociated arithmetic), so each
//! lane's hit, `t` and barycentrics are bit-identical to `intersect_soa`'s. Only lanes with an edge function exactly
//! zero (a ray through an edge or vertex), where the scalar kernel recomputes in double precision, go through it.

use super::offset::gamma;
use super::triangle::{TriSoa, TriangleHit, WatertightRay};
use glam::{Vec3A, Vec4};

/// Four triangles in structure-of-arrays form: `v[i][a]` lane k is coordinate `a` of vertex `i` of triangle k.
/// Unused lanes hold zeros; callers mask them out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriPacket {
    /// `v[vertex][axis]`, one triangle per lane.
    pub v: [[Vec4; 3]; 3],
}

impl TriPacket {
    /// Pack up to four triangles (given by their vertices); lanes past `tris.len()` are zero.
    pub fn new(tris: &[[Vec3A; 3]]) -> Self {
        assert!(tris.len() <= 4, "a triangle packet holds at most four triangles");
        let mut v = [[[0f32; 4]; 3]; 3];
        for (lane, tri) in tris.iter().enumerate() {
            for (i, p) in tri.iter().enumerate() {
                for a in 0..3 {
                    v[i][a][lane] = p[a];
                }
            }
        }
        TriPacket { v: v.map(|vertex| vertex.map(Vec4::from_array)) }
    }

    /// Triangle `lane` in the form the exact kernel takes.
    #[inline]
    pub fn lane(&self, lane: usize) -> TriSoa {
        let [p0, p1, p2] = &self.v;
        TriSoa {
            xs: Vec3A::new(p0[0][lane], p1[0][lane], p2[0][lane]),
            ys: Vec3A::new(p0[1][lane], p1[1][lane], p2[1][lane]),
            zs: Vec3A::new(p0[2][lane], p1[2][lane], p2[2][lane]),
        }
    }
}

impl WatertightRay {
    /// Bit k set: triangle k of the packet may be hit (its edge functions do not have both signs, or one is zero
    /// and only the exact test's double-precision fallback can tell). Never clears a bit the exact test would hit.
    #[inline(always)]
    pub fn packet_candidates(&self, p: &TriPacket) -> u32 {
        let ([kx, ky, kz], [ox, oy, oz], [sx, sy, _]) = self.permuted4();
        // Sheared x and y of vertex i: the numbers `intersect_soa` computes (see `WatertightRay::permuted4`).
        let sheared = |i: usize| {
            let v = &p.v[i];
            let dz = v[kz as usize] - oz;
            (v[kx as usize] - ox - sx * dz, v[ky as usize] - oy - sy * dz)
        };
        let (x0, y0) = sheared(0);
        let (x1, y1) = sheared(1);
        let (x2, y2) = sheared(2);
        let u = x2 * y1 - y2 * x1;
        let v = x0 * y2 - y0 * x2;
        let w = x1 * y0 - y1 * x0;
        let zero = Vec4::ZERO;
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let exact_zero = u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero);
        let rejected = (neg & pos).bitmask() & !exact_zero.bitmask();
        !rejected & 0xF
    }
}

impl WatertightRay {
    /// The nearest hit with `t` in `(0, tmax)` among the lanes of `lanes` (bit k: lane k is a triangle), as
    /// (lane, hit): bit for bit what calling `intersect_soa` on the lanes in order gives, each call's `tmax` the
    /// previous hit's `t` (so ties go to the lowest lane).
    #[inline(always)]
    pub fn intersect_packet(&self, p: &TriPacket, lanes: u32, tmax: f32) -> Option<(usize, TriangleHit)> {
        let ([kx, ky, kz], [okx, oky, okz], [shx, shy, shz]) = self.permuted4();
        // Vertex i less the origin on the permuted axes, then sheared (see `WatertightRay::permuted4`).
        let d = |i: usize| {
            let v = &p.v[i];
            (v[kx as usize] - okx, v[ky as usize] - oky, v[kz as usize] - okz)
        };
        let (d0, d1, d2) = (d(0), d(1), d(2));
        let sx = |d: (Vec4, Vec4, Vec4)| d.0 - shx * d.2;
        let sy = |d: (Vec4, Vec4, Vec4)| d.1 - shy * d.2;
        let sz = |d: (Vec4, Vec4, Vec4)| shz * d.2;
        let (x0, x1, x2) = (sx(d0), sx(d1), sx(d2));
        let (y0, y1, y2) = (sy(d0), sy(d1), sy(d2));
        let u = x2 * y1 - y2 * x1;
        let v = x0 * y2 - y0 * x2;
        let w = x1 * y0 - y1 * x0;
        let zero = Vec4::ZERO;
        let exact_zero = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)).bitmask() & lanes;
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let (z0, z1, z2) = (sz(d0), sz(d1), sz(d2));
        let t_scaled = u * z0 + v * z1 + w * z2;
        let limit = Vec4::splat(tmax) * det;
        let in_range_pos = det.cmpgt(zero) & t_scaled.cmpgt(zero) & t_scaled.cmplt(limit);
        let in_range_neg = det.cmplt(zero) & t_scaled.cmplt(zero) & t_scaled.cmpgt(limit);
        let inv = Vec4::ONE / det;
        let t = t_scaled * inv;
        let max_zt = z0.abs().max(z1.abs()).max(z2.abs());
        let max_xt = x0.abs().max(x1.abs()).max(x2.abs());
        let max_yt = y0.abs().max(y1.abs()).max(y2.abs());
        let delta_z = Vec4::splat(gamma(3)) * max_zt;
        let delta_x = Vec4::splat(gamma(5)) * (max_xt + max_zt);
        let delta_y = Vec4::splat(gamma(5)) * (max_yt + max_zt);
        let delta_e =
            Vec4::splat(2.0) * (Vec4::splat(gamma(2)) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t = Vec4::splat(3.0)
            * (Vec4::splat(gamma(3)) * max_e * max_zt + delta_e * max_zt + delta_z * max_e)
            * inv.abs();
        let ok = (in_range_pos | in_range_neg) & t.cmpgt(delta_t);
        let valid = ok.bitmask() & !(neg & pos).bitmask() & lanes & !exact_zero;
        let (ta, tsa, deta) = (t.to_array(), t_scaled.to_array(), det.to_array());
        let (ua, va, wa, inva) = (u.to_array(), v.to_array(), w.to_array(), inv.to_array());
        // The lanes in order, each against the nearest hit so far, exactly as the exact kernel called lane after
        // lane with `tmax` shrinking to each hit: a valid lane (in range of the first `tmax`) counts if its scaled
        // distance is in range of the current one, by the kernel's own comparisons; a lane with an edge function
        // exactly zero goes through the kernel itself (its double-precision edge functions).
        let mut best: Option<(usize, TriangleHit)> = None;
        let mut end = tmax;
        let mut m = valid | exact_zero;
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            if exact_zero >> k & 1 != 0 {
                if let Some(h) = self.intersect_soa(&p.lane(k), end) {
                    end = h.t;
                    best = Some((k, h));
                }
                continue;
            }
            let (ts, limit) = (tsa[k], end * deta[k]);
            let in_range = if deta[k] > 0.0 { ts > 0.0 && ts < limit } else { ts < 0.0 && ts > limit };
            if in_range {
                end = ta[k];
                best =
                    Some((k, TriangleHit { t: ta[k], b0: ua[k] * inva[k], b1: va[k] * inva[k], b2: wa[k] * inva[k] }));
            }
        }
        best
    }
}
