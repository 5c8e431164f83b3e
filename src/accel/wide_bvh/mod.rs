//! The default BVH (`--accel bvh`), an 8-wide BVH for CPU single-ray traversal: a BVH2 with leaves of up to eight
//! primitives — the cheaper by surface-area cost of obvhs's PLOC tree and a top-down binned-SAH tree (`build.rs`; the
//! top-down build of `bvh_topdown.rs` alone when many primitives share a Morton cell) — collapsed into nodes of eight
//! children (a node with slots to spare gives each analytic primitive that shares a leaf a leaf of its own:
//! `split_off_analytic`) whose boxes are stored as structure of arrays (each box plane's eight values side by side), so
//! one ray is tested against all eight boxes with one AVX operation per step where the CPU has AVX2, or against four
//! with one SSE operation elsewhere (`boxes.rs`; the same traversal bit for bit either way), and leaves hold their
//! triangles four to a [`TriPacket`] (the same conservative SIMD pre-filter and exact watertight test the kd-tree
//! uses); a leaf whose triangles lie in a face of its box (walls, floors, a block's faces) keeps that slab, and a ray
//! that starts beyond it moving away skips the leaf (`leaf.rs`: exact comparisons, so the same answers). A leaf's slot
//! in its parent holds its packet range and slab axis itself, so a leaf costs no load before its packets (and a leaf
//! skipped by its slab none of them). With AVX2 the whole query is compiled for AVX2 and FMA through `pulp` (safe Rust;
//! the features are detected at run time) — Rust never fuses a multiply and an add on its own, so the answers do not
//! change with the target.
//!
//! Why not obvhs's own CWBVH traversal (still available as `--accel cwbvh`, `bvh.rs`): its 8-wide nodes are
//! quantised for GPU memory bandwidth (Ylitie et al. 2017), so every node visit first decompresses eight boxes; on
//! a CPU core the uncompressed layout tests the same boxes with fewer instructions and no per-child decode
//! (measured in the README's performance section).
//!
//! Traversal: ordered (children pushed far to near by their entry distance, so the nearest is taken first; with
//! three or more, each child's stack slot is counted without branches, `BoxTest::stack_slots`), with a
//! 32-entry stack, which a query that would overflow it (rare) exchanges for one sized from the tree's depth by
//! starting again; box tests are robust to axis-parallel rays (reciprocals clamped to +-1e25, -0 treated as +0)
//! and conservative against rounding (the exit distance is scaled by `1 + 2 gamma(3)`, Ize 2013). Occlusion stops
//! at the first hit. A leaf's triangles that survive the pre-filter are finished four at a time when two or more do
//! (closest hit); a lone survivor is read from its packet by a permute, or by a branch on its lane for rays marked
//! [`Ray::coherent`] (camera rays, which predict it).
//!
//! Packets (`packet.rs`): up to sixteen coherent rays (a pixel's camera rays) go down the tree together, every box
//! and triangle tested against all of them lane by lane ([`Accelerator::intersect_packet`]); each ray gets its
//! lone query's closest hit.

use super::work::{NoCount, TraversalWork, WorkCounter};
use super::{AccelStats, Accelerator};
use crate::geometry::{Ray, TriPacket, WatertightRay};
use crate::primitives::{Hit, Primitives};
use boxes::{BoxTest, RayBoxes, RayBoxes8};
pub use build::{Candidate, SPLIT_SAMPLES_PER_PRIMITIVE, SpatialSplits};
use glam::Vec3A;
use obvhs::{aabb::Aabb, bvh2::Bvh2};
use pulp::x86::V3;
use pulp::{Simd, WithSimd};
use std::time::Duration;

mod boxes;
mod build;
mod leaf;
mod packet;

pub use packet::PACKET;

pub(crate) use leaf::MAX_PRIMITIVES;
use leaf::{LeafPacket, NO_SLAB, leaf_axis, leaf_packets, leaf_slab, leaf_word, moving_away, without_slab};

/// Child slot markers.
const LEAF_BIT: u32 = 1 << 31;
const EMPTY: u32 = u32::MAX;
/// The full traversal stack kept on the call stack (after a restart); trees deeper than `STACK / (WIDTH - 1)`
/// (degenerate input: thousands of identical boxes) traverse with a heap stack sized from their depth instead.
const STACK: usize = 128;

/// Children per node.
const WIDTH: usize = 8;

