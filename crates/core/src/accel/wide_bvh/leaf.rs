//! The wide BVH's leaves: packets of up to four primitives, and each leaf's slab — the exact extent of its
//! primitives along the axis on which its triangles lie in a face of the leaf's box — which lets a ray that starts
//! beyond the slab and moves away from it (a ray leaving a wall, a floor, a block's face) skip the leaf's tests.

use crate::geometry::Ray;
use crate::primitives::Primitives;
use glam::Vec3A;
use obvhs::aabb::Aabb;

/// The axis value of a leaf without a slab.
pub(super) const NO_SLAB: u8 = 3;

/// Bits of a leaf's child word that hold its first packet; above them its packet count less one (2 bits) and its
/// slab's axis (2 bits), under `LEAF_BIT`.
const FIRST_BITS: u32 = 27;

/// The most primitives the wide BVH holds: every packet holds at least one, so their indices fit `FIRST_BITS`.
pub(crate) const MAX_PRIMITIVES: usize = 1 << FIRST_BITS;

/// A leaf's child word without `LEAF_BIT`: its packets `first..first + count` and its slab's axis (`NO_SLAB`:
/// none; the slab itself is `slabs[first]`). The traversal reads a leaf's packets and whether to test its slab
/// straight from its parent's slot, with no load of a leaf record in between (one dependent load fewer per leaf),
/// and skips a leaf by its slab without touching its packets. `count` is 1 to 4 (a leaf holds at most 16
/// primitives: two BVH2 leaves of eight merged) and `first` below `MAX_PRIMITIVES`, both checked.
pub(super) fn leaf_word(first: usize, count: usize, axis: u8) -> u32 {
    assert!(first < MAX_PRIMITIVES && (1..=4).contains(&count), "leaf of {count} packets from packet {first}");
    (axis as u32 & 3) << (FIRST_BITS + 2) | (count as u32 - 1) << FIRST_BITS | first as u32
}

/// The packet range of a leaf's child word (without `LEAF_BIT`).
#[inline(always)]
pub(super) fn leaf_packets(word: u32) -> std::ops::Range<usize> {
    let first = (word & ((1 << FIRST_BITS) - 1)) as usize;
    first..first + ((word >> FIRST_BITS) & 3) as usize + 1
}

/// The slab axis of a leaf's child word (without `LEAF_BIT`), or `NO_SLAB`.
#[inline(always)]
pub(super) fn leaf_axis(word: u32) -> u8 {
    ((word >> (FIRST_BITS + 2)) & 3) as u8
}

/// Without a leaf's slab test: its word with the axis `NO_SLAB`.
pub(super) fn without_slab(word: u32) -> u32 {
    word | (NO_SLAB as u32) << (FIRST_BITS + 2)
}

/// Whether `ray` starts outside the slab `[lo, hi]` along `axis` and never re-enters it (exact comparisons: along
/// `axis` the ray's points at `t >= 0` are at least as far beyond the slab as its origin). NaN never qualifies.
#[inline(always)]
pub(super) fn moving_away(ray: &Ray, axis: u8, [lo, hi]: [f32; 2]) -> bool {
    let (o, d) = (ray.origin.to_array()[axis as usize], ray.dir.to_array()[axis as usize]);
    (o > hi && d >= 0.0) || (o < lo && d <= 0.0)
}

/// The slab of a leaf worth testing before its primitives: `(axis, lo, hi)` with `[lo, hi]` the exact extent of
/// primitives `ids` along the axis on which most of its triangles lie in a face of the leaf's box (walls, floors,
/// the faces of boxes: rays leave them away from the leaf), or axis 3 (no test) where no triangle does (a patch of a
/// curved mesh, whose rays leave from inside the box). `aabbs`: the primitives' padded boxes (shapes other than
/// triangles; a triangle is exactly the hull of its vertices, which the triangle test reads as they are).
pub(super) fn leaf_slab(ids: &[u32], prims: &Primitives, aabbs: &[Aabb]) -> (u8, f32, f32) {
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
        Some(a) => (a as u8, lo[a], hi[a]),
        None => (NO_SLAB, 0.0, 0.0),
    }
}
