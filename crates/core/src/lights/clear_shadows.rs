//! Shadow rays proven clear before they are traced. Next-event estimation traces a shadow ray from every path
//! vertex to a point of the chosen light; in a room such as the Cornell box most of them reach it, and they cost
//! about a seventh of a sample's time. A vertex on triangle `t`, in cell `c` of a uniform grid over the scene,
//! sends its shadow rays to light `l` along segments that all lie within the convex hull of the part of `t` in `c`
//! and the light's points. When no primitive comes within a gap of that hull, none of those rays can be blocked,
//! and the vertex skips the query: the answer it would have returned is known.
//!
//! The proof, for one key `(t, c, l)`, is computed once enough vertices have asked for it to pay (the patience,
//! 16 queries or a quarter of the scene's primitive count if larger, up to 200; until then the rays are traced)
//! and kept ([`ClearShadows::proven_clear`]): a pure function of the key, so whichever thread computes it first, every
//! render of the scene makes the same choices, and since a proven ray is one the query would have found clear,
//! the image is the one tracing every ray gives, bit for bit (tested). The proof is conservative throughout:
//! - **the region**: the triangle clipped to the cell grown by a margin (the vertex's point and its cell index carry
//!   rounding errors); the segments' real ends (origins offset off the surface, targets offset off the light,
//!   `tmax` just short of 1) lie within `1e-5` of the scene's largest coordinate of the hull, and every occluder
//!   must be apart from it by the [`Occluders`] gap (`1e-4` of it);
//! - **the light**: every light point must lie strictly on one side of the triangle's plane, so the rays all leave
//!   the surface towards that side; primitives wholly behind that plane (the surface's own coplanar neighbours,
//!   the faces of a box behind the one hit) cannot meet them. Likewise, when the light is planar and the region
//!   lies strictly in front of it, primitives wholly behind the light's plane (the light's own triangles, a
//!   ceiling just above it) are out of reach of rays that stop short of the light;
//! - **the occluders**: every other bounded primitive whose box meets the hull's is tested by its plane and then by
//!   GJK ([`crate::geometry::hulls_apart`]: a separating direction is only accepted once checked on the points);
//!   analytic shapes by the corners of their boxes; infinite planes must leave the whole hull on one side.
//!
//! Built for triangle-set area lights of at most `MAX_LIGHT_TRIANGLES` triangles, point and spot lights (their
//! position), in scenes of at most [`crate::primitives::MAX_OCCLUDERS`] bounded primitives (each proof scans them
//! all); other lights, vertices on analytic shapes and larger scenes trace every shadow ray as before. The grid
//! has `CELLS_PER_AXIS` cells along the scene's longest side. The proofs of a render share a budget of primitive
//! tests (`PROOF_BUDGET`, about a second): past it, keys stay unproven and their rays are traced, so a scene of
//! many lights cannot spend more time proving than tracing, and the image is the same either way.

use crate::lights::{AreaShape, LightSet, LightSource};
use crate::primitives::{Occluders, Primitives, SurfaceHit, dvec};
use glam::{DVec3, Vec3A};
use std::sync::atomic::{AtomicU8, AtomicU64, Ordering};

/// Cells of the grid along the scene's longest side.
const CELLS_PER_AXIS: f32 = 32.0;
/// Area lights of more triangles than this are not covered (their hull would be loose).
const MAX_LIGHT_TRIANGLES: u32 = 16;
/// At most this many cached proofs (one byte each); triangles past it are not covered.
const MAX_FLAGS: usize = 1 << 22; // below 2^23: see `proven_clear`

/// The most primitive tests all proofs of a render may take together (each proof scans every primitive): about a
/// second of work, where the Cornell box's proofs take 190,000. A scene of many lights and triangles could
/// otherwise ask for millions of proofs.
const PROOF_BUDGET: u64 = 1 << 27;

