//! Primitives: the scene's shapes flattened into world-space arrays, built once in the BuildAccel stage from the
//! entities' `Shape`, `WorldFromLocal`, `MaterialId` and `Light::Area` components. Accelerators index them.
//!
//! Primitive ids form one range: triangles `[0, T)`, then spheres `[T, T+S)`, then planes `[T+S, T+S+P)`.
//! Triangles are stored with their vertices already transformed (exact world-space vertices); a sphere keeps its
//! object-space centre and radius with the composed transform, and is intersected in object space (a sphere under
//! a non-uniform scale is an ellipsoid) unless the transform is a similarity, in which case it is stored as a
//! world-space sphere. Planes are unbounded and are never put in an accelerator.

use crate::components::{Light, MaterialId, Shape, WorldFromLocal};
use crate::error::{PrismError, Result};
use crate::geometry::{Bounds, Ray, WatertightRay, gamma, intersect_plane, intersect_sphere, spawn_ray, spawn_ray_to};
use crate::lights::LightSample;
use crate::mesh::MeshStore;
use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};

/// Marks "no area light" in `light` fields.
pub const NO_LIGHT: u32 = u32::MAX;

/// Shading data of one triangle (kept apart from the vertices so traversal touches only positions).
#[derive(Clone, Copy, Debug)]
pub struct TriShading {
    /// Vertex normals in world space (unit), if the mesh has them.
    pub normals: Option<[Vec3A; 3]>,
    pub uvs: [Vec2; 3],
    pub material: u32,
    pub light: u32,
    /// Index into `Primitives::tri_tangents`, or [`NO_TANGENTS`] (only normal-mapped meshes have them).
    pub tangents: u32,
    /// dp/du and dp/dv (constant over the triangle), computed once when the triangle is built.
    pub dpduv: [Vec3; 2],
}

/// Marks a triangle without vertex tangents.
pub const NO_TANGENTS: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
pub struct SphereGeom {
    /// Centre and radius in the sphere's frame (world space when `world_from_object` is `None`).
    pub center: Vec3A,
    pub radius: f32,
    /// Present for non-similarity transforms (ellipsoids): intersect in object space.
    pub transform: Option<SphereTransform>,
    pub material: u32,
    pub light: u32,
}

#[derive(Clone, Copy, Debug)]
pub struct SphereTransform {
    pub world_from_object: Affine3A,
    pub object_from_world: Affine3A,
    /// Inverse transpose of the linear part: maps object normals to world normals (then normalise).
    pub normal_to_world: Mat3A,
}

#[derive(Clone, Copy, Debug)]
pub struct PlaneGeom {
    pub normal: Vec3A,
    pub offset: f32,
    pub material: u32,
}

/// A closest hit found by an accelerator. For triangles `b1`, `b2` are the barycentric weights of vertices 1 and
/// 2; unused otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub prim: u32,
    pub b1: f32,
    pub b2: f32,
}

/// Everything an integrator needs to know about a surface point.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub p: Vec3A,
    /// Conservative absolute floating-point error bound of `p`, per coordinate (for robust ray spawning).
    pub p_err: Vec3A,
    /// Geometric normal (unit), oriented by the primitive (triangle winding, sphere outward, plane normal).
    pub ng: Vec3A,
    /// Shading normal (unit), on the same side as `ng`.
    pub ns: Vec3A,
    /// Surface parameterisation at the point (texture coordinates).
    pub uv: Vec2,
    /// Partial derivatives of the position with respect to u and v (world space, not normalised): from the
    /// triangle's uvs, the sphere's and the plane's parameterisations. Texturing and normal mapping use them.
    pub dpdu: Vec3A,
    pub dpdv: Vec3A,
    pub t: f32,
    pub prim: u32,
    pub material: u32,
    pub light: u32,
}

#[derive(Clone, Debug, Default)]
pub struct Primitives {
    pub tris: Vec<[Vec3A; 3]>,
    pub tri_shading: Vec<TriShading>,
    /// Per-vertex MikkTSpace tangents (xyz, bitangent sign in w) of the triangles of normal-mapped meshes.
    pub tri_tangents: Vec<[glam::Vec4; 3]>,
    pub spheres: Vec<SphereGeom>,
    pub planes: Vec<PlaneGeom>,
    /// Bounds of the bounded primitives (triangles and spheres).
    pub bounds: Bounds,
    /// Degenerate (zero-area or non-finite) mesh triangles that were skipped.
    pub skipped_degenerate: usize,
    /// Alpha masks of the scene (see [`crate::alpha`]) and, when there is any, one mask index per triangle
    /// ([`crate::alpha::NO_ALPHA`] for opaque ones); empty in scenes without masks.
    pub alpha_masks: Vec<crate::alpha::AlphaMask>,
    pub tri_alpha: Vec<u32>,
}