/// `WIDTH` children, box planes as lanes: `b[0..3]` = min x, y, z, `b[3..6]` = max x, y, z of child `lane` at
/// `[plane][lane]` (one 8-wide AVX load per plane, or two 4-wide SSE loads).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    b: [[f32; WIDTH]; 6],
    /// Inner child: node index; leaf: `LEAF_BIT | leaf index`; `EMPTY`: no child.
    child: [u32; WIDTH],
}

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

pub struct WideBvh {
    nodes: Vec<Node>,
    /// Each leaf's child word (without `LEAF_BIT`), in the order they were made (for tools and statistics: the
    /// traversal reads a leaf's packets from its parent's slot).
    leaves: Vec<u32>,
    /// A leaf's slab `[lo, hi]` along its axis at the index of its first packet (unused where the axis is
    /// `NO_SLAB`, and at the other packets).
    slabs: Vec<[f32; 2]>,
    packets: Vec<LeafPacket>,
    /// The root: a node, or a lone leaf (`LEAF_BIT`), or `EMPTY`.
    root: u32,
    /// Depth of the deepest node (a traversal stack needs at most `WIDTH - 1` entries per level, plus a few).
    depth: usize,
    /// AVX2 and FMA, if this CPU has them: the 8-wide box test (`boxes.rs`).
    avx: Option<V3>,
    /// Entries of the stack a query starts with (32; fewer in tests, to force the restart with a full one).
    first_stack: usize,
    pub(super) build_time: Duration,
}

impl WideBvh {
    /// The wide BVH over `prims`: of the two candidate trees (PLOC's and a binned-SAH top-down build with spatial
    /// splits), the one cheaper to traverse by the surface-area cost (`build.rs`); the top-down build alone for
    /// degenerate input.
    pub fn build(prims: &Primitives) -> Self {
        build::build(prims, None, SpatialSplits::Yes)
    }

    /// As [`WideBvh::build`], with or without the SAH candidate's spatial splits.
    pub fn build_with(prims: &Primitives, splits: SpatialSplits) -> Self {
        build::build(prims, None, splits)
    }

    /// The tree of one candidate build (for tests and comparisons; `build` picks the cheaper), the SAH candidate
    /// with spatial splits.
    pub fn build_candidate(prims: &Primitives, candidate: Candidate) -> Self {
        build::build(prims, Some(candidate), SpatialSplits::Yes)
    }

    /// Primitive references in the leaves: the primitive count, plus the extra references of triangles that spatial
    /// splits put in more than one leaf.
    pub fn references(&self) -> usize {
        self.packets.iter().map(|p| (p.tri_lanes | p.other_lanes).count_ones() as usize).sum()
    }

    /// An empty tree.
    fn empty() -> Self {
        WideBvh {
            nodes: vec![],
            leaves: vec![],
            slabs: vec![],
            packets: vec![],
            root: EMPTY,
            depth: 0,
            avx: V3::try_new(),
            first_stack: 32,
            build_time: Duration::ZERO,
        }
    }

    /// The wide tree of `bvh2`, built over `aabbs` (the primitives' padded boxes).
    fn from_bvh2(prims: &Primitives, aabbs: &[Aabb], bvh2: &Bvh2) -> Self {
        let mut out = Self::empty();
        out.root = out.collapse(bvh2, 0, prims, aabbs, 1);
        out
    }

    /// A text dump of the tree (debugging): one line per node with its children's boxes.
    pub fn dump(&self) -> String {
        let mut out = String::new();
        for (i, n) in self.nodes.iter().enumerate() {
            out += &format!("node {i}:\n");
            for lane in 0..WIDTH {
                let c = n.child[lane];
                if c == EMPTY {
                    continue;
                }
                let what = if c & LEAF_BIT != 0 {
                    let packets = leaf_packets(c & !LEAF_BIT);
                    let n: u32 =
                        self.packets[packets.clone()].iter().map(|p| (p.tri_lanes | p.other_lanes).count_ones()).sum();
                    format!("leaf of packets {packets:?} ({n} prims)")
                } else {
                    format!("node {c}")
                };
                out += &format!(
                    "  {what}: [{:.2} {:.2} {:.2}] - [{:.2} {:.2} {:.2}]\n",
                    n.b[0][lane], n.b[1][lane], n.b[2][lane], n.b[3][lane], n.b[4][lane], n.b[5][lane]
                );
            }
        }
        out
    }

