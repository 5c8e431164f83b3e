//! SAH kd-tree: a flat array of 8-byte nodes with `u32` indices (the "below" child follows its parent, the
//! "above" child's index is stored), leaves pointing into one array of primitive ids, traversed front to back
//! with a fixed stack of 64 entries (Jansen 1986; Havran 2000; pbrt-v3 section 4.4). The build (Wald & Havran
//! 2006, O(N log N), with perfect splits) is in `build.rs`.
//!
//! Traversal: the ray is clipped to the (padded) root box; at an interior node the child on the origin's side is
//! visited first, the other pushed with the far part of the interval when the ray crosses the plane inside it. An
//! axis-parallel ray never crosses the plane: it visits the child its origin is in, or both if the origin lies on
//! the plane. A leaf's primitives are tested with the closest hit so far as the ray's end; a hit may lie beyond the
//! leaf (primitives straddle leaves), and traversal stops when the closest hit lies before the next node's entry,
//! which never misses a nearer one (nodes starting beyond it are popped and skipped).
//!
//! Leaves: each leaf's triangles are copied, four to a [`TriPacket`](crate::geometry::TriPacket), into one array in
//! leaf order (`leaf_packet.rs`, shared with the wide BVH), so a leaf is read from consecutive memory and its
//! triangles are pre-filtered four at a time by the watertight edge test;
//! only the survivors (usually none or one) go through the exact test that every accelerator shares. Analytic
//! shapes take lanes of their own and are tested through `Primitives`' analytic dispatch. Primitives in several leaves may be tested more than once
//! (no mailboxes: the packet test is cheaper than the bookkeeping).
//!
//! Parameters ([`KdParams`]): traversal and intersection costs, the empty-space bonus, the leaf size below which
//! no split is tried, and the depth limit `8 + 1.3 log2 N` capped at [`MAX_DEPTH`]. The default cost ratio
//! (a node visit costs 12 triangle tests) is measured, not textbook: with packet leaves a triangle is cheap and
//! a node visit (an unpredictable branch, often a cache miss) dear. Sweeping it on the Stanford bunny, the dragon
//! and bunny_40k (one thread, interleaved best-of-21 against the BVH), 2 gave kd/BVH times of 1.4-1.6x for
//! bounce and shadow rays, 8-16 gave 0.9-1.2x with 12 best overall, and build time falls with it (fewer, larger
//! leaves).

mod build;

use crate::accel::clip::{RayInv, clip_ray, padded};
use crate::accel::leaf_packet::{LeafPacket, pack_leaf};
use crate::accel::work::{NoCount, TraversalWork, WorkCounter};
use crate::accel::{AccelStats, Accelerator};
use crate::geometry::{Bounds, Ray, WatertightRay};
use crate::primitives::{Hit, Primitives};
use build::build_tree;
use std::time::Duration;

/// Hard depth limit; the traversal stack has room for it.
pub const MAX_DEPTH: u32 = 60;
const STACK: usize = 64;

/// Build parameters.
#[derive(Clone, Copy, Debug)]
pub struct KdParams {
    /// Cost of visiting an interior node, relative to...
    pub traversal_cost: f32,
    /// ...the cost of one primitive intersection test.
    pub intersection_cost: f32,
    /// Cost multiplier when one side of a split is empty (Wald & Havran: 0.8).
    pub empty_bonus: f32,
    /// Nodes with at most this many primitives become leaves without trying to split.
    pub max_leaf: u32,
    /// Depth limit (`None`: `8 + 1.3 log2 N`, at most [`MAX_DEPTH`]).
    pub max_depth: Option<u32>,
}

impl Default for KdParams {
    fn default() -> Self {
        KdParams { traversal_cost: 12.0, intersection_cost: 1.0, empty_bonus: 0.9, max_leaf: 1, max_depth: None }
    }
}

/// One node: interior `(split bits, above << 2 | axis)` or leaf `(first prim, count << 2 | 3)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KdNode {
    a: u32,
    b: u32,
}

impl KdNode {
    /// An interior node splitting `axis` (0, 1, 2) at the plane `split`: the "below" child is the next node, the
    /// "above" child is node `above` (below `2^30`).
    pub fn interior(axis: usize, split: f32, above: u32) -> Self {
        KdNode { a: split.to_bits(), b: (above << 2) | axis as u32 }
    }

