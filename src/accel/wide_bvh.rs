//! The default BVH (`--accel bvh`), an 8-wide BVH for CPU single-ray traversal: built by obvhs (PLOC with
//! reinsertion, leaves of up to eight primitives; the top-down build of `bvh_fallback.rs` when many primitives share
//! a Morton cell), then collapsed into nodes of eight children whose boxes are stored as structure of arrays in two
//! groups of four, so one ray is tested against four boxes with one SIMD operation per slab (glam's `Vec4`, SSE on
//! x86-64), and leaves hold their triangles four to a [`TriPacket`] (the same conservative SIMD pre-filter and exact
//! watertight test the kd-tree uses).
//!
//! Why not obvhs's own CWBVH traversal (still available as `--accel cwbvh`, `bvh.rs`): its 8-wide nodes are
//! quantised for GPU memory bandwidth (Ylitie et al. 2017), so every node visit first decompresses eight boxes; on
//! a CPU core the uncompressed layout tests the same boxes with fewer instructions and no per-child decode
//! (measured in the README's performance section).
//!
//! Traversal: ordered (children pushed far to near by their entry distance, so the nearest is taken first), with a
//! fixed stack; box tests are robust to axis-parallel rays (reciprocals clamped to +-1e25, -0 treated as +0) and
//! conservative against rounding (the exit distance is scaled by `1 + 2 gamma(3)`, Ize 2013). Occlusion stops at
//! the first hit.

use super::work::{NoCount, TraversalWork, WorkCounter};
use super::{AccelStats, Accelerator};
use crate::geometry::{Ray, TriPacket, WatertightRay, gamma};
use crate::primitives::{Hit, Primitives};
use glam::{Vec3A, Vec4};
use obvhs::{BvhBuildParams, bvh2::Bvh2};
use std::time::Duration;

/// Child slot markers.
const LEAF_BIT: u32 = 1 << 31;
const EMPTY: u32 = u32::MAX;
/// Traversal stack kept on the call stack; trees deeper than `STACK / (WIDTH - 1)` (degenerate input: thousands of
/// identical boxes) traverse with a heap stack sized from their depth instead.
const STACK: usize = 128;

/// Groups of four children per node (`HALVES * 4` children; each group one SIMD box test).
const HALVES: usize = 2;
/// Children per node.
const WIDTH: usize = 4 * HALVES;

/// `WIDTH` children: per group of four, box planes as lanes (`b[g][0..3]` = min x, y, z; `b[g][3..6]` = max x, y, z).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node4 {
    b: [[Vec4; 6]; HALVES],
    /// Inner child: node index; leaf: `LEAF_BIT | leaf index`; `EMPTY`: no child.
    child: [u32; WIDTH],
}

/// A leaf's packets: `packets[first..first + count]`.
#[derive(Clone, Copy, Debug)]
struct LeafRange {
    first: u32,
    count: u32,
}

/// Up to four primitives of one leaf: triangles as a packet, other bounded shapes tested one by one.
#[derive(Clone, Copy, Debug, Default)]
struct LeafPacket {
    tris: TriPacket,
    ids: [u32; 4],
    tri_lanes: u8,
    other_lanes: u8,
}

pub struct WideBvh {
    nodes: Vec<Node4>,
    leaves: Vec<LeafRange>,
    packets: Vec<LeafPacket>,
    /// The root: a node, or a lone leaf (`LEAF_BIT`), or `EMPTY`.
    root: u32,
    /// Depth of the deepest node (a traversal stack needs at most 3 entries per level, plus one).
    depth: usize,
    pub(super) build_time: Duration,
}

/// The ray data of a traversal: origin, clamped reciprocal direction, and per axis whether the near plane is the
/// box's max (negative direction).
struct RayBoxes {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    near: [usize; 3],
    far: [usize; 3],
}