    /// The primitives under BVH2 inner node `node` when its two children are leaves better tested as one: their
    /// boxes nearly coincide (the union's area within 10% of the larger child's, e.g. the two halves of a cube's
    /// faces) and together they fill fewer packets than apart. A ray entering either box enters both, so one leaf
    /// saves a box test, a stack entry and a half-empty packet.
    fn merged_leaf_ids(bvh2: &Bvh2, node: usize) -> Option<Vec<u32>> {
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
    fn add_leaf_ids(&mut self, ids: &[u32], prims: &Primitives, aabbs: &[Aabb]) -> u32 {
        // A primitive split by a spatial split may reach one leaf twice (two leaves of its halves merged): once.
        let mut unique = Vec::with_capacity(ids.len());
        for &id in ids {
            if !unique.contains(&id) {
                unique.push(id);
            }
        }
        let ids = &unique[..];
        let nt = prims.num_tris();
        let (axis, lo, hi) = leaf_slab(ids, prims, aabbs);
        let (mut ordered, others): (Vec<u32>, Vec<u32>) = ids.iter().partition(|&&id| id < nt);
        ordered.extend(others);
        let first = self.packets.len() as u32;
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
            self.packets.push(p);
        }
        self.slabs.resize(self.packets.len(), [0.0; 2]);
        self.slabs[first as usize] = [lo, hi];
        let word = leaf_word(first as usize, self.packets.len() - first as usize, axis);
        self.leaves.push(word);
        LEAF_BIT | word
    }

    /// The primitives of BVH2 node `k` if it becomes one leaf (a BVH2 leaf, or two leaves merged).
    fn leaf_ids(bvh2: &Bvh2, k: usize) -> Option<Vec<u32>> {
        let nd = &bvh2.nodes[k];
        if nd.prim_count > 0 {
            let range = nd.first_index..nd.first_index + nd.prim_count;
            return Some(range.map(|i| bvh2.primitive_indices[i as usize]).collect());
        }
        Self::merged_leaf_ids(bvh2, k)
    }

    /// Collapse the BVH2 subtree at `node` into 8-wide nodes (depth first, a parent before its children); returns
    /// its child slot. `aabbs` are the primitives' (padded) boxes the BVH2 was built from.
    fn collapse(&mut self, bvh2: &Bvh2, node: usize, prims: &Primitives, aabbs: &[Aabb], depth: usize) -> u32 {
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

    /// Test the leaf of child word `leaf` (without `LEAF_BIT`); returns true when `ANY` and something was hit.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn test_leaf<const ANY: bool, C: WorkCounter, B: BoxTest>(
        &self,
        rb: &B,
        leaf: u32,
        prims: &Primitives,
        ray: &Ray,
        wt: &WatertightRay,
        end: &mut f32,
        best: &mut Option<Hit>,
        counter: &mut C,
    ) -> bool {
        let packets = leaf_packets(leaf);
        let axis = leaf_axis(leaf);
        if axis != NO_SLAB && moving_away(ray, axis, self.slabs[packets.start]) {
            return false;
        }
        for p in &self.packets[packets] {
            for _ in 0..(p.tri_lanes | p.other_lanes).count_ones() {
                counter.prim();
            }
            let mut candidates = wt.packet_candidates(&p.tris) & p.tri_lanes as u32;
            if !ANY && candidates & (candidates - 1) != 0 {
                // Closest hit, two or more lanes left: the rest of the watertight test for all four at once,
                // lane after lane as the scalar kernel would (`intersect_packet`), not one lane at a time.
                let leaves = p.ids.iter().enumerate().fold(0, |m, (k, &id)| m | ((id == ray.leaves) as u32) << k);
                if let Some((lane, h)) = wt.intersect_packet(&p.tris, candidates & !leaves, *end) {
                    *end = h.t;
                    *best = Some(Hit { t: h.t, prim: p.ids[lane], b1: h.b1, b2: h.b2 });
                }
                candidates = 0;
            }
            while candidates != 0 {
                let lane = candidates.trailing_zeros() as usize;
                candidates &= candidates - 1;
                if p.ids[lane] == ray.leaves {
                    // The triangle the ray leaves cannot be hit again (see `Ray::leaves`): no exact test.
                    continue;
                }
                // Coherent rays predict a branch on the lane; a permute costs the others less (`Ray::coherent`).
                let tri = if ray.coherent { p.tris.lane(lane) } else { rb.packet_lane(&p.tris, lane) };
                if let Some(h) = wt.intersect_soa(&tri, *end) {
                    *end = h.t;
                    *best = Some(Hit { t: h.t, prim: p.ids[lane], b1: h.b1, b2: h.b2 });
                    if ANY {
                        return true;
                    }
                }
            }
            let mut others = p.other_lanes as u32;
            while others != 0 {
                let lane = others.trailing_zeros() as usize;
                others &= others - 1;
                if let Some(h) = prims.intersect_bounded(p.ids[lane], &Ray { tmax: *end, ..*ray }, wt) {
                    *end = h.t;
                    *best = Some(h);
                    if ANY {
                        return true;
                    }
                }
            }
        }
        false
    }

