//! The wide BVH's leaves: packets of up to four primitives, and each leaf's slab — the exact extent of its
//! primitives along the axis on which its triangles lie in a face of the leaf's box — which lets a ray that starts
//! beyond the slab and moves away from it (a ray leaving a wall, a floor, a block's face) skip the leaf's tests.

use crate::geometry::{Ray, TriPacket};
use crate::primitives::Primitives;
use glam::Vec3A;
use obvhs::aabb::Aabb;

/// A leaf's packets, `packets[first..first + count]`, and the axis of its slab (`slabs`, see [`leaf_slab`]): a ray
/// whose origin is beyond the slab and that does not move back towards it cannot meet anything in the leaf — a ray
/// leaving a wall, the floor or a box's face is such a ray for the leaf it starts on — so the leaf's tests are
/// skipped. Eight bytes (the axis in the top two bits), so leaves without a slab pay one compare.
#[derive(Clone, Copy, Debug)]
pub(super) struct LeafRange {
    pub(super) first: u32,
    count_axis: u32,
}

/// The axis value of a leaf without a slab.
pub(super) const NO_SLAB: u32 = 3;

impl LeafRange {
    pub(super) fn new(first: u32, count: u32, axis: u32) -> Self {
        assert!(count < 1 << 30, "a leaf of {count} packets");
        LeafRange { first, count_axis: count | axis << 30 }
    }

    #[inline(always)]
    pub(super) fn count(&self) -> u32 {
        self.count_axis & ((1 << 30) - 1)
    }

    #[inline(always)]
    pub(super) fn axis(&self) -> u32 {
        self.count_axis >> 30
    }

    #[inline(always)]
    pub(super) fn packets(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count()) as usize
    }
}

/// Whether `ray` starts outside the slab `[lo, hi]` along `axis` and never re-enters it (exact comparisons: along
/// `axis` the ray's points at `t >= 0` are at least as far beyond the slab as its origin). NaN never qualifies.
#[inline(always)]
pub(super) fn moving_away(ray: &Ray, axis: u32, [lo, hi]: [f32; 2]) -> bool {
    let (o, d) = (ray.origin.to_array()[axis as usize], ray.dir.to_array()[axis as usize]);
    (o > hi && d >= 0.0) || (o < lo && d <= 0.0)
}

/// Up to four primitives of one leaf: triangles as a packet, other bounded shapes tested one by one.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct LeafPacket {
    pub(super) tris: TriPacket,
    pub(super) ids: [u32; 4],
    pub(super) tri_lanes: u8,
    pub(super) other_lanes: u8,
}

/// The slab of a leaf worth testing before its primitives: `(axis, lo, hi)` with `[lo, hi]` the exact extent of
/// primitives `ids` along the axis on which most of its triangles lie in a face of the leaf's box (walls, floors,
/// the faces of boxes: rays leave them away from the leaf), or axis 3 (no test) where no triangle does (a patch of a
/// curved mesh, whose rays leave from inside the box). `aabbs`: the primitives' padded boxes (shapes other than
/// triangles; a triangle is exactly the hull of its vertices, which the triangle test reads as they are).
pub(super) fn leaf_slab(ids: &[u32], prims: &Primitives, aabbs: &[Aabb]) -> (u32, f32, f32) {
    let nt = prims.num_tris();
    let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
    for &id in ids {
        let (a, b) = if id < nt {
            let t = prims.tris[id as usize];
            (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
        } else {
            (aabbs[id as usize].min, aabbs[id as usize].max)
        };
        (lo, hi) = (lo.min(a), hi.max(b));
    }
    // Which only decides whether the slab is tested; the test itself compares with the exact extent.
    let tol = 1e-5 * (hi - lo).max_element();
    let mut on_face = [0usize; 3];
    for &id in ids.iter().filter(|&&id| id < nt) {
        let t = prims.tris[id as usize];
        for (axis, count) in on_face.iter_mut().enumerate() {
            let near = |c: f32| t.iter().all(|v| (v[axis] - c).abs() <= tol);
            if near(lo[axis]) || near(hi[axis]) {
                *count += 1;
            }
        }
    }
    match (0..3).filter(|&a| on_face[a] > 0).max_by_key(|&a| on_face[a]) {
        Some(a) => (a as u32, lo[a], hi[a]),
        None => (NO_SLAB, 0.0, 0.0),
    }
}