/// A key's flag: below `CLEAR`, the number of queries it has had unproven (its rays traced); then its proof's answer.
const CLEAR: u8 = 254;
const MAYBE: u8 = 255;
/// Queries a key waits before it is proved, per bounded primitive of the scene (a proof scans them all, and a
/// clear key saves a shadow ray per query), within `PATIENCE_MIN..=PATIENCE_MAX`: keys few vertices reach, as in
/// a large scene at low sample counts, are never worth proving.
const PATIENCE_PER_PRIMITIVE: f32 = 0.25;
const PATIENCE_MIN: u8 = 16;
const PATIENCE_MAX: u8 = 200;

/// A triangle's block of cells: flag `base + l . stride + light` for cell `lo + l`, `l` below `dims` (whole
/// numbers held as floats, so that the lookup stays in vector registers: exact below 2^24).
#[derive(Clone, Copy, Debug)]
struct TriCells {
    lo: Vec3A,
    dims: Vec3A,
    stride: Vec3A,
    base: u32,
}

/// Adding and subtracting 2^23 rounds an `f32` in [0, 2^22) to the nearest whole number (ties to even); the sum's
/// low 23 bits are that number.
const ROUND: f32 = 8_388_608.0;

/// Where a light's samples lie: the hull of `points`, and the plane of a planar light (unit normal, offset).
#[derive(Clone, Debug)]
struct LightRegion {
    points: Vec<DVec3>,
    plane: Option<(DVec3, f64)>,
}

/// The grid of cached proofs (see the module header).
pub struct ClearShadows {
    origin: Vec3A,
    inv_cell: f32,
    /// One entry per triangle (analytic primitives are not covered).
    cells: Vec<TriCells>,
    /// Covered lights by slot (`None`: not covered); the flags hold `slots` entries per cell.
    lights: Vec<Option<LightRegion>>,
    slots: usize,
    flags: Vec<AtomicU8>,
    /// The scene's primitives as point sets; its gap is also the margin the cells grow by.
    occluders: Occluders,
    /// Primitive tests taken by the proofs so far (against `PROOF_BUDGET`).
    work: AtomicU64,
    /// Queries a key waits before it is proved (see `PATIENCE_PER_PRIMITIVE`).
    patience: u8,
}

impl std::fmt::Debug for ClearShadows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClearShadows").field("slots", &self.slots).field("flags", &self.flags.len()).finish()
    }
}

impl ClearShadows {
    /// The cache for `lights` over `prims`, or None when the scene is not covered (too many primitives, no light
    /// that can be covered, an empty or non-finite scene).
    pub fn new(lights: &LightSet, prims: &Primitives) -> Option<Self> {
        let bounds = prims.bounds;
        if prims.tris.is_empty() {
            return None;
        }
        let occluders = Occluders::new(prims)?;
        let regions: Vec<Option<LightRegion>> = lights.lights.iter().map(|l| light_region(l, prims)).collect();
        let slots = regions.iter().rposition(Option::is_some)? + 1;
        let extent = bounds.diagonal().max_element();
        let inv_cell = CELLS_PER_AXIS / extent;
        let origin = bounds.min;
        let mut cells = Vec::with_capacity(prims.tris.len());
        let mut total = 0usize;
        for t in &prims.tris {
            let b = crate::geometry::Bounds::from_points(t);
            let lo = cell_of(origin, inv_cell, b.min);
            let dims = (cell_of(origin, inv_cell, b.max) - lo + Vec3A::ONE).max(Vec3A::ZERO);
            let n = (dims.x * dims.y * dims.z) as usize * slots;
            let stride = Vec3A::new(dims.y * dims.z, dims.z, 1.0) * slots as f32;
            if total + n > MAX_FLAGS || !dims.is_finite() {
                cells.push(TriCells { lo, dims: Vec3A::ZERO, stride, base: 0 });
                continue;
            }
            cells.push(TriCells { lo, dims, stride, base: total as u32 });
            total += n;
        }
        Some(ClearShadows {
            origin,
            inv_cell,
            cells,
            lights: regions,
            slots,
            flags: (0..total).map(|_| AtomicU8::new(0)).collect(),
            patience: (occluders.len() as f32 * PATIENCE_PER_PRIMITIVE).clamp(PATIENCE_MIN as f32, PATIENCE_MAX as f32)
                as u8,
            occluders,
            work: AtomicU64::new(0),
        })
    }

