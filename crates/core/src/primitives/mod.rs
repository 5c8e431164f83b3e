//! Primitives: the scene's shapes flattened into world-space arrays, built once in the BuildAccel stage from the
//! entities' `Shape`, `WorldFromLocal`, `MaterialId` and `Light::Area` components (`build.rs`). Accelerators index
//! them.
//!
//! Primitive ids form one range: triangles `[0, T)`, then analytic shapes `[T, T+A)`, then planes `[T+A, T+A+P)`.
//! Triangles are stored with their vertices already transformed (exact world-space vertices): they are the
//! accelerators' fast path. Every other bounded shape (sphere, ellipsoid, surface of revolution, Bézier patch;
//! `crate::shapes`) is an *analytic* primitive, stored in its kind's array and named by `analytic[id - T]`; the
//! accelerators reach all of them through one dispatch: [`Primitives::prim_bounds`],
//! [`Primitives::intersect_analytic`], [`Primitives::occludes_analytic`], [`Primitives::analytic_overlaps_box`],
//! [`Primitives::analytic_clip_bounds`] and [`Primitives::surface`]. Planes are unbounded and are never put in an
//! accelerator.

use crate::geometry::{Bounds, Ray, WatertightRay, gamma, intersect_plane};
use crate::math::Frame;
use crate::shapes::{AnalyticShape, BezierPatch, Revolution, ShapeHit, ShapePoint, ShapeRef};
use glam::{Vec2, Vec3, Vec3A};

mod alpha_holes;
mod build;
mod occluders;

pub use crate::geometry::{Hit, SurfaceHit};
pub use crate::shapes::{SphereGeom, SphereTransform, sphere_point_error, sphere_uv};
pub use build::{ShapeInstance, to_f64};
pub use occluders::{MAX_OCCLUDERS, Occluders, dvec};

/// Marks "no area light" in `light` fields.
pub const NO_LIGHT: u32 = u32::MAX;

/// Shading data of one triangle (kept apart from the vertices so traversal touches only positions).
#[derive(Clone, Copy, Debug)]
pub struct TriShading {
    /// Vertex normals in world space (unit), if the mesh has them.
    pub normals: Option<[Vec3A; 3]>,
    /// Vertex texture coordinates (the mesh's, or `(0,0), (1,0), (0,1)` when it has none).
    pub uvs: [Vec2; 3],
    /// Index into the scene's material table.
    pub material: u32,
    /// Index of the area light the triangle belongs to, or [`NO_LIGHT`].
    pub light: u32,
    /// Index into `Primitives::tri_tangents`, or [`NO_TANGENTS`] (only normal-mapped meshes have them).
    pub tangents: u32,
    /// dp/du and dp/dv (constant over the triangle), computed once when the triangle is built.
    pub dpduv: [Vec3; 2],
    /// The unit geometric normal `normalize((p1 - p0) x (p2 - p0))`, computed once when the triangle is built (a
    /// hit record needs it first; computed there, its square root and division would sit on every path vertex's
    /// critical path).
    pub ng: Vec3A,
}

/// The unit geometric normal of a (non-degenerate) triangle, as every hit record uses it.
#[inline]
pub fn triangle_normal(v: &[Vec3A; 3]) -> Vec3A {
    (v[1] - v[0]).cross(v[2] - v[0]).normalize()
}

/// Marks a triangle without vertex tangents.
pub const NO_TANGENTS: u32 = u32::MAX;

/// An infinite plane `normal . p = offset`, world space (never in an accelerator).
#[derive(Clone, Copy, Debug)]
pub struct PlaneGeom {
    /// Unit normal, the plane's front side.
    pub normal: Vec3A,
    /// Signed distance of the plane from the origin along `normal`.
    pub offset: f32,
    /// Index into the scene's material table.
    pub material: u32,
}