/// The primitive range one entity produced (used to attach area lights).
#[derive(Clone, Copy, Debug)]
pub struct EntityPrims {
    pub first_tri: u32,
    pub tri_count: u32,
    pub sphere: Option<u32>,
}

impl SurfaceHit {
    /// A ray leaving this point in unit direction `dir`, offset off the surface.
    #[inline]
    pub fn spawn(&self, dir: Vec3A) -> Ray {
        spawn_ray(self.p, self.p_err, self.ng, dir)
    }

    /// A shadow ray from this point to a light sample (both ends offset off their surfaces).
    #[inline]
    pub fn spawn_to(&self, ls: &LightSample) -> Ray {
        if ls.dist.is_finite() {
            spawn_ray_to(self.p, self.p_err, self.ng, ls.p, ls.p_err, ls.n)
        } else {
            self.spawn(ls.wi)
        }
    }
}

/// Error bound of a barycentric combination `b0 p0 + b1 p1 + b2 p2` (pbrt-v4: gamma(7) times the sum of magnitudes).
#[inline]
pub fn interpolation_error(b: [f32; 3], p: &[Vec3A; 3]) -> Vec3A {
    gamma(7) * ((b[0] * p[0]).abs() + (b[1] * p[1]).abs() + (b[2] * p[2]).abs())
}

/// Error bound of the point `c + r n` reprojected onto a sphere, then mapped by `transform` (if any).
#[inline]
pub fn sphere_point_error(center: Vec3A, rn: Vec3A, transform: Option<&SphereTransform>) -> Vec3A {
    let err_o = gamma(6) * (center.abs() + rn.abs());
    match transform {
        None => err_o,
        Some(x) => {
            let m = x.world_from_object.matrix3;
            let abs_m = Mat3A::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
            let po = center + rn;
            (1.0 + gamma(3)) * (abs_m * err_o) + gamma(3) * (abs_m * po.abs() + x.world_from_object.translation.abs())
        }
    }
}

impl Primitives {
    #[inline]
    pub fn num_tris(&self) -> u32 {
        self.tris.len() as u32
    }

    /// Triangles + spheres: the primitives accelerators hold.
    #[inline]
    pub fn num_bounded(&self) -> u32 {
        (self.tris.len() + self.spheres.len()) as u32
    }

    pub fn num_total(&self) -> u32 {
        self.num_bounded() + self.planes.len() as u32
    }

    /// World bounds of bounded primitive `id`.
    pub fn prim_bounds(&self, id: u32) -> Bounds {
        let nt = self.num_tris();
        if id < nt {
            Bounds::from_points(&self.tris[id as usize])
        } else {
            let s = &self.spheres[(id - nt) as usize];
            let local = Bounds::new(s.center - Vec3A::splat(s.radius), s.center + Vec3A::splat(s.radius));
            match &s.transform {
                None => local,
                Some(t) => local.transformed(&t.world_from_object),
            }
        }
    }

    /// Intersect bounded primitive `id`; `wt` is the ray's watertight precomputation.
    #[inline(always)]
    pub fn intersect_bounded(&self, id: u32, ray: &Ray, wt: &WatertightRay) -> Option<Hit> {
        let nt = self.num_tris();
        if id < nt {
            let [p0, p1, p2] = self.tris[id as usize];
            wt.intersect(p0, p1, p2, ray.tmax).map(|h| Hit { t: h.t, prim: id, b1: h.b1, b2: h.b2 })
        } else {
            self.intersect_sphere(id, ray)
        }
    }