    /// True when every shadow ray from `s` to light `slot` is proven clear (see the module header): the caller may
    /// skip tracing it. False when not proven, whatever the ray would find.
    #[inline(always)]
    pub fn proven_clear(&self, s: &SurfaceHit, slot: usize) -> bool {
        let Some(tc) = self.cells.get(s.prim as usize) else { return false };
        let local = cell_of(self.origin, self.inv_cell, s.p) - tc.lo;
        if !(local.cmpge(Vec3A::ZERO) & local.cmplt(tc.dims)).all() || slot >= self.slots {
            return false;
        }
        // The dot product is a whole number below 2^23: its low mantissa bits after adding 2^23 (no conversion).
        let index = tc.base as usize + ((local.dot(tc.stride) + ROUND).to_bits() & 0x7F_FFFF) as usize + slot;
        let Some(flag) = self.flags.get(index) else { return false };
        match flag.load(Ordering::Relaxed) {
            CLEAR => true,
            MAYBE => false,
            waited if waited >= self.patience => self.prove_and_store(flag, s.prim, local + tc.lo, slot),
            waited => {
                // One more query traced. A count lost to another thread's at the same moment only delays the proof.
                let _ = flag.compare_exchange(waited, waited + 1, Ordering::Relaxed, Ordering::Relaxed);
                false
            }
        }
    }

    #[cold]
    #[inline(never)]
    fn prove_and_store(&self, flag: &AtomicU8, tri: u32, cell: Vec3A, slot: usize) -> bool {
        // Past the budget keys are left unproven: the rays are traced, so only the time can change, never the image.
        let within = self.work.fetch_add(self.occluders.len() as u64, Ordering::Relaxed) < PROOF_BUDGET;
        let clear = within && self.prove(tri, cell, slot);
        flag.store(if clear { CLEAR } else { MAYBE }, Ordering::Relaxed);
        clear
    }

    /// The proof for key `(tri, cell, slot)`: true when no primitive can block a shadow ray from the part of
    /// triangle `tri` in `cell` to light `slot`.
    pub(crate) fn prove(&self, tri: u32, cell: Vec3A, slot: usize) -> bool {
        let Some(Some(light)) = self.lights.get(slot) else { return false };
        let t: [DVec3; 3] = self.occluders.points(tri).try_into().expect("a triangle's three corners");
        let g = self.occluders.gap;
        let h = 1.0 / self.inv_cell as f64;
        // Cell `k` holds the points whose scaled offset from the origin rounds to `k` (see `cell_of`).
        let lo = dvec(self.origin) + (dvec(cell) - DVec3::splat(0.5)) * h - DVec3::splat(g);
        let hi = lo + DVec3::splat(h + 2.0 * g);
        let (corners, len) = clip_to_box(&t, lo, hi);
        let region = &corners[..len];
        if region.is_empty() {
            return false;
        }
        // The surface's plane, oriented towards the light (which must lie wholly on one side of it).
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        if n == DVec3::ZERO {
            return false;
        }
        let side = |p: DVec3| n.dot(p - t[0]);
        let surface = if light.points.iter().all(|&q| side(q) > g) {
            (n, n.dot(t[0]))
        } else if light.points.iter().all(|&q| side(q) < -g) {
            (-n, -n.dot(t[0]))
        } else {
            return false;
        };
        // The light's plane, oriented towards the region, when the region lies wholly on one side of it.
        let light_plane = light.plane.and_then(|(ln, ld)| {
            if region.iter().all(|&p| ln.dot(p) - ld > g) {
                Some((ln, ld))
            } else if region.iter().all(|&p| ln.dot(p) - ld < -g) {
                Some((-ln, -ld))
            } else {
                None
            }
        });
        let hull: Vec<DVec3> = region.iter().chain(&light.points).copied().collect();
        let behind = |(pn, pd): (DVec3, f64), pts: &[DVec3]| pts.iter().all(|&v| pn.dot(v) - pd <= 0.0);
        self.occluders.hull_clear(&hull, |id, pts| {
            id == tri || behind(surface, pts) || light_plane.is_some_and(|lp| behind(lp, pts))
        })
    }
}