    #[inline(always)]
    fn query<const ANY: bool, C: WorkCounter, B: BoxTest>(
        &self,
        prims: &Primitives,
        ray: &Ray,
        counter: &mut C,
        rb: &B,
    ) -> Option<Hit> {
        if self.root == EMPTY {
            return None;
        }
        // Zeroing the stack is part of every query's cost (a `memset` of up to 1 KiB on deep trees), so every
        // query starts with 32 entries, enough for all but rare rays; one that would overflow them starts again
        // with a stack that fits the tree's depth (the same answer and, counted afresh, the same work).
        let saved = *counter;
        let mut small = [(0u32, 0f32); 32];
        let first = &mut small[..self.first_stack];
        if let Some(hit) = self.query_with::<ANY, C, B>(prims, ray, counter, first, rb) {
            return hit;
        }
        *counter = saved;
        let need = (WIDTH - 1) * self.depth + 4;
        let done = if need <= STACK {
            let mut stack = [(0u32, 0f32); STACK];
            self.query_with::<ANY, C, B>(prims, ray, counter, &mut stack, rb)
        } else {
            let mut stack = vec![(0u32, 0f32); need];
            self.query_with::<ANY, C, B>(prims, ray, counter, &mut stack, rb)
        };
        done.unwrap_or(None)
    }

    /// The traversal, testing boxes with `rb`; `None` if `stack` would overflow (never with `(WIDTH - 1) depth + 4`
    /// entries or more).
    #[inline(always)]
    fn query_with<const ANY: bool, C: WorkCounter, B: BoxTest>(
        &self,
        prims: &Primitives,
        ray: &Ray,
        counter: &mut C,
        stack: &mut [(u32, f32)],
        rb: &B,
    ) -> Option<Option<Hit>> {
        let wt = WatertightRay::new(ray);
        let mut best: Option<Hit> = None;
        let mut end = ray.tmax;
        let mut sp = 0usize;
        let mut cur = self.root;
        loop {
            if cur & LEAF_BIT != 0 {
                if self.test_leaf::<ANY, C, B>(rb, cur & !LEAF_BIT, prims, ray, &wt, &mut end, &mut best, counter) {
                    return Some(best);
                }
            } else {
                counter.node();
                let n = &self.nodes[cur as usize];
                let (t, mask) = rb.test(n, end);
                if mask != 0 {
                    if sp + WIDTH > stack.len() {
                        return None;
                    }
                    let first = mask.trailing_zeros() as usize;
                    let rest = mask & (mask - 1);
                    if rest == 0 {
                        // One child: no stack traffic.
                        cur = n.child[first];
                        continue;
                    }
                    if ANY {
                        // Occlusion: any order will do.
                        cur = n.child[first];
                        let mut m = rest;
                        while m != 0 {
                            let i = m.trailing_zeros() as usize;
                            m &= m - 1;
                            stack[sp] = (n.child[i], t[i]);
                            sp += 1;
                        }
                        continue;
                    }
                    let second = rest.trailing_zeros() as usize;
                    if rest & (rest - 1) == 0 {
                        // Two children: take the nearer, push the farther.
                        let (near, far) = if t[first] <= t[second] { (first, second) } else { (second, first) };
                        stack[sp] = (n.child[far], t[far]);
                        sp += 1;
                        cur = n.child[near];
                        continue;
                    }
                    // Three or more: all eight written far to near (the children not hit above the stack pointer),
                    // then pop the nearest.
                    let slots = rb.stack_slots(&t, mask);
                    let top = &mut stack[sp..sp + WIDTH];
                    for i in 0..WIDTH {
                        top[slots[i] as usize & (WIDTH - 1)] = (n.child[i], t[i]);
                    }
                    sp += mask.count_ones() as usize;
                }
            }
            // Next: the nearest pending child that starts before the closest hit so far.
            loop {
                if sp == 0 {
                    return Some(best);
                }
                sp -= 1;
                let (c, t) = stack[sp];
                if t <= end {
                    cur = c;
                    break;
                }
            }
        }
    }
}

