//! The BVH2 collapsed into the wide tree: each inner node opens its children of largest surface area until it has
//! `WIDTH` (eight) of them, each child a subtree (a node of its own) or a leaf (its primitives packed four to a
//! leaf packet, `accel/leaf_packet.rs`, with the slab of a leaf whose triangles lie in one face of its box). Two
//! BVH2 leaves whose boxes nearly coincide become one leaf (`merged_leaf_ids`), and analytic primitives that share a
//! leaf get one of their own while the node has slots to spare (`split_off_analytic`). Nodes are written depth
//! first, a parent before its children.

use super::leaf::{leaf_slab, leaf_word};
use super::{EMPTY, LEAF_BIT, Node, WIDTH, WideBvh};
use crate::accel::leaf_packet::pack_leaf;
use crate::primitives::Primitives;
use obvhs::{aabb::Aabb, bvh2::Bvh2};

/// A child of a node being collapsed: a BVH2 subtree, or the primitives of one leaf, with its box.
enum Kid {
    Subtree(usize, Aabb),
    Leaf(Vec<u32>, Aabb),
}

impl Kid {
    fn aabb(&self) -> &Aabb {
        match self {
            Kid::Subtree(_, a) | Kid::Leaf(_, a) => a,
        }
    }
}

/// Give analytic primitives (ids `>= num_tris`: spheres, revolutions, patches) that share a leaf with others a
/// leaf of their own while the node has empty slots. A node tests all its slots' boxes in one operation, so the
/// extra box is free, while an analytic test (divisions, square roots, Newton steps) costs several triangle
/// tests: with its own tight box, only the rays that come near the shape pay for it. (On the sphere Cornell boxes
/// the BVH2 puts each sphere in a leaf with a wall, whose box every ray to that wall enters.)
fn split_off_analytic(kids: &mut Vec<Kid>, num_tris: u32, aabbs: &[Aabb]) {
    while kids.len() < WIDTH {
        let found = kids.iter().enumerate().find_map(|(i, kid)| match kid {
            Kid::Leaf(ids, _) if ids.len() > 1 => ids.iter().position(|&id| id >= num_tris).map(|j| (i, j)),
            _ => None,
        });
        let Some((i, j)) = found else { return };
        if let Kid::Leaf(ids, rest) = &mut kids[i] {
            let id = ids.remove(j);
            *rest = ids.iter().fold(Aabb::empty(), |b, &r| b.union(&aabbs[r as usize]));
            kids.push(Kid::Leaf(vec![id], aabbs[id as usize]));
        }
    }
}

impl WideBvh {
    /// The wide tree of `bvh2`, built over `aabbs` (the primitives' padded boxes).
    pub(super) fn from_bvh2(prims: &Primitives, aabbs: &[Aabb], bvh2: &Bvh2) -> Self {
        let mut out = Self::empty();
        out.root = out.collapse(bvh2, 0, prims, aabbs, 1);
        out
    }

    /// The primitives under BVH2 inner node `node` when its two children are leaves better tested as one: their
    /// boxes nearly coincide (the union's area within 10% of the larger child's, e.g. the two halves of a cube's
    /// faces) and together they fill fewer packets than apart. A ray entering either box enters both, so one leaf
    /// saves a box test, a stack entry and a half-empty packet.
    pub(super) fn merged_leaf_ids(bvh2: &Bvh2, node: usize) -> Option<Vec<u32>> {
        let nd = &bvh2.nodes[node];
        if nd.prim_count > 0 {
            return None;
        }
        let (a, b) = (&bvh2.nodes[nd.first_index as usize], &bvh2.nodes[nd.first_index as usize + 1]);
        let (na, nb) = (a.prim_count as usize, b.prim_count as usize);
        if na == 0 || nb == 0 || (na + nb).div_ceil(4) >= na.div_ceil(4) + nb.div_ceil(4) {
            return None;
        }
        if nd.aabb.half_area() > 1.1 * a.aabb.half_area().max(b.aabb.half_area()) {
            return None;
        }
        let range = |n: &obvhs::bvh2::node::Bvh2Node| n.first_index..n.first_index + n.prim_count;
        Some(range(a).chain(range(b)).map(|i| bvh2.primitive_indices[i as usize]).collect())
    }