/// The cell of point `p` in a grid of cell size `1 / inv_cell` from `origin`: the scaled offset rounded to the
/// nearest whole number (ties to even; as a float). The same arithmetic for the triangles' blocks and the lookups,
/// and monotone in each coordinate, so a point inside a triangle's box is inside its block.
#[inline(always)]
fn cell_of(origin: Vec3A, inv_cell: f32, p: Vec3A) -> Vec3A {
    (p - origin) * inv_cell + Vec3A::splat(ROUND) - Vec3A::splat(ROUND)
}

/// At most this many corners: a triangle clipped by a box's six planes.
const CLIP_MAX: usize = 9;

/// The polygon where triangle `t` meets the box `[lo, hi]` (Sutherland–Hodgman against its six planes) and its
/// number of corners, 0 when they do not meet (or rounding made the clipped polygon ill-formed).
fn clip_to_box(t: &[DVec3; 3], lo: DVec3, hi: DVec3) -> ([DVec3; CLIP_MAX], usize) {
    let mut poly = [DVec3::ZERO; CLIP_MAX];
    poly[..3].copy_from_slice(t);
    let mut len = 3;
    for axis in 0..3 {
        for (bound, keep_below) in [(lo[axis], false), (hi[axis], true)] {
            let inside = |p: &DVec3| if keep_below { p[axis] <= bound } else { p[axis] >= bound };
            let mut out = [DVec3::ZERO; CLIP_MAX];
            let mut n = 0;
            for i in 0..len {
                let (a, b) = (poly[i], poly[(i + 1) % len]);
                // A convex polygon gains at most one corner per plane; anything else (rounding) proves nothing.
                let needed = inside(&a) as usize + (inside(&a) != inside(&b)) as usize;
                if n + needed > CLIP_MAX {
                    return (poly, 0);
                }
                if inside(&a) {
                    out[n] = a;
                    n += 1;
                }
                if inside(&a) != inside(&b) {
                    let s = (bound - a[axis]) / (b[axis] - a[axis]);
                    let mut p = a + (b - a) * s;
                    p[axis] = bound;
                    out[n] = p;
                    n += 1;
                }
            }
            (poly, len) = (out, n);
            if len == 0 {
                return (poly, 0);
            }
        }
    }
    (poly, len)
}

/// The region light `l`'s samples come from, when it is covered: a triangle set's corners (planar when every
/// corner lies on the first triangle's plane), a point or spot light's position.
fn light_region(l: &LightSource, prims: &Primitives) -> Option<LightRegion> {
    match l {
        LightSource::Area(a) => match &a.shape {
            AreaShape::Triangles { first, count, .. } if *count <= MAX_LIGHT_TRIANGLES && *count > 0 => {
                let tris = &prims.tris[*first as usize..(*first + *count) as usize];
                let points: Vec<DVec3> = tris.iter().flatten().map(|&p| dvec(p)).collect();
                let (p0, p1, p2) = (points[0], points[1], points[2]);
                let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                let d = n.dot(p0);
                let planar = n != DVec3::ZERO && points.iter().all(|&p| n.dot(p) - d == 0.0);
                Some(LightRegion { points, plane: planar.then_some((n, d)) })
            }
            _ => None,
        },
        LightSource::Point(p) => Some(LightRegion { points: vec![dvec(p.position)], plane: None }),
        LightSource::Spot(s) => Some(LightRegion { points: vec![dvec(s.position)], plane: None }),
        LightSource::Directional(_) => None,
    }
}