    /// A leaf of `count` (below `2^30`) entries from index `first` of the tree's primitive (or packet) list.
    pub fn leaf(first: u32, count: u32) -> Self {
        KdNode { a: first, b: (count << 2) | 3 }
    }

    /// True for a leaf, false for an interior node.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.b & 3 == 3
    }

    /// The split axis (0 = x, 1 = y, 2 = z) of an interior node; 3 for a leaf.
    #[inline(always)]
    pub fn axis(&self) -> usize {
        (self.b & 3) as usize
    }

    /// The split plane's position along [`KdNode::axis`] (interior nodes only).
    #[inline(always)]
    pub fn split(&self) -> f32 {
        f32::from_bits(self.a)
    }

    /// Index of the "above" child, the side of larger coordinates (interior nodes only).
    #[inline(always)]
    pub fn above(&self) -> u32 {
        self.b >> 2
    }

    /// Index of the leaf's first entry in the primitive (or packet) list (leaves only).
    #[inline(always)]
    pub fn first(&self) -> u32 {
        self.a
    }

    /// Number of entries of the leaf (leaves only).
    #[inline(always)]
    pub fn count(&self) -> u32 {
        self.b >> 2
    }

    /// Shift child and primitive indices (when a subtree built on its own is appended to a larger tree).
    pub fn relocated(&self, node_offset: u32, prim_offset: u32) -> Self {
        if self.is_leaf() {
            KdNode::leaf(self.first() + prim_offset, self.count())
        } else {
            KdNode::interior(self.axis(), self.split(), self.above() + node_offset)
        }
    }
}

/// What the build produced.
#[derive(Clone, Debug, Default)]
pub struct KdTreeData {
    /// The nodes, root first, each "below" child right after its parent.
    pub nodes: Vec<KdNode>,
    /// Primitive ids of the leaves.
    pub prims: Vec<u32>,
    /// Depth of the deepest leaf (the root is depth 0).
    pub max_depth: u32,
}

/// `--accel kdtree`: the SAH kd-tree, its leaves' primitives in packets (see the module notes).
pub struct KdTree {
    /// Interior nodes as built; leaves re-pointed at their first packet in `packets` (count = packets).
    nodes: Vec<KdNode>,
    /// Each leaf's primitives, four to a packet, a leaf's packets consecutive: its triangles read from
    /// consecutive memory and pre-filtered four at a time.
    packets: Vec<LeafPacket>,
    references: usize,
    bounds: Bounds,
    depth: u32,
    num_prims: u32,
    pub(super) build_time: Duration,
}

/// Pack each leaf's primitives (triangles first) into packets and point the leaf nodes at them.
fn pack_leaves(prims: &Primitives, data: KdTreeData) -> (Vec<KdNode>, Vec<LeafPacket>) {
    let mut packets = Vec::new();
    let nodes = data
        .nodes
        .iter()
        .map(|n| {
            if !n.is_leaf() {
                return *n;
            }
            let ids = &data.prims[n.first() as usize..(n.first() + n.count()) as usize];
            let first = pack_leaf(ids, prims, &mut packets);
            KdNode::leaf(first, packets.len() as u32 - first)
        })
        .collect();
    (nodes, packets)
}

impl KdTree {
    /// Build over the bounded primitives of `prims` with the default [`KdParams`].
    pub fn build(prims: &Primitives) -> Self {
        Self::build_with(prims, KdParams::default())
    }

    /// Build over the bounded primitives of `prims` with the given costs and limits (for measuring them).
    pub fn build_with(prims: &Primitives, params: KdParams) -> Self {
        let n = prims.num_bounded();
        let bounds = if n == 0 { Bounds::EMPTY } else { padded(&prims.bounds) };
        let data = if n == 0 { KdTreeData::default() } else { build_tree(prims, bounds, params) };
        let (references, depth) = (data.prims.len(), data.max_depth);
        let (nodes, packets) = pack_leaves(prims, data);
        KdTree { nodes, packets, references, bounds, depth, num_prims: n, build_time: Duration::ZERO }
    }

    /// Depth of the deepest leaf.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The nodes, root first. Leaves point into the packet array: their `first` and `count` are packets, not
    /// primitives.
    pub fn nodes(&self) -> &[KdNode] {
        &self.nodes
    }

    /// Total primitive references in leaves.
    pub fn references(&self) -> usize {
        self.references
    }

