//! A scene's primitives as convex point sets, for proofs that a region of space — the convex hull of a few points —
//! is clear of everything but the primitives a caller names: triangles by their corners, analytic shapes by the
//! corners of their boxes, infinite planes by their equations. "Clear" means at least `gap` away (1e-4 of the
//! scene's largest coordinate or extent): far beyond the rounding of rays' ends and of the intersection tests, so a
//! ray inside the region cannot hit a primitive proven clear of it. The shadow-ray proofs
//! ([`crate::lights::ClearShadows`]) rest on it. Built only for scenes of at most `MAX_OCCLUDERS` bounded primitives: every proof scans them all.

use super::Primitives;
use crate::geometry::hulls_apart;
use glam::{DVec3, Vec3A};

/// Scenes with more bounded primitives than this get no proofs.
pub const MAX_OCCLUDERS: u32 = 1024;
/// The clearance demanded, relative to the scene's scale: ten times the largest offset of a spawned ray's ends
/// from the surfaces they leave and reach.
const GAP_SCALE: f64 = 1e-4;

/// One primitive's points and box.
#[derive(Clone, Debug)]
struct Occluder {
    points: Vec<DVec3>,
    min: DVec3,
    max: DVec3,
}

/// The primitives of a scene as convex point sets (see the module header).
#[derive(Clone, Debug)]
pub struct Occluders {
    items: Vec<Occluder>,
    planes: Vec<(DVec3, f64)>,
    /// The clearance every proof demands (world units).
    pub gap: f64,
}

/// An `f32` point in `f64`.
pub fn dvec(v: Vec3A) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

impl Occluders {
    /// The point sets of `prims`, or None when the scene is too large or not finite.
    pub fn new(prims: &Primitives) -> Option<Self> {
        let bounds = prims.bounds;
        if prims.num_bounded() > MAX_OCCLUDERS || bounds.is_empty() {
            return None;
        }
        let extent = bounds.diagonal().max_element() as f64;
        let scale = bounds.min.abs().max(bounds.max.abs()).max_element() as f64;
        if !(extent > 0.0 && extent.is_finite() && scale.is_finite()) {
            return None;
        }
        let items = (0..prims.num_bounded())
            .map(|id| {
                let points: Vec<DVec3> = if id < prims.num_tris() {
                    prims.tris[id as usize].iter().map(|&p| dvec(p)).collect()
                } else {
                    let b = prims.prim_bounds(id);
                    let (lo, hi) = (dvec(b.min), dvec(b.max));
                    (0..8)
                        .map(|i| {
                            let pick = |bit: u32, axis: usize| if i & bit == 0 { lo[axis] } else { hi[axis] };
                            DVec3::new(pick(1, 0), pick(2, 1), pick(4, 2))
                        })
                        .collect()
                };
                let min = points.iter().fold(DVec3::INFINITY, |m, &p| m.min(p));
                let max = points.iter().fold(DVec3::NEG_INFINITY, |m, &p| m.max(p));
                Occluder { points, min, max }
            })
            .collect();
        Some(Occluders {
            items,
            planes: prims.planes.iter().map(|p| (dvec(p.normal), p.offset as f64)).collect(),
            gap: GAP_SCALE * scale.max(extent),
        })
    }

    /// The number of bounded primitives.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when the scene has no bounded primitive.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The points of bounded primitive `id` (a triangle's three corners).
    pub fn points(&self, id: u32) -> &[DVec3] {
        &self.items[id as usize].points
    }

    /// True when every primitive but those `skip` names (by id and points) is at least the gap away from the convex
    /// hull of `hull`, and every infinite plane leaves the whole hull on one side. Tested cheapest first: boxes, the
    /// primitive's own plane, then GJK checked on the points.
    pub fn hull_clear(&self, hull: &[DVec3], mut skip: impl FnMut(u32, &[DVec3]) -> bool) -> bool {
        let g = self.gap;
        let apart_from_plane =
            |n: DVec3, d: f64| hull.iter().all(|&p| n.dot(p) - d > g) || hull.iter().all(|&p| n.dot(p) - d < -g);
        if !self.planes.iter().all(|&(n, d)| apart_from_plane(n, d)) {
            return false;
        }
        let hmin = hull.iter().fold(DVec3::INFINITY, |m, &p| m.min(p)) - DVec3::splat(g);
        let hmax = hull.iter().fold(DVec3::NEG_INFINITY, |m, &p| m.max(p)) + DVec3::splat(g);
        for (id, o) in self.items.iter().enumerate() {
            if o.max.cmplt(hmin).any() || o.min.cmpgt(hmax).any() || skip(id as u32, &o.points) {
                continue;
            }
            if o.points.len() == 3 && plane_separates(&o.points, hull, g) {
                continue;
            }
            if !hulls_apart(hull, &o.points, g) {
                return false;
            }
        }
        true
    }
}

/// True when the plane of triangle `tri` leaves all of `pts` on one side, further than `g`.
fn plane_separates(tri: &[DVec3], pts: &[DVec3], g: f64) -> bool {
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
    if n == DVec3::ZERO {
        return false;
    }
    let d = n.dot(tri[0]);
    pts.iter().all(|&p| n.dot(p) - d > g) || pts.iter().all(|&p| n.dot(p) - d < -g)
}