/// A query run compiled for AVX2 and FMA (`pulp` enables the features for [`WithSimd::with_simd`], and everything
/// below it is inlined), with the 8-wide box test.
struct AvxQuery<'a, const ANY: bool, C> {
    simd: V3,
    bvh: &'a WideBvh,
    prims: &'a Primitives,
    ray: &'a Ray,
    counter: &'a mut C,
}

impl<const ANY: bool, C: WorkCounter> WithSimd for AvxQuery<'_, ANY, C> {
    type Output = Option<Hit>;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) -> Option<Hit> {
        let rb = RayBoxes8::new(self.simd, self.ray);
        self.bvh.query::<ANY, C, _>(self.prims, self.ray, self.counter, &rb)
    }
}

impl WideBvh {
    /// Use the 4-wide SSE box test even where AVX2 is available (for tests and comparisons: the answers are the
    /// same bit for bit, only the speed differs).
    pub fn use_baseline_boxes(&mut self) {
        self.avx = None;
    }

    /// Test every leaf's primitives even where the ray moves away from the leaf's slab (for tests: the answers
    /// must not change, only the work).
    pub fn disable_leaf_slabs(&mut self) {
        for l in &mut self.leaves {
            *l = without_slab(*l);
        }
        for n in &mut self.nodes {
            for c in &mut n.child {
                if *c != EMPTY && *c & LEAF_BIT != 0 {
                    *c = LEAF_BIT | without_slab(*c & !LEAF_BIT);
                }
            }
        }
        if self.root != EMPTY && self.root & LEAF_BIT != 0 {
            self.root = LEAF_BIT | without_slab(self.root & !LEAF_BIT);
        }
    }

    /// The primitives of each leaf, in leaf order (for tests and tools).
    pub fn leaf_primitives(&self) -> Vec<Vec<u32>> {
        self.leaves
            .iter()
            .map(|l| {
                let mut ids = vec![];
                for p in &self.packets[leaf_packets(*l)] {
                    let used = p.tri_lanes | p.other_lanes;
                    ids.extend((0..4).filter(|&k| used & (1 << k) != 0).map(|k| p.ids[k]));
                }
                ids
            })
            .collect()
    }

    /// Start every query with a stack of only `entries` (at most 32) so that most overflow it and start again
    /// with a full one (for tests: the answers and the work counted must not change).
    pub fn set_first_stack(&mut self, entries: usize) {
        self.first_stack = entries.min(32);
    }

    /// Whether queries use the 8-wide AVX box test.
    pub fn uses_avx_boxes(&self) -> bool {
        self.avx.is_some()
    }

    /// A query with the widest box test this CPU runs.
    #[inline(always)]
    fn run<const ANY: bool, C: WorkCounter>(&self, prims: &Primitives, ray: &Ray, counter: &mut C) -> Option<Hit> {
        match self.avx {
            Some(simd) => Simd::vectorize(simd, AvxQuery::<ANY, C> { simd, bvh: self, prims, ray, counter }),
            None => self.query::<ANY, C, _>(prims, ray, counter, &RayBoxes::new(ray)),
        }
    }
}

impl Accelerator for WideBvh {
    #[inline]
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        self.run::<false, _>(prims, ray, &mut NoCount)
    }

    #[inline]
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        self.run::<true, _>(prims, ray, &mut NoCount).is_some()
    }

    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        self.run::<false, _>(prims, ray, work)
    }

    /// Sixteen rays at a time down the tree together (`packet.rs`), where the CPU has AVX2 or AVX-512.
    fn intersect_packet(&self, prims: &Primitives, rays: &[Ray], out: &mut [Option<Hit>]) {
        for (rays, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            if self.avx.is_some() {
                packet::intersect_packet(self, prims, rays, out);
            } else {
                for (o, r) in out.iter_mut().zip(rays) {
                    *o = self.intersect(prims, r);
                }
            }
        }
    }

    fn stats(&self) -> AccelStats {
        AccelStats {
            kind: "bvh",
            build_time: self.build_time,
            memory_bytes: self.nodes.len() * std::mem::size_of::<Node>()
                + self.leaves.len() * std::mem::size_of::<u32>()
                + self.slabs.len() * std::mem::size_of::<[f32; 2]>()
                + self.packets.len() * std::mem::size_of::<LeafPacket>(),
            nodes: self.nodes.len(),
            detail: format!(
                "{} 8-wide nodes, depth {}, {} leaves, {} packets",
                self.nodes.len(),
                self.depth,
                self.leaves.len(),
                self.packets.len()
            ),
        }
    }
}