    #[inline]
    fn query<const ANY: bool, C: WorkCounter>(&self, prims: &Primitives, ray: &Ray, counter: &mut C) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let ri = RayInv::new(ray.dir);
        let (mut tmin, mut tmax) = clip_ray(&self.bounds, ray.origin, &ri, 0.0, ray.tmax)?;
        let wt = WatertightRay::new(ray);
        // Per-axis ray data as 4-element arrays: indexing by a node's 2-bit axis is a plain load.
        let (origin, inv) = (ray.origin.extend(0.0).to_array(), ri.inv.extend(0.0).to_array());
        let parallel = [ri.parallel[0], ri.parallel[1], ri.parallel[2], false];
        let dir_down = ray.dir.extend(0.0).to_array().map(|d| d <= 0.0);
        let mut best: Option<Hit> = None;
        let mut end = ray.tmax;
        let mut stack = [(0u32, 0f32, 0f32); STACK];
        let mut sp = 0;
        let mut node = 0u32;
        loop {
            // A node that starts beyond the closest hit is skipped. Not `break`: the stack is not sorted by entry
            // when an axis-parallel ray in a split plane pushed a sibling with the same interval.
            if end < tmin {
                if sp == 0 {
                    break;
                }
                sp -= 1;
                (node, tmin, tmax) = stack[sp];
                continue;
            }
            counter.node();
            let n = self.nodes[node as usize];
            if !n.is_leaf() {
                let axis = n.axis();
                let split = n.split();
                let o = origin[axis];
                let (below, above) = (node + 1, n.above());
                if parallel[axis] {
                    if o < split {
                        node = below;
                    } else if o > split {
                        node = above;
                    } else {
                        stack[sp] = (above, tmin, tmax);
                        sp += 1;
                        node = below;
                    }
                    continue;
                }
                let t_plane = (split - o) * inv[axis];
                let below_first = o < split || (o == split && dir_down[axis]);
                let (first, second) = if below_first { (below, above) } else { (above, below) };
                if t_plane > tmax || t_plane <= 0.0 {
                    node = first;
                } else if t_plane < tmin {
                    node = second;
                } else {
                    stack[sp] = (second, t_plane, tmax);
                    sp += 1;
                    node = first;
                    tmax = t_plane;
                }
                continue;
            }
            let first = n.first() as usize;
            for p in &self.packets[first..first + n.count() as usize] {
                let lanes = p.tri_lanes | p.other_lanes;
                for _ in 0..lanes.count_ones() {
                    counter.prim();
                }
                let mut candidates = (wt.packet_candidates(&p.tris) & p.tri_lanes as u32) | p.other_lanes as u32;
                while candidates != 0 {
                    let lane = candidates.trailing_zeros() as usize;
                    candidates &= candidates - 1;
                    let id = p.ids[lane];
                    let hit = if p.tri_lanes & (1 << lane) != 0 {
                        wt.intersect_soa(&p.tris.lane(lane), end).map(|h| Hit { t: h.t, prim: id, b1: h.b1, b2: h.b2 })
                    } else if ANY {
                        let r = Ray { tmax: end, ..*ray };
                        prims.occludes_analytic(id, &r).then_some(Hit { t: 0.0, prim: id, b1: 0.0, b2: 0.0 })
                    } else {
                        prims.intersect_analytic(id, &Ray { tmax: end, ..*ray })
                    };
                    if let Some(h) = hit {
                        end = h.t;
                        best = Some(h);
                        if ANY {
                            return best;
                        }
                    }
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            (node, tmin, tmax) = stack[sp];
        }
        best
    }
}

impl Accelerator for KdTree {
    #[inline]
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        self.query::<false, _>(prims, ray, &mut NoCount)
    }

    #[inline]
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        self.query::<true, _>(prims, ray, &mut NoCount).is_some()
    }

    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        self.query::<false, _>(prims, ray, work)
    }

    fn stats(&self) -> AccelStats {
        let leaves = self.nodes.iter().filter(|n| n.is_leaf()).count();
        AccelStats {
            kind: "kdtree",
            build_time: self.build_time,
            memory_bytes: self.nodes.len() * std::mem::size_of::<KdNode>()
                + self.packets.len() * std::mem::size_of::<LeafPacket>(),
            nodes: self.nodes.len(),
            detail: format!(
                "depth {}, {} leaves, {:.2} refs/prim",
                self.depth,
                leaves,
                self.references as f64 / self.num_prims.max(1) as f64
            ),
        }
    }
}