    /// Pack primitives `ids` into a new leaf; returns the leaf's child slot. `aabbs`: the primitives' padded boxes.
    pub(super) fn add_leaf_ids(&mut self, ids: &[u32], prims: &Primitives, aabbs: &[Aabb]) -> u32 {
        // A primitive split by a spatial split may reach one leaf twice (two leaves of its halves merged): once.
        let mut unique = Vec::with_capacity(ids.len());
        for &id in ids {
            if !unique.contains(&id) {
                unique.push(id);
            }
        }
        let ids = &unique[..];
        let (axis, lo, hi) = leaf_slab(ids, prims, aabbs);
        let first = pack_leaf(ids, prims, &mut self.packets);
        self.slabs.resize(self.packets.len(), [0.0; 2]);
        self.slabs[first as usize] = [lo, hi];
        let word = leaf_word(first as usize, self.packets.len() - first as usize, axis);
        self.leaves.push(word);
        LEAF_BIT | word
    }

    /// The primitives of BVH2 node `k` if it becomes one leaf (a BVH2 leaf, or two leaves merged).
    pub(super) fn leaf_ids(bvh2: &Bvh2, k: usize) -> Option<Vec<u32>> {
        let nd = &bvh2.nodes[k];
        if nd.prim_count > 0 {
            let range = nd.first_index..nd.first_index + nd.prim_count;
            return Some(range.map(|i| bvh2.primitive_indices[i as usize]).collect());
        }
        Self::merged_leaf_ids(bvh2, k)
    }

    /// Collapse the BVH2 subtree at `node` into 8-wide nodes (depth first, a parent before its children); returns
    /// its child slot. `aabbs` are the primitives' (padded) boxes the BVH2 was built from.
    pub(super) fn collapse(
        &mut self,
        bvh2: &Bvh2,
        node: usize,
        prims: &Primitives,
        aabbs: &[Aabb],
        depth: usize,
    ) -> u32 {
        self.depth = self.depth.max(depth);
        if let Some(ids) = Self::leaf_ids(bvh2, node) {
            return self.add_leaf_ids(&ids, prims, aabbs);
        }
        let nd = &bvh2.nodes[node];
        // Open the inner child of largest surface area until there are WIDTH children.
        let mut kids = vec![nd.first_index as usize, nd.first_index as usize + 1];
        while kids.len() < WIDTH {
            let best = kids
                .iter()
                .enumerate()
                .filter(|(_, k)| Self::leaf_ids(bvh2, **k).is_none())
                .max_by(|a, b| bvh2.nodes[*a.1].aabb.half_area().total_cmp(&bvh2.nodes[*b.1].aabb.half_area()))
                .map(|(i, _)| i);
            let Some(i) = best else { break };
            let k = kids.swap_remove(i);
            let first = bvh2.nodes[k].first_index as usize;
            kids.extend([first, first + 1]);
        }
        let mut kids: Vec<Kid> = kids
            .into_iter()
            .map(|k| match Self::leaf_ids(bvh2, k) {
                Some(ids) => Kid::Leaf(ids, bvh2.nodes[k].aabb),
                None => Kid::Subtree(k, bvh2.nodes[k].aabb),
            })
            .collect();
        split_off_analytic(&mut kids, prims.num_tris(), aabbs);
        let me = self.nodes.len();
        // Empty slots: a box from +inf to -inf, which no ray meets.
        let mut b = [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ];
        for (lane, kid) in kids.iter().enumerate() {
            let a = kid.aabb();
            for axis in 0..3 {
                b[axis][lane] = a.min[axis];
                b[3 + axis][lane] = a.max[axis];
            }
        }
        self.nodes.push(Node { b, child: [EMPTY; WIDTH] });
        for (lane, kid) in kids.iter().enumerate() {
            let slot = match kid {
                Kid::Subtree(k, _) => self.collapse(bvh2, *k, prims, aabbs, depth + 1),
                Kid::Leaf(ids, _) => {
                    self.depth = self.depth.max(depth + 1);
                    self.add_leaf_ids(ids, prims, aabbs)
                }
            };
            self.nodes[me].child[lane] = slot;
        }
        me as u32
    }
}
