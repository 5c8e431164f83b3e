//! Accelerators over the scene's bounded primitives (triangles and spheres; planes are kept aside by [`Scene`]).
//! Every accelerator answers the same two queries, closest hit and occlusion, with identical results up to exact
//! ties (cross-checked against brute force in `tests/accel.rs`). [`Accel`] is an enum, so the per-ray dispatch is a
//! predictable `match`, not a virtual call.
//!
//! [`Scene`]: crate::scene::Scene

mod brute;
mod bvh;

pub use brute::BruteForce;
pub use bvh::BvhAccel;

use crate::error::Result;
use crate::geometry::Ray;
use crate::primitives::{Hit, Primitives};
use crate::settings::AccelKind;
use std::time::{Duration, Instant};

/// Size and build cost of an accelerator.
#[derive(Clone, Debug, Default)]
pub struct AccelStats {
    pub kind: &'static str,
    pub build_time: Duration,
    /// Bytes of the acceleration structure itself (nodes, index lists, reordered copies), not the primitives.
    pub memory_bytes: usize,
    /// Nodes (BVH, kd-tree) or cells (grid).
    pub nodes: usize,
}

/// The interface every accelerator implements.
pub trait Accelerator: Send + Sync {
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit>;
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool;
    fn stats(&self) -> AccelStats;
}

pub enum Accel {
    Bvh(BvhAccel),
    Brute(BruteForce),
}

impl Accel {
    /// Build the accelerator of the given kind over `prims`.
    pub fn build(kind: AccelKind, prims: &Primitives) -> Result<Accel> {
        let start = Instant::now();
        let mut accel = match kind {
            AccelKind::Bvh => Accel::Bvh(BvhAccel::build(prims)),
            AccelKind::Brute => Accel::Brute(BruteForce::build(prims)),
        };
        accel.set_build_time(start.elapsed());
        Ok(accel)
    }

    fn set_build_time(&mut self, d: Duration) {
        match self {
            Accel::Bvh(a) => a.build_time = d,
            Accel::Brute(_) => {}
        }
    }

    #[inline]
    pub fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::Bvh(a) => a.intersect(prims, ray),
            Accel::Brute(a) => a.intersect(prims, ray),
        }
    }

    #[inline]
    pub fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        match self {
            Accel::Bvh(a) => a.occluded(prims, ray),
            Accel::Brute(a) => a.occluded(prims, ray),
        }
    }

    pub fn stats(&self) -> AccelStats {
        match self {
            Accel::Bvh(a) => a.stats(),
            Accel::Brute(a) => a.stats(),
        }
    }
}
