//! `--accel cwbvh`: obvhs's compressed 8-wide BVH (CWBVH, Ylitie et al. 2017) and its own traversal, kept to
//! compare against the default BVH (`wide_bvh/`, built by the same obvhs builder). Built by PLOC with
//! reinsertion over the bounds of all bounded primitives, analytic shapes included (through `Primitives`' one
//! analytic dispatch). After the build, primitive data is copied into
//! BVH leaf order (`slot_tris`, `slot_ids`) so traversal reads triangles sequentially; obvhs hands the traversal
//! closure a slot, never our primitive id.

use super::work::TraversalWork;
use super::{AccelStats, Accelerator};
use crate::geometry::{Ray, TriSoa, WatertightRay};
use crate::primitives::{Hit, Primitives};
use glam::{UVec2, Vec3A};
use obvhs::{BvhBuildParams, aabb::Aabb, cwbvh::CwBvh, ray::RayHit};
use std::time::Duration;

/// `--accel cwbvh`: obvhs's compressed wide BVH and its traversal, with the primitives in leaf order.
pub struct BvhAccel {
    bvh: CwBvh,
    /// Vertices of the triangle in each slot (zero for analytic shapes' slots).
    slot_tris: Vec<TriSoa>,
    /// Primitive id of each slot.
    slot_ids: Vec<u32>,
    num_tris: u32,
    /// No analytic shapes: every slot is a triangle and the traversal closure skips the per-slot type check.
    triangles_only: bool,
    pub(super) build_time: Duration,
}

/// Every bounded primitive's box, grown by a few ulps for the BVH builds: a flat box gets a thickness, so a ray
/// lying in the plane of flat geometry (coplanar triangles) does not get an empty slab interval.
pub(super) fn padded_prim_aabbs(prims: &Primitives) -> Vec<Aabb> {
    (0..prims.num_bounded())
        .map(|i| {
            let b = prims.prim_bounds(i);
            let pad = 4.0 * f32::EPSILON * b.min.abs().max(b.max.abs())
                + Vec3A::splat(1e-6 * b.diagonal().max_element() + f32::MIN_POSITIVE);
            Aabb::new(b.min - pad, b.max + pad)
        })
        .collect()
}

impl BvhAccel {
    /// Build over every bounded primitive of `prims` by PLOC, or top-down binned SAH where many primitives share
    /// a Morton cell; an empty tree when there are none.
    pub fn build(prims: &Primitives) -> Self {
        let aabbs = padded_prim_aabbs(prims);
        let bvh = if aabbs.is_empty() {
            CwBvh::default()
        } else if super::wide_bvh::topdown::needs_fallback(&aabbs) {
            // Many primitives in one Morton cell make PLOC quadratic and its tree a chain: build top-down instead.
            obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(
                &super::wide_bvh::topdown::build_bvh2(&aabbs, super::wide_bvh::topdown::Binning::FALLBACK),
                3,
                true,
                false,
            )
        } else {
            obvhs::cwbvh::builder::build_cwbvh(&aabbs, BvhBuildParams::medium_build(), &mut Duration::default())
        };
        let nt = prims.num_tris();
        let slot_ids = bvh.primitive_indices.clone();
        let slot_tris = slot_ids
            .iter()
            .map(|&id| if id < nt { TriSoa::new(&prims.tris[id as usize]) } else { TriSoa::default() })
            .collect();
        BvhAccel {
            bvh,
            slot_tris,
            slot_ids,
            num_tris: nt,
            triangles_only: prims.triangles_only(),
            build_time: Duration::ZERO,
        }
    }

    #[inline(always)]
    fn hit_slot(&self, prims: &Primitives, slot: usize, ray: &Ray, wt: &WatertightRay) -> Option<Hit> {
        let id = self.slot_ids[slot];
        if id < self.num_tris {
            wt.intersect_soa(&self.slot_tris[slot], ray.tmax).map(|h| Hit { t: h.t, prim: id, b1: h.b1, b2: h.b2 })
        } else {
            prims.intersect_analytic(id, ray)
        }
    }

    /// Does the primitive in `slot` block the ray? (Analytic shapes may stop at their first hit.)
    #[inline(always)]
    fn blocks_slot(&self, prims: &Primitives, slot: usize, ray: &Ray, wt: &WatertightRay) -> bool {
        let id = self.slot_ids[slot];
        if id < self.num_tris {
            wt.intersect_soa(&self.slot_tris[slot], ray.tmax).is_some()
        } else {
            prims.occludes_analytic(id, ray)
        }
    }