impl RayBoxes {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        const BIG: f32 = 1e25;
        let d = ray.dir + Vec3A::ZERO; // -0 becomes +0
        let r = d.recip();
        let inv = Vec3A::select(r.abs().cmpgt(Vec3A::splat(BIG)), Vec3A::splat(BIG).copysign(d), r);
        let neg = [d.x < 0.0, d.y < 0.0, d.z < 0.0];
        RayBoxes {
            o: [Vec4::splat(ray.origin.x), Vec4::splat(ray.origin.y), Vec4::splat(ray.origin.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            near: [neg[0] as usize * 3, 1 + neg[1] as usize * 3, 2 + neg[2] as usize * 3],
            far: [3 - neg[0] as usize * 3, 4 - neg[1] as usize * 3, 5 - neg[2] as usize * 3],
        }
    }

    /// Entry distances of four children and the mask of those the ray meets within `(0, tmax)`.
    #[inline(always)]
    fn test4(&self, b: &[Vec4; 6], tmax: f32) -> (Vec4, u32) {
        let t0 = (b[self.near[0]] - self.o[0]) * self.inv[0];
        let t1 = (b[self.near[1]] - self.o[1]) * self.inv[1];
        let t2 = (b[self.near[2]] - self.o[2]) * self.inv[2];
        let u0 = (b[self.far[0]] - self.o[0]) * self.inv[0];
        let u1 = (b[self.far[1]] - self.o[1]) * self.inv[1];
        let u2 = (b[self.far[2]] - self.o[2]) * self.inv[2];
        let tnear = t0.max(t1).max(t2.max(Vec4::ZERO));
        let tfar = u0.min(u1).min(u2.min(Vec4::splat(tmax))) * (1.0 + 2.0 * gamma(3));
        (tnear, tnear.cmple(tfar).bitmask())
    }

    /// Entry distances of every child and the mask of those the ray meets.
    #[inline(always)]
    fn test(&self, n: &Node4, tmax: f32) -> ([f32; WIDTH], u32) {
        let mut t = [0f32; WIDTH];
        let mut mask = 0;
        for g in 0..HALVES {
            let (tn, m) = self.test4(&n.b[g], tmax);
            t[4 * g..4 * g + 4].copy_from_slice(&tn.to_array());
            mask |= m << (4 * g);
        }
        (t, mask)
    }
}

impl WideBvh {
    pub fn build(prims: &Primitives) -> Self {
        let aabbs = super::bvh::padded_prim_aabbs(prims);
        let mut out = WideBvh {
            nodes: vec![],
            leaves: vec![],
            packets: vec![],
            root: EMPTY,
            depth: 0,
            build_time: Duration::ZERO,
        };
        if aabbs.is_empty() {
            return out;
        }
        let bvh2 = if super::bvh_fallback::needs_fallback(&aabbs) {
            // Many primitives in one Morton cell make PLOC quadratic and its tree a chain: build top-down instead.
            super::bvh_fallback::build_bvh2(&aabbs)
        } else {
            let params = BvhBuildParams { max_prims_per_leaf: 8, ..BvhBuildParams::medium_build() };
            obvhs::bvh2::builder::build_bvh2(&aabbs, params, &mut Duration::default())
        };
        out.root = out.collapse(&bvh2, 0, prims, 1);
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
                    let l = self.leaves[(c & !LEAF_BIT) as usize];
                    let n: u32 = self.packets[l.first as usize..(l.first + l.count) as usize]
                        .iter()
                        .map(|p| (p.tri_lanes | p.other_lanes).count_ones())
                        .sum();
                    format!("leaf {} ({n} prims)", c & !LEAF_BIT)
                } else {
                    format!("node {c}")
                };
                out += &format!(
                    "  {what}: [{:.2} {:.2} {:.2}] - [{:.2} {:.2} {:.2}]\n",
                    n.b[lane / 4][0][lane % 4],
                    n.b[lane / 4][1][lane % 4],
                    n.b[lane / 4][2][lane % 4],
                    n.b[lane / 4][3][lane % 4],
                    n.b[lane / 4][4][lane % 4],
                    n.b[lane / 4][5][lane % 4]
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

    /// Pack BVH2 leaf `node`'s primitives; returns the leaf's child slot.
    fn add_leaf(&mut self, bvh2: &Bvh2, node: usize, prims: &Primitives) -> u32 {
        let nd = &bvh2.nodes[node];
        let ids: Vec<u32> =
            (nd.first_index..nd.first_index + nd.prim_count).map(|i| bvh2.primitive_indices[i as usize]).collect();
        self.add_leaf_ids(&ids, prims)
    }

    /// Pack primitives `ids` into a new leaf; returns the leaf's child slot.
    fn add_leaf_ids(&mut self, ids: &[u32], prims: &Primitives) -> u32 {
        let nt = prims.num_tris();
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
        self.leaves.push(LeafRange { first, count: self.packets.len() as u32 - first });
        LEAF_BIT | (self.leaves.len() as u32 - 1)
    }

    /// Collapse the BVH2 subtree at `node` into 8-wide nodes (depth first, a parent before its children); returns
    /// its child slot.
    fn collapse(&mut self, bvh2: &Bvh2, node: usize, prims: &Primitives, depth: usize) -> u32 {
        self.depth = self.depth.max(depth);
        let nd = &bvh2.nodes[node];
        if nd.prim_count > 0 {
            return self.add_leaf(bvh2, node, prims);
        }
        if let Some(ids) = Self::merged_leaf_ids(bvh2, node) {
            return self.add_leaf_ids(&ids, prims);
        }
        // Open the inner child of largest surface area until there are WIDTH children.
        let mut kids = vec![nd.first_index as usize, nd.first_index as usize + 1];
        while kids.len() < WIDTH {
            let best = kids
                .iter()
                .enumerate()
                .filter(|(_, k)| bvh2.nodes[**k].prim_count == 0 && Self::merged_leaf_ids(bvh2, **k).is_none())
                .max_by(|a, b| bvh2.nodes[*a.1].aabb.half_area().total_cmp(&bvh2.nodes[*b.1].aabb.half_area()))
                .map(|(i, _)| i);
            let Some(i) = best else { break };
            let k = kids.swap_remove(i);
            let first = bvh2.nodes[k].first_index as usize;
            kids.extend([first, first + 1]);
        }
        let me = self.nodes.len();
        let empty = [
            [f32::INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::NEG_INFINITY; 4],
        ];
        let mut b = [empty; HALVES];
        for (lane, &k) in kids.iter().enumerate() {
            let a = bvh2.nodes[k].aabb;
            for axis in 0..3 {
                b[lane / 4][axis][lane % 4] = a.min[axis];
                b[lane / 4][3 + axis][lane % 4] = a.max[axis];
            }
        }
        self.nodes.push(Node4 { b: b.map(|g| g.map(Vec4::from_array)), child: [EMPTY; WIDTH] });
        for (lane, &k) in kids.iter().enumerate() {
            let slot = self.collapse(bvh2, k, prims, depth + 1);
            self.nodes[me].child[lane] = slot;
        }
        me as u32
    }

    /// Test leaf `leaf`; returns true when `ANY` and something was hit.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn test_leaf<const ANY: bool, C: WorkCounter>(
        &self,
        leaf: u32,
        prims: &Primitives,
        ray: &Ray,
        wt: &WatertightRay,
        end: &mut f32,
        best: &mut Option<Hit>,
        counter: &mut C,
    ) -> bool {
        let l = self.leaves[leaf as usize];
        for p in &self.packets[l.first as usize..(l.first + l.count) as usize] {
            for _ in 0..(p.tri_lanes | p.other_lanes).count_ones() {
                counter.prim();
            }
            let mut candidates = wt.packet_candidates(&p.tris) & p.tri_lanes as u32;
            while candidates != 0 {
                let lane = candidates.trailing_zeros() as usize;
                candidates &= candidates - 1;
                if p.ids[lane] == ray.leaves {
                    // The triangle the ray leaves cannot be hit again (see `Ray::leaves`): no exact test.
                    continue;
                }
                if let Some(h) = wt.intersect_soa(&p.tris.lane(lane), *end) {
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
    fn query<const ANY: bool, C: WorkCounter>(&self, prims: &Primitives, ray: &Ray, counter: &mut C) -> Option<Hit> {
        if self.root == EMPTY {
            return None;
        }
        // The smallest stack that fits: zeroing it is part of every query's cost.
        let need = (WIDTH - 1) * self.depth + 4;
        if need <= 32 {
            let mut stack = [(0u32, 0f32); 32];
            self.query_with::<ANY, C>(prims, ray, counter, &mut stack)
        } else if need <= STACK {
            let mut stack = [(0u32, 0f32); STACK];
            self.query_with::<ANY, C>(prims, ray, counter, &mut stack)
        } else {
            let mut stack = vec![(0u32, 0f32); (WIDTH - 1) * self.depth + 4];
            self.query_with::<ANY, C>(prims, ray, counter, &mut stack)
        }
    }

    /// The traversal with a stack of at least `3 depth + 4` entries.
    #[inline(always)]
    fn query_with<const ANY: bool, C: WorkCounter>(
        &self,
        prims: &Primitives,
        ray: &Ray,
        counter: &mut C,
        stack: &mut [(u32, f32)],
    ) -> Option<Hit> {
        let wt = WatertightRay::new(ray);
        let rb = RayBoxes::new(ray);
        let mut best: Option<Hit> = None;
        let mut end = ray.tmax;
        let mut sp = 0usize;
        let mut cur = self.root;
        loop {
            if cur & LEAF_BIT != 0 {
                if self.test_leaf::<ANY, C>(cur & !LEAF_BIT, prims, ray, &wt, &mut end, &mut best, counter) {
                    return best;
                }
            } else {
                counter.node();
                let n = &self.nodes[cur as usize];
                let (t, mut mask) = rb.test(n, end);
                if mask != 0 {
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
                    // Three or more: push far to near (insertion), then pop the nearest.
                    let base = sp;
                    while mask != 0 {
                        let i = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let e = (n.child[i], t[i]);
                        let mut j = sp;
                        while j > base && stack[j - 1].1 < e.1 {
                            stack[j] = stack[j - 1];
                            j -= 1;
                        }
                        stack[j] = e;
                        sp += 1;
                    }
                }
            }
            // Next: the nearest pending child that starts before the closest hit so far.
            loop {
                if sp == 0 {
                    return best;
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

impl Accelerator for WideBvh {
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
        AccelStats {
            kind: "bvh",
            build_time: self.build_time,
            memory_bytes: self.nodes.len() * std::mem::size_of::<Node4>()
                + self.leaves.len() * std::mem::size_of::<LeafRange>()
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
