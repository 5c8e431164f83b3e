//! Accelerators over the scene's bounded primitives (triangles, and analytic shapes through one dispatch; planes
//! are kept aside by [`Scene`]).
//! Every accelerator answers the same two queries, closest hit and occlusion, with identical results up to exact
//! ties (cross-checked against brute force in `tests/accel.rs`), plus a counted closest-hit query that reports the
//! traversal work of one ray for heat maps. [`Accel`] is an enum, so the per-ray dispatch is a predictable
//! `match`, not a virtual call.
//!
//! | accelerator | file | build |
//! |---|---|---|
//! | BVH (the default; 8-wide, SoA boxes tested 8 at a time with AVX2, packet leaves) | `wide_bvh/` | the cheaper of obvhs PLOC and top-down binned SAH; top-down for clustered input |
//! | obvhs CWBVH (`cwbvh`) | `cwbvh.rs` | obvhs PLOC, parallel |
//! | SAH kd-tree | `kdtree/` | Wald & Havran O(N log N), perfect splits |
//! | uniform grid | `grid/` | per-cell triangle/box overlap, nested grids for crowded cells |
//! | brute force | `brute.rs` | none |
//!
//! Beside them, [`PointHashGrid`] (`point_hash_grid.rs`) finds stored points (photons, light vertices) within a
//! radius, for the density estimates of `ppm` and `vcm`.
//!
//! [`Scene`]: crate::scene::Scene

mod brute;
mod clip;
mod cwbvh;
pub mod grid;
pub mod kdtree;
mod leaf_packet;
mod mailbox;
mod point_hash_grid;
mod tri_box;
mod triangle_clip;
mod wide_bvh;
mod work;

pub use brute::BruteForce;
pub use cwbvh::BvhAccel;
pub use grid::{CellHit, GridCell, UniformGrid};
pub use kdtree::{KdParams, KdTree};
pub use point_hash_grid::{GridPoint, PointHashGrid};
pub use tri_box::triangle_overlaps_box;
pub use wide_bvh::{Candidate as BvhCandidate, PACKET, SPLIT_SAMPLES_PER_PRIMITIVE, SpatialSplits, WideBvh};
pub use work::{NoCount, TraversalWork, WorkCounter};

use crate::error::{PrismError, Result};
use crate::geometry::Ray;
use crate::primitives::{Hit, Primitives};
use crate::settings::AccelKind;
use std::time::{Duration, Instant};

/// Size and build cost of an accelerator.
#[derive(Clone, Debug, Default)]
pub struct AccelStats {
    /// The accelerator's `--accel` name (`bvh`, `cwbvh`, `kdtree`, `grid`, `brute`).
    pub kind: &'static str,
    /// Wall-clock time of the build (zero for brute force, which builds nothing).
    pub build_time: Duration,
    /// Bytes of the acceleration structure itself (nodes, index lists, reordered copies), not the primitives.
    pub memory_bytes: usize,
    /// Nodes (BVH, kd-tree) or cells (grid).
    pub nodes: usize,
    /// A one-line description (resolution, depth, references per primitive ...).
    pub detail: String,
}

/// The interface every accelerator implements.
pub trait Accelerator: Send + Sync {
    /// The closest hit of a bounded primitive along `ray` in `(0, tmax)`; `None` when there is none.
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit>;
    /// Whether any bounded primitive meets `ray` in `(0, tmax)` (stops at the first hit found, not the closest).
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool;
    /// `intersect`, adding the nodes/cells visited and primitives tested to `work` (slower; for heat maps).
    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit>;
    /// The closest hit of each of `rays` into `out` (as long as `rays`), for rays that are traced together (a
    /// pixel's camera rays): the same hits as [`Accelerator::intersect`] ray by ray (which this default does),
    /// except that of two primitives at exactly the same distance either may be reported.
    fn intersect_packet(&self, prims: &Primitives, rays: &[Ray], out: &mut [Option<Hit>]) {
        for (o, r) in out.iter_mut().zip(rays) {
            *o = self.intersect(prims, r);
        }
    }
    /// Size, build time and a description of the structure.
    fn stats(&self) -> AccelStats;
}

