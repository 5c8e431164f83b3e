//! Which tree the wide BVH keeps: two candidate BVH2 builds, each collapsed into 8-wide nodes, and the one with the
//! lower surface-area cost kept.
//!
//! - **PLOC** (obvhs, parallel, with reinsertion and its leaf collapse: leaves of up to eight primitives where the
//!   surface-area model says so). On scenes of large, axis-aligned pieces (the Cornell boxes, the teapot in a
//!   stadium) it keeps each wall in a leaf of its own, which the leaf slabs then skip.
//! - **Binned SAH, top-down, with spatial splits** (`spatial_split.rs`: 32 bins on every axis, triangles split
//!   where the best object split's children overlap; then obvhs's leaf collapse). On meshes of uniform triangles it
//!   finds a tree 7-8% cheaper than PLOC's by the cost model (without its spatial splits it already traced the
//!   dragon's bounce rays 9% and the Stanford bunny's 12% faster; the splits cut the dragon's node tests per bounce
//!   ray by another 6%); on the box scenes it merges walls into shared leaves and is 20-50% slower.
//!
//! The cost of a wide tree, relative to its root's box: every node's box test weighs its box's area, every leaf
//! its box's area times its packets (the expected number of node tests and packet tests of a ray through the root
//! box, by the surface-area heuristic). It ranked the two candidates the way the bench's rays did on every scene
//! measured (see `docs/decisions/0002-two-candidate-trees.md`). The two builds run side by side (`rayon::join`);
//! inputs that make PLOC degenerate (many primitives in one Morton cell) get the top-down build alone, with its
//! robust binning.

use super::topdown::{self, Binning};
use super::{EMPTY, LEAF_BIT, Node, WIDTH, WideBvh, leaf_packets};
use crate::primitives::Primitives;
use obvhs::BvhBuildParams;
use std::time::Duration;

/// One of the two candidate builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Candidate {
    /// obvhs's PLOC with reinsertion.
    Ploc,
    /// Top-down binned SAH over every axis.
    Sah,
}

/// Whether the SAH candidate splits triangles (`spatial_split.rs`). Spatial splits cost the build about twice its time
/// (the dragon, 100k triangles: 80 -> 160 ms on two threads) and save traversal only in proportion to the rays
/// traced (its bounce rays 5-7% faster; a 256x256 render of it under an environment map at 64 spp 1.5% faster, which
/// does not yet repay the build): see [`SpatialSplits::for_samples`] and
/// `docs/decisions/0003-spatial-splits.md`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpatialSplits {
    /// Search spatial splits wherever the best object split's children overlap.
    Yes,
    /// Object splits only.
    No,
}

/// Camera samples per primitive from which a render builds the spatial splits.
pub const SPLIT_SAMPLES_PER_PRIMITIVE: u64 = 64;

impl SpatialSplits {
    /// For a render of `samples` camera samples (pixels x spp; `None`: unbounded, a time budget) over `primitives`
    /// bounded primitives: spatial splits when there are at least [`SPLIT_SAMPLES_PER_PRIMITIVE`] samples per
    /// primitive, where the traversal they save can repay their build (measured on the dragon: 256x256 at 64 spp,
    /// 42 samples per triangle, saves 35 ms of rendering for 80 ms more build; the saving grows with the samples,
    /// the build does not).
    pub fn for_samples(samples: Option<u64>, primitives: u64) -> Self {
        match samples {
            Some(s) if s < SPLIT_SAMPLES_PER_PRIMITIVE.saturating_mul(primitives) => SpatialSplits::No,
            _ => SpatialSplits::Yes,
        }
    }
}

/// obvhs's parameters for both candidates' leaf collapse (and PLOC's build).
const PARAMS: BvhBuildParams = BvhBuildParams { max_prims_per_leaf: 8, ..BvhBuildParams::medium_build() };

/// The wide BVH over `prims` from `only` that candidate, or from the cheaper of the two.
pub(super) fn build(prims: &Primitives, only: Option<Candidate>, splits: SpatialSplits) -> WideBvh {
    let aabbs = crate::accel::cwbvh::padded_prim_aabbs(prims);
    if aabbs.is_empty() {
        return WideBvh::empty();
    }
    if topdown::needs_fallback(&aabbs) {
        // Many primitives in one Morton cell make PLOC quadratic and its tree a chain: build top-down instead.
        return WideBvh::from_bvh2(prims, &aabbs, &topdown::build_bvh2(&aabbs, Binning::FALLBACK));
    }
    let build_one = |c: Candidate| {
        let bvh2 = match c {
            Candidate::Ploc => obvhs::bvh2::builder::build_bvh2(&aabbs, PARAMS, &mut Duration::default()),
            Candidate::Sah => {
                let budget = match splits {
                    SpatialSplits::Yes => super::spatial_split::REFERENCE_BUDGET,
                    SpatialSplits::No => 0.0,
                };
                let mut bvh2 = super::spatial_split::build_sbvh2(&aabbs, &prims.tris, budget);
                obvhs::bvh2::leaf_collapser::collapse(
                    &mut bvh2,
                    PARAMS.max_prims_per_leaf,
                    PARAMS.collapse_traversal_cost,
                );
                bvh2
            }
        };
        WideBvh::from_bvh2(prims, &aabbs, &bvh2)
    };
    match only {
        Some(c) => build_one(c),
        None => {
            let (ploc, sah) = rayon::join(|| build_one(Candidate::Ploc), || build_one(Candidate::Sah));
            // Ties keep PLOC's tree.
            if sah.sah_cost() < ploc.sah_cost() { sah } else { ploc }
        }
    }
}

impl WideBvh {
    /// The tree's surface-area cost relative to its root's box: the root's test, plus for every child slot its
    /// box's area (a node: one box test of its children; a leaf: one test per packet), divided by the root box's
    /// area. 0 for an empty tree or a lone leaf.
    pub fn sah_cost(&self) -> f64 {
        if self.root == EMPTY || self.root & LEAF_BIT != 0 {
            return 0.0;
        }
        let area = |lo: [f32; 3], hi: [f32; 3]| {
            let d = [(hi[0] - lo[0]) as f64, (hi[1] - lo[1]) as f64, (hi[2] - lo[2]) as f64];
            d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
        };
        let lane_box = |n: &Node, lane: usize| {
            ([n.b[0][lane], n.b[1][lane], n.b[2][lane]], [n.b[3][lane], n.b[4][lane], n.b[5][lane]])
        };
        let root = &self.nodes[self.root as usize];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for lane in (0..WIDTH).filter(|&l| root.child[l] != EMPTY) {
            let (a, b) = lane_box(root, lane);
            for k in 0..3 {
                (lo[k], hi[k]) = (lo[k].min(a[k]), hi[k].max(b[k]));
            }
        }
        let root_area = area(lo, hi);
        if !(root_area > 0.0 && root_area.is_finite()) {
            return 0.0;
        }
        let mut cost = root_area;
        for n in &self.nodes {
            for lane in (0..WIDTH).filter(|&l| n.child[l] != EMPTY) {
                let (a, b) = lane_box(n, lane);
                let c = n.child[lane];
                let tests = if c & LEAF_BIT != 0 { leaf_packets(c & !LEAF_BIT).len() as f64 } else { 1.0 };
                cost += area(a, b) * tests;
            }
        }
        cost / root_area
    }
}
