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

use super::triangle::{TriSoa, WatertightRay};
use glam::{Vec3A, Vec4};

/// Four triangles in structure-of-arrays form: `v[i][a]` lane k is coordinate `a` of vertex `i` of triangle k.
/// Unused lanes hold zeros; callers mask them out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriPacket {
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
        let [o_x, o_y, o_z] = self.origin_splat().map(Vec4::splat);
        let [r0, r1, _] = self.shear_rows();
        let (c00, c01, c02) = (Vec4::splat(r0[0]), Vec4::splat(r0[1]), Vec4::splat(r0[2]));
        let (c10, c11, c12) = (Vec4::splat(r1[0]), Vec4::splat(r1[1]), Vec4::splat(r1[2]));
        // Sheared x and y of vertex i, as in `intersect_soa` (same products, same order of additions).
        let sheared = |i: usize| {
            let (dx, dy, dz) = (p.v[i][0] - o_x, p.v[i][1] - o_y, p.v[i][2] - o_z);
            (dx * c00 + dy * c01 + dz * c02, dx * c10 + dy * c11 + dz * c12)
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