/// The scene's accelerator, one of the kinds of [`AccelKind`], dispatched by `match`.
pub enum Accel {
    /// `--accel bvh` (the default): the 8-wide BVH.
    Bvh(WideBvh),
    /// `--accel cwbvh`: obvhs's compressed wide BVH.
    CwBvh(BvhAccel),
    /// `--accel kdtree`: the SAH kd-tree.
    KdTree(KdTree),
    /// `--accel grid`: the uniform grid.
    Grid(UniformGrid),
    /// `--accel brute`: every primitive tested.
    Brute(BruteForce),
}

macro_rules! dispatch {
    ($self:expr, $a:ident => $e:expr) => {
        match $self {
            Accel::Bvh($a) => $e,
            Accel::CwBvh($a) => $e,
            Accel::KdTree($a) => $e,
            Accel::Grid($a) => $e,
            Accel::Brute($a) => $e,
        }
    };
}

impl Accel {
    /// Build the accelerator of the given kind over `prims`. Fails only on bad grid resolutions and on more
    /// primitives than the wide BVH's leaf encoding holds (`2^28`).
    pub fn build(kind: AccelKind, prims: &Primitives) -> Result<Accel> {
        Self::build_with(kind, prims, SpatialSplits::Yes)
    }

    /// As [`Accel::build`]; `splits` says whether the `bvh`'s SAH candidate splits triangles (a render chooses by
    /// its samples, [`SpatialSplits::for_samples`]; `prism bench` and the other callers always do).
    pub fn build_with(kind: AccelKind, prims: &Primitives, splits: SpatialSplits) -> Result<Accel> {
        let start = Instant::now();
        if kind == AccelKind::Bvh && prims.num_bounded() as usize >= wide_bvh::MAX_PRIMITIVES {
            return Err(PrismError::invalid(format!(
                "{} primitives: the bvh accelerator holds fewer than {}; choose another with --accel",
                prims.num_bounded(),
                wide_bvh::MAX_PRIMITIVES
            )));
        }
        let mut accel = match kind {
            AccelKind::Bvh => Accel::Bvh(WideBvh::build_with(prims, splits)),
            AccelKind::CwBvh => Accel::CwBvh(BvhAccel::build(prims)),
            AccelKind::KdTree => Accel::KdTree(KdTree::build(prims)),
            AccelKind::Grid(res) => Accel::Grid(UniformGrid::build(prims, res)?),
            AccelKind::Brute => Accel::Brute(BruteForce::build(prims)),
        };
        accel.set_build_time(start.elapsed());
        Ok(accel)
    }

    fn set_build_time(&mut self, d: Duration) {
        match self {
            Accel::Bvh(a) => a.build_time = d,
            Accel::CwBvh(a) => a.build_time = d,
            Accel::KdTree(a) => a.build_time = d,
            Accel::Grid(a) => a.build_time = d,
            Accel::Brute(_) => {}
        }
    }

    /// The closest hit. The `bvh` (the default) is called directly; the other accelerators through an out-of-line
    /// dispatch, so that what the path loops inline stays small.
    #[inline]
    pub fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::Bvh(a) => a.intersect(prims, ray),
            _ => self.intersect_other(prims, ray),
        }
    }

    #[inline(never)]
    fn intersect_other(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        dispatch!(self, a => a.intersect(prims, ray))
    }

    /// Whether anything blocks the ray before its `tmax` (dispatched as [`Accel::intersect`]).
    #[inline]
    pub fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        match self {
            Accel::Bvh(a) => a.occluded(prims, ray),
            _ => self.occluded_other(prims, ray),
        }
    }

    #[inline(never)]
    fn occluded_other(&self, prims: &Primitives, ray: &Ray) -> bool {
        dispatch!(self, a => a.occluded(prims, ray))
    }

    /// Closest hits of rays traced together ([`Accelerator::intersect_packet`]).
    #[inline]
    pub fn intersect_packet(&self, prims: &Primitives, rays: &[Ray], out: &mut [Option<Hit>]) {
        dispatch!(self, a => a.intersect_packet(prims, rays, out))
    }

    /// Closest hit, counting the traversal work into `work`.
    pub fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        dispatch!(self, a => a.intersect_counted(prims, ray, work))
    }

    /// The accelerator's size, build time and description ([`Accelerator::stats`]).
    pub fn stats(&self) -> AccelStats {
        dispatch!(self, a => a.stats())
    }

    /// The uniform grid, if this is one (for the grid visualisation).
    pub fn as_grid(&self) -> Option<&UniformGrid> {
        match self {
            Accel::Grid(g) => Some(g),
            _ => None,
        }
    }
}
