//! The default BVH (`--accel bvh`), an 8-wide BVH for CPU single-ray traversal: a BVH2 with leaves of up to eight
//! primitives — the cheaper by surface-area cost of obvhs's PLOC tree and a top-down binned-SAH tree (`build.rs`; the
//! top-down build of `topdown.rs` alone when many primitives share a Morton cell) — collapsed into nodes of eight
//! children (`collapse.rs`; a node with slots to spare gives each analytic primitive that shares a leaf a leaf of
//! its own: `split_off_analytic`) whose boxes are stored as structure of arrays (each box plane's eight values side
//! by side), so one ray is tested against all eight boxes with one AVX operation per step where the CPU has AVX2, or
//! against four with one SSE operation elsewhere (`boxes.rs`; the same traversal bit for bit either way), and leaves
//! hold their triangles four to a [`TriPacket`](crate::geometry::TriPacket) (the same conservative SIMD pre-filter
//! and exact watertight test the kd-tree uses); a leaf whose triangles lie in a face of its box (walls, floors, a
//! block's faces) keeps that slab, and a ray that starts beyond it moving away skips the leaf (`leaf.rs`: exact
//! comparisons, so the same answers). A leaf's slot in its parent holds its packet range and slab axis itself, so a
//! leaf costs no load before its packets (and a leaf skipped by its slab none of them). With AVX2 the whole query is
//! compiled for AVX2 and FMA through `pulp` (safe Rust; the features are detected at run time) — Rust never fuses a
//! multiply and an add on its own, so the answers do not change with the target.
//!
//! Why not obvhs's own CWBVH traversal (still available as `--accel cwbvh`, `cwbvh.rs`): its 8-wide nodes are
//! quantised for GPU memory bandwidth (Ylitie et al. 2017), so every node visit first decompresses eight boxes; on
//! a CPU core the uncompressed layout tests the same boxes with fewer instructions and no per-child decode
//! (see `docs/decisions/0001-wide-bvh-default.md`).
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
use crate::geometry::{Ray, WatertightRay};
use crate::primitives::{Hit, Primitives};
use boxes::{BoxTest, RayBoxes, RayBoxes8};
pub use build::{Candidate, SPLIT_SAMPLES_PER_PRIMITIVE, SpatialSplits};
use pulp::x86::V3;
use pulp::{Simd, WithSimd};
use std::time::Duration;

mod boxes;
mod build;
mod collapse;
mod leaf;
mod packet;
mod spatial_split;
pub(crate) mod topdown;

pub use packet::PACKET;

use super::leaf_packet::LeafPacket;
pub(crate) use leaf::MAX_PRIMITIVES;
use leaf::{NO_SLAB, leaf_axis, leaf_packets, moving_away, without_slab};

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

/// `--accel bvh`, the default: the 8-wide BVH with structure-of-arrays boxes and packet leaves (see the module
/// notes).
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
            None => self.run_scalar::<ANY, C>(prims, ray, counter),
        }
    }

    /// [`WideBvh::run`] on CPUs without AVX2: out of line, so that the dispatch inlined into its callers stays a
    /// test and a call.
    #[inline(never)]
    fn run_scalar<const ANY: bool, C: WorkCounter>(
        &self,
        prims: &Primitives,
        ray: &Ray,
        counter: &mut C,
    ) -> Option<Hit> {
        self.query::<ANY, C, _>(prims, ray, counter, &RayBoxes::new(ray))
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