/// Every primitive of the scene in world space, by id (triangles, then analytic shapes, then planes).
#[derive(Clone, Debug, Default)]
pub struct Primitives {
    /// Each triangle's exact world-space vertices; the triangle's id is its index.
    pub tris: Vec<[Vec3A; 3]>,
    /// Each triangle's shading data, by the same index as `tris`.
    pub tri_shading: Vec<TriShading>,
    /// Per-vertex MikkTSpace tangents (xyz, bitangent sign in w) of the triangles of normal-mapped meshes.
    pub tri_tangents: Vec<[glam::Vec4; 3]>,
    /// Spheres and ellipsoids (`ShapeRef::Sphere` indexes here).
    pub spheres: Vec<SphereGeom>,
    /// Surfaces of revolution (`ShapeRef::Revolution` indexes here).
    pub revolutions: Vec<Revolution>,
    /// Bézier patches (`ShapeRef::Patch` indexes here).
    pub patches: Vec<BezierPatch>,
    /// The analytic primitive with id `T + k` is `analytic[k]`.
    pub analytic: Vec<ShapeRef>,
    /// Infinite planes; plane `k` has id `num_bounded() + k`.
    pub planes: Vec<PlaneGeom>,
    /// Bounds of the bounded primitives (triangles and analytic shapes).
    pub bounds: Bounds,
    /// Degenerate (zero-area or non-finite) mesh triangles that were skipped.
    pub skipped_degenerate: usize,
    /// Alpha masks of the scene (see [`crate::alpha`]) and, when there is any, one mask index per triangle
    /// ([`crate::alpha::NO_ALPHA`] for opaque ones); empty in scenes without masks.
    pub alpha_masks: Vec<crate::alpha::AlphaMask>,
    /// Each triangle's index into `alpha_masks`, or [`crate::alpha::NO_ALPHA`]; empty without masks.
    pub tri_alpha: Vec<u32>,
}

/// The primitive range one entity produced (used to attach area lights).
#[derive(Clone, Copy, Debug)]
pub struct EntityPrims {
    /// Id of the entity's first triangle.
    pub first_tri: u32,
    /// Number of triangles it produced (consecutive from `first_tri`).
    pub tri_count: u32,
    /// Index in `Primitives::spheres`, for a sphere or ellipsoid.
    pub sphere: Option<u32>,
    /// A curved analytic shape (revolution, patch): its index in `Primitives::analytic` (primitive id
    /// `num_tris() + index`).
    pub curved: Option<u32>,
}

/// Run `$e` with `$s` bound to the analytic shape named by `$r` (a [`ShapeRef`]): the one dispatch over shape kinds.
macro_rules! with_shape {
    ($p:expr, $r:expr, $s:ident => $e:expr) => {
        match $r {
            ShapeRef::Sphere(i) => {
                let $s = &$p.spheres[i as usize];
                $e
            }
            ShapeRef::Revolution(i) => {
                let $s = &$p.revolutions[i as usize];
                $e
            }
            ShapeRef::Patch(i) => {
                let $s = &$p.patches[i as usize];
                $e
            }
        }
    };
}

/// Error bound of a barycentric combination `b0 p0 + b1 p1 + b2 p2` (pbrt-v4: gamma(7) times the sum of magnitudes).
#[inline]
pub fn interpolation_error(b: [f32; 3], p: &[Vec3A; 3]) -> Vec3A {
    gamma(7) * ((b[0] * p[0]).abs() + (b[1] * p[1]).abs() + (b[2] * p[2]).abs())
}

impl Primitives {
    /// Number of triangles `T`: ids below it are triangles.
    #[inline]
    pub fn num_tris(&self) -> u32 {
        self.tris.len() as u32
    }

    /// Triangles + analytic shapes: the primitives accelerators hold.
    #[inline]
    pub fn num_bounded(&self) -> u32 {
        (self.tris.len() + self.analytic.len()) as u32
    }

    /// Every primitive: bounded ones and planes.
    pub fn num_total(&self) -> u32 {
        self.num_bounded() + self.planes.len() as u32
    }

