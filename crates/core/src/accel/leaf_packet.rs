//! The leaf storage the kd-tree and the wide BVH share: a leaf's primitives four to a packet, its triangles first —
//! their vertices as one [`TriPacket`] (the SIMD pre-filter and the exact watertight test), other bounded shapes
//! (spheres, surfaces of revolution, patches) named by id and tested one by one.

use crate::geometry::TriPacket;
use crate::primitives::Primitives;
use glam::Vec3A;

/// Up to four primitives of one leaf: triangles in `tris` (lanes in `tri_lanes`), other bounded shapes (lanes in
/// `other_lanes`) tested directly; `ids[lane]` is the primitive (`u32::MAX` in empty lanes).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LeafPacket {
    pub(crate) tris: TriPacket,
    pub(crate) ids: [u32; 4],
    pub(crate) tri_lanes: u8,
    pub(crate) other_lanes: u8,
}

/// Primitives `ids` packed into leaf packets appended to `out`, triangles first (so a leaf's triangles fill as few
/// packets as they can); returns the index of the first.
pub(crate) fn pack_leaf(ids: &[u32], prims: &Primitives, out: &mut Vec<LeafPacket>) -> u32 {
    let nt = prims.num_tris();
    let (mut ordered, others): (Vec<u32>, Vec<u32>) = ids.iter().partition(|&&id| id < nt);
    ordered.extend(others);
    let first = out.len() as u32;
    for chunk in ordered.chunks(4) {
        let mut p = LeafPacket { ids: [u32::MAX; 4], ..Default::default() };
        let mut verts = Vec::with_capacity(4);
        for (lane, &id) in chunk.iter().enumerate() {
            p.ids[lane] = id;
            if id < nt {
                p.tri_lanes |= 1 << lane;
                verts.push(prims.tris[id as usize]);
            } else {
                p.other_lanes |= 1 << lane;
                verts.push([Vec3A::ZERO; 3]);
            }
        }
        p.tris = TriPacket::new(&verts);
        out.push(p);
    }
    first
}
