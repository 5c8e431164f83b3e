//! Building the primitives from the scene's shapes (the BuildAccel stage): every shape flattened into world space —
//! mesh triangles with their shading data, tangents and alpha masks, analytic shapes with their transforms, planes
//! — each checked against Prism's coordinate limit and for degenerate input, with the errors naming the shape's
//! owner; and, per shape that is an area light, the primitives it emits from. The engine gathers the shapes from
//! the scene's entities ([`ShapeInstance`]).

use super::{EntityPrims, NO_LIGHT, NO_TANGENTS, PlaneGeom, Primitives, TriShading, triangle_normal};
use crate::alpha::AlphaMask;
use crate::error::{PrismError, Result};
use crate::geometry::Bounds;
use crate::mesh::MeshStore;
use crate::shapes::{BezierPatch, Revolution, Shape, ShapeRef, SphereGeom};
use glam::{Affine3A, DAffine3, DMat3, Vec2, Vec3, Vec3A};

/// One shape to flatten, placed in the world: what an entity with a `Shape` component carries.
#[derive(Clone, Copy, Debug)]
pub struct ShapeInstance<'a> {
    /// The geometry, in its local frame.
    pub shape: &'a Shape,
    /// The composed transform from the shape's frame to world space.
    pub world_from_local: Affine3A,
    /// Index of its material in the scene's material table.
    pub material: u32,
    /// Whether the shape is an area light (it then gets a light slot).
    pub area_light: bool,
    /// The alpha mask cutting holes into it (triangles and meshes only).
    pub alpha: Option<&'a AlphaMask>,
    /// Whether anything reads the surface's texture coordinates (spheres skip computing them otherwise).
    pub surface_coordinates: bool,
    /// Whether its material is normal-mapped (meshes then carry MikkTSpace tangents).
    pub tangents: bool,
}

impl Primitives {
    /// Flatten `shapes` in order. `label(i)` names the owner of `shapes[i]` in errors. Returns the primitives and,
    /// per area light in light-slot order, the index of its shape and its primitives.
    pub fn build(
        shapes: &[ShapeInstance<'_>],
        meshes: &MeshStore,
        label: impl Fn(usize) -> String,
    ) -> Result<(Self, Vec<(usize, EntityPrims)>)> {
        // Counted before anything is made: a mesh placed by many entities is copied into world space once per use.
        let total = shapes.iter().fold(0u64, |n, s| {
            n.saturating_add(match s.shape {
                Shape::Mesh(h) => meshes.get(*h).indices.len() as u64,
                _ => 1,
            })
        });
        if total > crate::limits::MAX_PRIMITIVES {
            return Err(PrismError::invalid(format!(
                "the scene has {total} primitives once every mesh is placed (instances count once per use), more \
                 than Prism holds ({})",
                crate::limits::MAX_PRIMITIVES
            )));
        }
        let mut prims = Primitives::default();
        let mut emitters = Vec::new();
        for (index, item) in shapes.iter().enumerate() {
            let ShapeInstance { shape, world_from_local: m, material, area_light: emits, alpha, .. } = *item;
            let light_slot = if emits { emitters.len() as u32 } else { NO_LIGHT };
            let first_tri = prims.num_tris();
            let mut sphere = None;
            let mut curved = None;
            let name = || label(index);
            match shape {
                Shape::Sphere { center, radius } => {
                    sphere = Some(prims.spheres.len() as u32);
                    prims.analytic.push(ShapeRef::Sphere(prims.spheres.len() as u32));
                    // Texture coordinates only where something reads them (the material, or the light's
                    // textured radiance and sampling density).
                    let coordinates = emits || item.surface_coordinates;
                    let geom = SphereGeom::new(&m, (*center).into(), *radius, material, light_slot);
                    prims.spheres.push(SphereGeom { coordinates, ..geom });
                    let b = prims.prim_bounds(prims.num_bounded() - 1);
                    if !within_limits(b.min) || !within_limits(b.max) {
                        return Err(beyond_limits(name(), "sphere", b.min.abs().max(b.max.abs())));
                    }
                }
                Shape::Revolution { profile } => {
                    curved = Some(prims.analytic.len() as u32);
                    prims.analytic.push(ShapeRef::Revolution(prims.revolutions.len() as u32));
                    prims.revolutions.push(Revolution::new(profile.clone(), to_f64(&m), material, light_slot));
                    let b = prims.prim_bounds(prims.num_bounded() - 1);
                    if !within_limits(b.min) || !within_limits(b.max) {
                        return Err(beyond_limits(name(), "surface of revolution", b.min.abs().max(b.max.abs())));
                    }
                }
                Shape::BezierPatch { points } => {
                    let w = to_f64(&m);
                    let ctrl = points.map(|p| w.transform_point3(p.as_dvec3()));
                    if ctrl.iter().any(|p| !p.is_finite()) {
                        return Err(PrismError::scene(name(), "Bézier patch has non-finite control points"));
                    }
                    curved = Some(prims.analytic.len() as u32);
                    prims.analytic.push(ShapeRef::Patch(prims.patches.len() as u32));
                    prims.patches.push(BezierPatch::new(ctrl, material, light_slot));
                    let b = prims.prim_bounds(prims.num_bounded() - 1);
                    if !within_limits(b.min) || !within_limits(b.max) {
                        return Err(beyond_limits(name(), "Bézier patch", b.min.abs().max(b.max.abs())));
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
                        ng: triangle_normal(&v),
                    });
                }
                Shape::Mesh(h) => {
                    let mesh = meshes.get(*h);
                    let world_pos: Vec<Vec3A> = mesh.positions.iter().map(|&q| m.transform_point3a(q.into())).collect();
                    let world_n: Vec<Vec3A> = mesh.normals.iter().map(|&q| transform_normal(&m, q.into())).collect();
                    // Tangents only for normal-mapped meshes: object-space MikkTSpace, carried to world space (a
                    // mirroring transform flips the bitangent sign).
                    let tangents = item.tangents.then(|| crate::mesh_tangents::corner_tangents(mesh));
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
                            ng: triangle_normal(&v),
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
                if tri_count == 0 && sphere.is_none() && curved.is_none() {
                    return Err(PrismError::scene(name(), "area light has no surface (all triangles degenerate)"));
                }
                emitters.push((index, EntityPrims { first_tri, tri_count, sphere, curved }));
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

/// An f32 affine map in f64 (exactly).
pub fn to_f64(m: &Affine3A) -> DAffine3 {
    DAffine3 {
        matrix3: DMat3::from_cols(
            m.matrix3.x_axis.as_dvec3(),
            m.matrix3.y_axis.as_dvec3(),
            m.matrix3.z_axis.as_dvec3(),
        ),
        translation: m.translation.as_dvec3(),
    }
}

fn transform_normal(m: &Affine3A, n: Vec3A) -> Vec3A {
    (m.matrix3.inverse().transpose() * n).normalize_or_zero()
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