    /// The analytic shape of bounded primitive `id >= num_tris()`.
    #[inline(always)]
    pub fn shape_ref(&self, id: u32) -> ShapeRef {
        self.analytic[(id - self.num_tris()) as usize]
    }

    /// True when every bounded primitive is a triangle (accelerators then skip the per-primitive kind test).
    #[inline]
    pub fn triangles_only(&self) -> bool {
        self.analytic.is_empty()
    }

    /// World bounds of bounded primitive `id`.
    pub fn prim_bounds(&self, id: u32) -> Bounds {
        if id < self.num_tris() {
            Bounds::from_points(&self.tris[id as usize])
        } else {
            with_shape!(self, self.shape_ref(id), s => s.bounds())
        }
    }

    /// Intersect bounded primitive `id`; `wt` is the ray's watertight precomputation.
    #[inline(always)]
    pub fn intersect_bounded(&self, id: u32, ray: &Ray, wt: &WatertightRay) -> Option<Hit> {
        if id < self.num_tris() {
            let [p0, p1, p2] = self.tris[id as usize];
            wt.intersect(p0, p1, p2, ray.tmax).map(|h| Hit { t: h.t, prim: id, b1: h.b1, b2: h.b2 })
        } else {
            self.intersect_analytic(id, ray)
        }
    }

    /// Nearest hit of analytic primitive `id` in `(0, ray.tmax)`.
    #[inline]
    pub fn intersect_analytic(&self, id: u32, ray: &Ray) -> Option<Hit> {
        let h: Option<ShapeHit> = with_shape!(self, self.shape_ref(id), s => s.intersect(ray));
        h.map(|h| Hit { t: h.t, prim: id, b1: h.u, b2: h.v })
    }

    /// Does analytic primitive `id` block the ray before `ray.tmax`?
    #[inline]
    pub fn occludes_analytic(&self, id: u32, ray: &Ray) -> bool {
        with_shape!(self, self.shape_ref(id), s => s.occludes(ray))
    }

    /// Might analytic primitive `id` overlap the box (conservative; grid insertion)?
    pub fn analytic_overlaps_box(&self, id: u32, b: &Bounds) -> bool {
        with_shape!(self, self.shape_ref(id), s => s.overlaps_box(b))
    }

    /// Conservative bounds of analytic primitive `id` inside `voxel` (kd-tree splits).
    pub fn analytic_clip_bounds(&self, id: u32, voxel: &Bounds) -> Option<Bounds> {
        with_shape!(self, self.shape_ref(id), s => s.clip_bounds(voxel))
    }

    /// Surface data of curved analytic primitive `id` at parameter point `uv` (area-light sampling); `None` for
    /// other primitives.
    pub fn analytic_point_at(&self, id: u32, uv: Vec2) -> Option<ShapePoint> {
        if id < self.num_tris() || id >= self.num_bounded() {
            return None;
        }
        with_shape!(self, self.shape_ref(id), s => s.point_at_uv(uv))
    }

    /// Closest plane hit closer than `ray.tmax`.
    #[inline]
    pub fn intersect_planes(&self, ray: &Ray) -> Option<Hit> {
        let base = self.num_bounded();
        let mut best: Option<Hit> = None;
        let mut tmax = ray.tmax;
        for (i, p) in self.planes.iter().enumerate() {
            if let Some(t) = intersect_plane(p.normal, p.offset, &Ray { tmax, ..*ray }) {
                tmax = t;
                best = Some(Hit { t, prim: base + i as u32, b1: 0.0, b2: 0.0 });
            }
        }
        best
    }

    /// True when some plane blocks the ray before `ray.tmax`.
    #[inline]
    pub fn planes_occlude(&self, ray: &Ray) -> bool {
        self.planes.iter().any(|p| intersect_plane(p.normal, p.offset, ray).is_some())
    }