    /// The underlying obvhs BVH (for benchmarks against raw obvhs traversal).
    pub fn cwbvh(&self) -> &CwBvh {
        &self.bvh
    }
}

/// The obvhs ray, made robust for axis-parallel rays:
/// - negative zero direction components become +0: obvhs picks the slab ends by `d < 0` but the reciprocal's
///   sign (and the octant) by the sign bit, so a -0 component swapped a slab and the ray missed everything;
/// - a (near-)zero component gets the reciprocal 1e25 instead of obvhs's 1/EPSILON = 8.4e6, which let a
///   parallel ray drift 1.2e-7 per unit length out of a box it runs along (missing hits beyond a few units);
///   1e25 keeps node tests finite for scenes up to 1e13 units.
#[inline(always)]
fn to_obvhs(ray: &Ray) -> obvhs::ray::Ray {
    const BIG: f32 = 1e25;
    let direction = ray.dir + Vec3A::ZERO;
    let recip = direction.recip();
    let inv_direction =
        Vec3A::select(recip.abs().cmpgt(Vec3A::splat(BIG)), Vec3A::splat(BIG).copysign(direction), recip);
    obvhs::ray::Ray { origin: ray.origin, direction, inv_direction, tmin: 0.0, tmax: ray.tmax }
}

impl Accelerator for BvhAccel {
    #[inline]
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        if self.slot_ids.is_empty() {
            return None;
        }
        let wt = WatertightRay::new(ray);
        let mut rh = RayHit::none();
        if self.triangles_only {
            // Hot path: read only the slot's vertices; the primitive id is looked up once, for the final hit.
            let mut bary = (0.0, 0.0);
            self.bvh.ray_traverse(to_obvhs(ray), &mut rh, |r, slot| {
                match wt.intersect_soa(&self.slot_tris[slot], r.tmax) {
                    Some(h) => {
                        bary = (h.b1, h.b2);
                        h.t
                    }
                    None => f32::INFINITY,
                }
            });
            return (rh.t < ray.tmax).then(|| Hit {
                t: rh.t,
                prim: self.slot_ids[rh.primitive_id as usize],
                b1: bary.0,
                b2: bary.1,
            });
        }
        let mut best: Option<Hit> = None;
        self.bvh.ray_traverse(to_obvhs(ray), &mut rh, |r, slot| {
            let cur = Ray { tmax: r.tmax, ..*ray };
            match self.hit_slot(prims, slot, &cur, &wt) {
                Some(h) => {
                    best = Some(h);
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    #[inline]
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        if self.slot_ids.is_empty() {
            return false;
        }
        let wt = WatertightRay::new(ray);
        !self.bvh.ray_traverse_miss(to_obvhs(ray), |_, slot| {
            if self.blocks_slot(prims, slot, ray, &wt) { f32::NEG_INFINITY } else { f32::INFINITY }
        })
    }

    /// The general closest-hit path through obvhs's `traverse!` macro, counting node tests and primitive tests.
    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        if self.slot_ids.is_empty() {
            return None;
        }
        let wt = WatertightRay::new(ray);
        let mut traverse_ray = to_obvhs(ray);
        let mut best: Option<Hit> = None;
        let mut state = self.bvh.new_traversal(traverse_ray.direction);
        let mut node;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            {
                work.nodes += 1;
                node.intersect_ray(&traverse_ray, state.oct_inv4)
            },
            {
                work.prims += 1;
                let cur = Ray { tmax: traverse_ray.tmax, ..*ray };
                if let Some(h) = self.hit_slot(prims, state.primitive_id as usize, &cur, &wt)
                    && h.t < traverse_ray.tmax
                {
                    traverse_ray.tmax = h.t;
                    best = Some(h);
                }
            }
        );
        best
    }

    fn stats(&self) -> AccelStats {
        AccelStats {
            kind: "cwbvh",
            detail: format!("{} CWBVH nodes, {} leaf slots", self.bvh.nodes.len(), self.slot_ids.len()),
            build_time: self.build_time,
            memory_bytes: self.bvh.nodes.len() * std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>()
                + self.slot_ids.len() * (4 + std::mem::size_of::<TriSoa>()),
            nodes: self.bvh.nodes.len(),
        }
    }
}