    #[inline]
    pub fn intersect_sphere(&self, id: u32, ray: &Ray) -> Option<Hit> {
        let s = &self.spheres[(id - self.num_tris()) as usize];
        let t = match &s.transform {
            None => intersect_sphere(s.center, s.radius, ray.origin, ray.dir, ray.tmax),
            Some(x) => intersect_sphere(
                s.center,
                s.radius,
                x.object_from_world.transform_point3a(ray.origin),
                x.object_from_world.transform_vector3a(ray.dir),
                ray.tmax,
            ),
        }?;
        Some(Hit { t, prim: id, b1: 0.0, b2: 0.0 })
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
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfaceHit {
        let nt = self.num_tris();
        let ns_ = self.spheres.len() as u32;
        if hit.prim < nt {
            let [p0, p1, p2] = self.tris[hit.prim as usize];
            let sh = &self.tri_shading[hit.prim as usize];
            let b0 = 1.0 - hit.b1 - hit.b2;
            // Interpolating the vertices is more accurate than o + t d (Wächter & Binder).
            let p = b0 * p0 + hit.b1 * p1 + hit.b2 * p2;
            let ng = (p1 - p0).cross(p2 - p0).normalize();
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
        } else if hit.prim < nt + ns_ {
            let s = &self.spheres[(hit.prim - nt) as usize];
            let (p, p_err, n, no) = match &s.transform {
                None => {
                    let n = (ray.at(hit.t) - s.center).normalize();
                    (s.center + n * s.radius, sphere_point_error(s.center, n * s.radius, None), n, n)
                }
                Some(x) => {
                    let po = x.object_from_world.transform_point3a(ray.origin)
                        + x.object_from_world.transform_vector3a(ray.dir) * hit.t;
                    let no = (po - s.center).normalize();
                    let p = x.world_from_object.transform_point3a(s.center + no * s.radius);
                    let err = sphere_point_error(s.center, no * s.radius, Some(x));
                    (p, err, (x.normal_to_world * no).normalize(), no)
                }
            };
            // uv and derivatives from the object-space normal (the sphere's own parameterisation).
            let (uv, mut dpdu, mut dpdv) = sphere_uv(no, s.radius);
            if let Some(x) = &s.transform {
                dpdu = x.world_from_object.transform_vector3a(dpdu);
                dpdv = x.world_from_object.transform_vector3a(dpdv);
            }
            SurfaceHit {
                p,
                p_err,
                ng: n,
                ns: n,
                uv,
                dpdu,
                dpdv,
                t: hit.t,
                prim: hit.prim,
                material: s.material,
                light: s.light,
            }
        } else {
            let pl = &self.planes[(hit.prim - nt - ns_) as usize];
            let mut p = ray.at(hit.t);
            p -= (pl.normal.dot(p) - pl.offset) * pl.normal;
            // u, v: coordinates along the plane's frame (world units, so textures tile once per unit).
            let f = crate::math::Frame::from_normal(pl.normal);
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

    /// Flatten every entity with a shape. Returns the primitives and, per entity with an area light, its prims.
    pub fn build(
        world: &hecs::World,
        meshes: &MeshStore,
        materials: &[crate::material::Material],
    ) -> Result<(Self, Vec<(hecs::Entity, EntityPrims)>)> {
        let num_materials = materials.len() as u32;
        let mut prims = Primitives::default();
        let mut emitters = Vec::new();
        let mut q = world.query::<(
            hecs::Entity,
            &Shape,
            Option<&WorldFromLocal>,
            Option<&MaterialId>,
            Option<&Light>,
            Option<&crate::alpha::AlphaMask>,
        )>();
        let mut items: Vec<_> = q.iter().collect();
        // Entity order is deterministic already; sort by id so the primitive order does not depend on archetypes.
        items.sort_by_key(|(e, ..)| e.id());
        for (entity, shape, wfl, mat, light, alpha) in items {
            let m = wfl.map(|w| w.0).unwrap_or(Affine3A::IDENTITY);
            let material = mat.map(|m| m.0).unwrap_or(0).min(num_materials.saturating_sub(1));
            let emits = matches!(light, Some(Light::Area { .. }));
            let light_slot = if emits { emitters.len() as u32 } else { NO_LIGHT };
            let first_tri = prims.num_tris();
            let mut sphere = None;
            let name = || crate::load::entity_label(world, entity);
            match shape {
                Shape::Sphere { center, radius } => {
                    sphere = Some(prims.spheres.len() as u32);
                    prims.spheres.push(make_sphere(&m, (*center).into(), *radius, material, light_slot));
                    let b = prims.prim_bounds(prims.num_bounded() - 1);
                    if !within_limits(b.min) || !within_limits(b.max) {
                        return Err(beyond_limits(name(), "sphere", b.min.abs().max(b.max.abs())));
                    }
                }
                Shape::Plane { normal, offset } => {
                    if emits {
                        return Err(PrismError::scene(
                            name(),
                            "a plane cannot be an area light (its area is infinite)",
                        ));
                    }
                    // n.x = d in local space; world: n' = M^-T n, d' = n' . (M p0) for a point p0 on the plane.
                    let n_local = Vec3A::from(*normal).normalize();
                    let p0 = n_local * *offset;
                    let inv_t = m.matrix3.inverse().transpose();
                    let n_world = (inv_t * n_local).normalize();
                    let off = n_world.dot(m.transform_point3a(p0));
                    if !(n_world.is_finite() && off.is_finite() && off.abs() <= crate::limits::MAX_COORDINATE) {
                        return Err(beyond_limits(name(), "plane", Vec3A::splat(off.abs())));
                    }
                    prims.planes.push(PlaneGeom { normal: n_world, offset: off, material });
                }
                Shape::Triangle { p, n, uv } => {
                    let v = p.map(|q| m.transform_point3a(q.into()));
                    if let Some(far) = v.iter().find(|q| !within_limits(**q)) {
                        return Err(beyond_limits(name(), "triangle", far.abs()));
                    }
                    if !is_valid_triangle(&v) {
                        return Err(PrismError::scene(name(), "triangle has zero area (or non-finite vertices)"));
                    }
                    let normals = n.map(|n| n.map(|q| transform_normal(&m, q.into())));
                    let uvs = uv.unwrap_or([Vec2::ZERO, Vec2::X, Vec2::Y]);
                    let dpduv = triangle_dpduv(v, uvs);
                    prims.tris.push(v);
                    prims.tri_shading.push(TriShading {
                        normals,
                        uvs,
                        material,
                        light: light_slot,
                        tangents: NO_TANGENTS,
                        dpduv,
                    });
                }
                Shape::Mesh(h) => {
                    let mesh = meshes.get(*h);
                    let world_pos: Vec<Vec3A> = mesh.positions.iter().map(|&q| m.transform_point3a(q.into())).collect();
                    let world_n: Vec<Vec3A> = mesh.normals.iter().map(|&q| transform_normal(&m, q.into())).collect();
                    // Tangents only for normal-mapped meshes: object-space MikkTSpace, carried to world space (a
                    // mirroring transform flips the bitangent sign).
                    let tangents = materials
                        .get(material as usize)
                        .is_some_and(|mat| mat.needs_tangents())
                        .then(|| crate::mesh_tangents::corner_tangents(mesh));
                    let det_sign = m.matrix3.determinant().signum();
                    for (f, idx) in mesh.indices.iter().enumerate() {
                        let v = idx.map(|i| world_pos[i as usize]);
                        if let Some(far) = v.iter().find(|q| !within_limits(**q)) {
                            return Err(beyond_limits(name(), &format!("mesh '{}'", mesh.name), far.abs()));
                        }
                        if !is_valid_triangle(&v) {
                            prims.skipped_degenerate += 1;
                            continue;
                        }
                        let normals = (!world_n.is_empty()).then(|| idx.map(|i| world_n[i as usize]));
                        let uvs = if mesh.uvs.is_empty() {
                            [Vec2::ZERO, Vec2::X, Vec2::Y]
                        } else {
                            idx.map(|i| mesh.uvs[i as usize])
                        };
                        let tangents = match &tangents {
                            Some(t) => {
                                prims.tri_tangents.push(t[f].map(|c| {
                                    let d = m.matrix3.mul_vec3a(c.truncate().into()).normalize_or_zero();
                                    d.extend(c.w * det_sign)
                                }));
                                prims.tri_tangents.len() as u32 - 1
                            }
                            None => NO_TANGENTS,
                        };
                        let dpduv = triangle_dpduv(v, uvs);
                        prims.tris.push(v);
                        prims.tri_shading.push(TriShading {
                            normals,
                            uvs,
                            material,
                            light: light_slot,
                            tangents,
                            dpduv,
                        });
                    }
                }
            }
            if let Some(mask) = alpha {
                if sphere.is_some() {
                    return Err(PrismError::scene(name(), "alpha masks apply to triangles and meshes, not spheres"));
                }
                prims.tri_alpha.resize(first_tri as usize, crate::alpha::NO_ALPHA);
                prims.tri_alpha.resize(prims.tris.len(), prims.alpha_masks.len() as u32);
                prims.alpha_masks.push(mask.clone());
            }
            if emits {
                let tri_count = prims.num_tris() - first_tri;
                if tri_count == 0 && sphere.is_none() {
                    return Err(PrismError::scene(name(), "area light has no surface (all triangles degenerate)"));
                }
                emitters.push((entity, EntityPrims { first_tri, tri_count, sphere }));
            }
        }
        if !prims.tri_alpha.is_empty() {
            prims.tri_alpha.resize(prims.tris.len(), crate::alpha::NO_ALPHA);
        }
        prims.bounds = (0..prims.num_bounded()).fold(Bounds::EMPTY, |b, i| b.union(prims.prim_bounds(i)));
        Ok((prims, emitters))
    }
}

/// True when every coordinate of `p` is finite and within [`crate::limits::MAX_COORDINATE`].
fn within_limits(p: Vec3A) -> bool {
    p.is_finite() && p.abs().max_element() <= crate::limits::MAX_COORDINATE
}

/// The error for a shape that reaches `extent` (per-axis magnitude) in world space, beyond the coordinate limit.
fn beyond_limits(entity: String, what: &str, extent: Vec3A) -> PrismError {
    PrismError::scene(
        entity,
        format!(
            "{what} reaches {:e} in world space, beyond Prism's coordinate limit of {:e} (or is not finite)",
            extent.max_element(),
            crate::limits::MAX_COORDINATE
        ),
    )
}

fn is_valid_triangle(v: &[Vec3A; 3]) -> bool {
    v.iter().all(|p| p.is_finite()) && (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}

fn transform_normal(m: &Affine3A, n: Vec3A) -> Vec3A {
    (m.matrix3.inverse().transpose() * n).normalize_or_zero()
}

/// A sphere under `m`: stored in world space if `m` is a similarity (rotation, uniform scale, translation),
/// otherwise kept in object space with the transform (an ellipsoid).
fn make_sphere(m: &Affine3A, center: Vec3A, radius: f32, material: u32, light: u32) -> SphereGeom {
    let l = m.matrix3;
    let (sx, sy, sz) = (l.x_axis.length(), l.y_axis.length(), l.z_axis.length());
    let orthogonal = l.x_axis.dot(l.y_axis).abs() < 1e-6 * sx * sy
        && l.y_axis.dot(l.z_axis).abs() < 1e-6 * sy * sz
        && l.z_axis.dot(l.x_axis).abs() < 1e-6 * sz * sx;
    let uniform = (sx - sy).abs() <= 1e-6 * sx && (sy - sz).abs() <= 1e-6 * sy;
    if orthogonal && uniform {
        return SphereGeom {
            center: m.transform_point3a(center),
            radius: radius * sx,
            transform: None,
            material,
            light,
        };
    }
    let inv = m.inverse();
    SphereGeom {
        center,
        radius,
        transform: Some(SphereTransform {
            world_from_object: *m,
            object_from_world: inv,
            normal_to_world: inv.matrix3.transpose(),
        }),
        material,
        light,
    }
}

/// Spherical (u, v) in [0,1]^2 from a unit object-space normal, and dp/du, dp/dv for radius `r`: u around +y,
/// 0.5 straight ahead along +z and growing towards +x (an image wrapped around the sphere reads left to right
/// seen from outside), v = theta / pi from the north pole (+y, the image's top row) down.
pub fn sphere_uv(n: Vec3A, r: f32) -> (Vec2, Vec3A, Vec3A) {
    use std::f32::consts::PI;
    let u = 0.5 + n.x.atan2(n.z) / (2.0 * PI);
    let v = n.y.clamp(-1.0, 1.0).acos() / PI;
    let sin_t = (n.x * n.x + n.z * n.z).sqrt();
    let dpdu = 2.0 * PI * r * Vec3A::new(n.z, 0.0, -n.x);
    let dpdv = if sin_t > 1e-6 {
        PI * r * Vec3A::new(n.x * n.y / sin_t, -sin_t, n.z * n.y / sin_t)
    } else {
        // At the poles dp/du vanishes; any tangent orthogonal to the normal will do for dp/dv.
        PI * r * Vec3A::new(0.0, 0.0, if n.y > 0.0 { 1.0 } else { -1.0 })
    };
    (Vec2::new(u, v), dpdu, dpdv)
}

/// dp/du and dp/dv of a triangle from its vertex uvs (pbrt-v4's formulas); a frame around the normal when the uvs
/// are degenerate.
fn triangle_dpduv(p: [Vec3A; 3], uv: [Vec2; 3]) -> [Vec3; 2] {
    let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    if det.abs() > 1e-12 {
        let inv = 1.0 / det;
        let dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
        let dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
        if dpdu.cross(dpdv).length_squared() > 0.0 && dpdu.is_finite() && dpdv.is_finite() {
            return [dpdu.into(), dpdv.into()];
        }
    }
    let f = crate::math::Frame::from_normal(ng);
    [f.s.into(), f.t.into()]
}

/// World-space position of the local point `p` (used by lights).
pub fn world_point(m: &Affine3A, p: Vec3) -> Vec3A {
    m.transform_point3a(p.into())
}