    /// The interpolated MikkTSpace tangent and bitangent sign at a triangle hit of a normal-mapped mesh.
    pub fn mesh_tangent(&self, s: &SurfaceHit) -> Option<(Vec3A, f32)> {
        let sh = self.tri_shading.get(s.prim as usize)?;
        if s.prim >= self.num_tris() || sh.tangents == NO_TANGENTS {
            return None;
        }
        let t = &self.tri_tangents[sh.tangents as usize];
        // Barycentrics of the hit point (the hit record keeps only the interpolated results).
        let [p0, p1, p2] = self.tris[s.prim as usize];
        let (e1, e2, d) = (p1 - p0, p2 - p0, s.p - p0);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (d.dot(e1), d.dot(e2));
        let den = d11 * d22 - d12 * d12;
        let (b1, b2) = if den > 0.0 { ((d22 * d1 - d12 * d2) / den, (d11 * d2 - d12 * d1) / den) } else { (0.0, 0.0) };
        let b0 = 1.0 - b1 - b2;
        let v = b0 * t[0] + b1 * t[1] + b2 * t[2];
        let sign = if t[0].w < 0.0 { -1.0 } else { 1.0 };
        Some((Vec3A::from(v.truncate()), sign))
    }

    /// Surface data at a hit.
    #[inline(always)]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfaceHit {
        let nt = self.num_tris();
        let nb = self.num_bounded();
        if hit.prim < nt {
            let [p0, p1, p2] = self.tris[hit.prim as usize];
            let sh = &self.tri_shading[hit.prim as usize];
            let b0 = 1.0 - hit.b1 - hit.b2;
            // Interpolating the vertices is more accurate than o + t d (Wächter & Binder).
            let p = b0 * p0 + hit.b1 * p1 + hit.b2 * p2;
            let ng = sh.ng;
            let ns = match sh.normals {
                Some([n0, n1, n2]) => {
                    let n = (b0 * n0 + hit.b1 * n1 + hit.b2 * n2).normalize_or_zero();
                    if n == Vec3A::ZERO {
                        ng
                    } else if n.dot(ng) < 0.0 {
                        -n
                    } else {
                        n
                    }
                }
                None => ng,
            };
            let uv = b0 * sh.uvs[0] + hit.b1 * sh.uvs[1] + hit.b2 * sh.uvs[2];
            let p_err = interpolation_error([b0, hit.b1, hit.b2], &[p0, p1, p2]);
            let (dpdu, dpdv) = (Vec3A::from(sh.dpduv[0]), Vec3A::from(sh.dpduv[1]));
            SurfaceHit {
                p,
                p_err,
                ng,
                ns,
                uv,
                dpdu,
                dpdv,
                t: hit.t,
                prim: hit.prim,
                material: sh.material,
                light: sh.light,
            }
        } else if hit.prim < nb {
            let r = self.shape_ref(hit.prim);
            let sh = ShapeHit { t: hit.t, u: hit.b1, v: hit.b2 };
            let (q, material, light) = with_shape!(self, r, s => (s.surface(ray, &sh), s.material(), s.light()));
            SurfaceHit {
                p: q.p,
                p_err: q.p_err,
                ng: q.n,
                ns: q.n,
                uv: q.uv,
                dpdu: q.dpdu,
                dpdv: q.dpdv,
                t: hit.t,
                prim: hit.prim,
                material,
                light,
            }
        } else {
            let pl = &self.planes[(hit.prim - nb) as usize];
            let mut p = ray.at(hit.t);
            p -= (pl.normal.dot(p) - pl.offset) * pl.normal;
            // u, v: coordinates along the plane's frame (world units, so textures tile once per unit).
            let f = Frame::from_normal(pl.normal);
            SurfaceHit {
                p,
                p_err: gamma(6) * (p.abs() + (pl.normal * pl.offset).abs()),
                ng: pl.normal,
                ns: pl.normal,
                uv: Vec2::new(p.dot(f.s), p.dot(f.t)),
                dpdu: f.s,
                dpdv: f.t,
                t: hit.t,
                prim: hit.prim,
                material: pl.material,
                light: NO_LIGHT,
            }
        }
    }
}
