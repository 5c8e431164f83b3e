//! Brute force: test every bounded primitive. The ground truth the other accelerators are checked against.

use super::work::TraversalWork;
use super::{AccelStats, Accelerator};
use crate::geometry::{Ray, WatertightRay};
use crate::primitives::{Hit, Primitives};

/// `--accel brute`: no structure, every bounded primitive tested by every ray, in id order.
pub struct BruteForce {
    count: u32,
}

impl BruteForce {
    /// Over the bounded primitives of `prims` (planes are the scene's to test); nothing is built.
    pub fn build(prims: &Primitives) -> Self {
        BruteForce { count: prims.num_bounded() }
    }
}

impl Accelerator for BruteForce {
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        let wt = WatertightRay::new(ray);
        let mut r = *ray;
        let mut best = None;
        for id in 0..self.count {
            if let Some(h) = prims.intersect_bounded(id, &r, &wt) {
                r.tmax = h.t;
                best = Some(h);
            }
        }
        best
    }

    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        let wt = WatertightRay::new(ray);
        (0..self.count).any(|id| prims.intersect_bounded(id, ray, &wt).is_some())
    }

    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        work.prims += self.count;
        self.intersect(prims, ray)
    }

    fn stats(&self) -> AccelStats {
        AccelStats { kind: "brute", detail: format!("{} primitives", self.count), ..Default::default() }
    }
}
