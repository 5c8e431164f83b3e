//! The shapes of a RON scene's entities: validation of each analytic shape's parameters (with errors naming the
//! entity), the tessellation settings, and mesh files split into one part per material group.

use super::{Spawner, point};
use crate::curved;
use crate::obj::load_obj;
use crate::schema::{ShapeDesc, TessellationDesc};
use glam::{Vec2, Vec3};
use prism_core::error::{PrismError, Result};
use prism_core::material::Material;
use prism_core::mesh::MeshData;
use prism_engine::components::Shape;
use prism_engine::reload_cache::{LoadedMeshes, MeshFileKey, ReloadCache};
use std::path::Path;

impl Spawner<'_> {
    pub(super) fn shape(&mut self, s: &ShapeDesc, ctx: &str) -> Result<ShapeOut> {
        Ok(ShapeOut::One(match s {
            ShapeDesc::Sphere { center, radius } => {
                if !(radius.is_finite() && *radius > 0.0) {
                    return Err(PrismError::scene(ctx, format!("sphere radius must be positive, got {radius}")));
                }
                Shape::Sphere { center: point(*center, "sphere center", ctx)?, radius: *radius }
            }
            ShapeDesc::Plane { normal, offset } => {
                let n = point(*normal, "plane normal", ctx)?;
                if n == Vec3::ZERO || !offset.is_finite() {
                    return Err(PrismError::scene(ctx, "plane needs a non-zero normal and a finite offset"));
                }
                // In f64: the squared length of a tiny normal (1e-30) would underflow in f32.
                let n64 = n.as_dvec3();
                let len = n64.length();
                let d = *offset as f64 / len;
                if d.abs() > prism_core::limits::MAX_COORDINATE as f64 {
                    return Err(PrismError::scene(
                        ctx,
                        format!(
                            "plane `normal . x = offset` lies {d:e} from the origin, beyond Prism's coordinate limit \
                             of {:e}",
                            prism_core::limits::MAX_COORDINATE
                        ),
                    ));
                }
                Shape::Plane { normal: (n64 / len).as_vec3(), offset: d as f32 }
            }
            ShapeDesc::Triangle { vertices, normals, uvs } => {
                let p = [
                    point(vertices[0], "vertex", ctx)?,
                    point(vertices[1], "vertex", ctx)?,
                    point(vertices[2], "vertex", ctx)?,
                ];
                if (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0 {
                    return Err(PrismError::scene(ctx, format!("triangle has zero area: {vertices:?}")));
                }
                let n = normals
                    .map(|ns| -> Result<[Vec3; 3]> {
                        let mut out = [Vec3::ZERO; 3];
                        for (o, v) in out.iter_mut().zip(ns) {
                            *o = prism_core::math::unit_vector(point(v, "normal", ctx)?)
                                .ok_or_else(|| PrismError::scene(ctx, "triangle normal is zero"))?;
                        }
                        Ok(out)
                    })
                    .transpose()?;
                Shape::Triangle { p, n, uv: uvs.map(|u| u.map(Vec2::from)) }
            }
            ShapeDesc::Quad { corners } => {
                let mesh = match corners {
                    None => MeshData::unit_quad(),
                    Some(c) => {
                        let q = [
                            point(c[0], "corner", ctx)?,
                            point(c[1], "corner", ctx)?,
                            point(c[2], "corner", ctx)?,
                            point(c[3], "corner", ctx)?,
                        ];
                        if (q[1] - q[0]).cross(q[2] - q[0]).length_squared() == 0.0
                            || (q[2] - q[0]).cross(q[3] - q[0]).length_squared() == 0.0
                        {
                            return Err(PrismError::scene(ctx, format!("quad is degenerate (zero area): {c:?}")));
                        }
                        MeshData::quad("quad", q)
                    }
                };
                Shape::Mesh(self.res.meshes.add(mesh))
            }
            ShapeDesc::Cube => Shape::Mesh(self.res.meshes.add(MeshData::unit_cube())),
            ShapeDesc::Mesh { path, flat, reverse } => {
                let full = self.base_dir.join(path);
                return self.mesh_file(&full, *flat, *reverse, ctx);
            }
            ShapeDesc::Gltf { .. } => {
                return Err(PrismError::scene(ctx, "a glTF scene is placed by its entity, not as a shape part"));
            }
            ShapeDesc::TriangleMesh(name) => Shape::Mesh(*self.inline_meshes.get(name).ok_or_else(|| {
                let mut known: Vec<&str> = self.inline_meshes.keys().map(String::as_str).collect();
                known.sort();
                PrismError::scene(ctx, format!("unknown mesh '{name}' (defined: {})", known.join(", ")))
            })?),
            ShapeDesc::Revolution { profile, tessellation } => {
                let profile = curved::profile_curve(profile, ctx)?;
                curved::revolution_shape(self.res, profile, self.tessellation(*tessellation), ctx)?
            }
            ShapeDesc::BezierPatch { points, tessellation } => {
                let points = curved::patch_points(points, ctx)?;
                curved::patch_shape(self.res, points, self.tessellation(*tessellation), ctx)?
            }
            ShapeDesc::Splines { path, tessellation } => {
                let full = self.base_dir.join(path);
                let mut parts = curved::spline_file_shapes(self.res, &full, self.tessellation(*tessellation), ctx)?;
                if parts.len() == 1 {
                    return Ok(ShapeOut::One(parts.remove(0).1));
                }
                return Ok(ShapeOut::Parts(
                    parts
                        .into_iter()
                        .map(|(name, shape)| MeshPart { name, shape, material: None, emission: None })
                        .collect(),
                ));
            }
        }))
    }

    /// The tessellation a curved shape asks for, unless curves are rendered exactly (`--exact-curves`).
    fn tessellation(&self, t: Option<TessellationDesc>) -> Option<TessellationDesc> {
        if self.res.overrides.exact_curves { None } else { t }
    }

    fn mesh_file(&mut self, path: &Path, flat: bool, reverse: bool, ctx: &str) -> Result<ShapeOut> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if ext != "obj" && ext != "ply" {
            return Err(PrismError::scene(
                ctx,
                format!("mesh '{}': unsupported format (expected .obj, .ply, or a .gltf/.glb scene)", path.display()),
            ));
        }
        if let Err(e) = prism_core::io::open_regular(path, "mesh file") {
            return Err(PrismError::scene(ctx, e.to_string()));
        }
        self.res.inputs.push(path.to_path_buf());
        let key = path.to_path_buf();
        if let Some(p) = self.part_cache.get(&(key.clone(), flat, reverse)) {
            // Referenced before: share the meshes and materials.
            let p = p.clone();
            return Ok(if ext == "ply" { ShapeOut::One(p[0].shape.clone()) } else { parts_out(p) });
        }
        // A process that loads the scene again (`prism watch`) keeps the file's meshes while the file is unchanged.
        let cache_key = self.res.get::<ReloadCache>().and_then(|_| MeshFileKey::of(path, flat, reverse));
        let cached = cache_key.as_ref().and_then(|k| self.res.get_mut::<ReloadCache>()?.mesh_file(k));
        let loaded = match cached {
            Some(l) => l,
            None => {
                let loaded = self.read_mesh_file(path, &ext, flat, reverse)?;
                if let (Some(k), Some(c)) = (cache_key, self.res.get_mut::<ReloadCache>()) {
                    c.keep_mesh_file(k, loaded.clone());
                }
                loaded
            }
        };
        let mut out = Vec::with_capacity(loaded.len());
        for (mesh, mtl, emission) in loaded {
            let material = mtl.map(|m| {
                let k = (key.clone(), m.name.clone());
                *self.mtl_ids.entry(k).or_insert_with(|| {
                    self.res.materials.push(Material { name: format!("{}:{}", path.display(), m.name), ..m });
                    self.res.materials.len() as u32 - 1
                })
            });
            let name = mesh.name.clone();
            let h = self.res.meshes.add_shared(mesh);
            out.push(MeshPart { name, shape: Shape::Mesh(h), material, emission });
        }
        self.part_cache.insert((key, flat, reverse), out.clone());
        Ok(if ext == "ply" { ShapeOut::One(out.remove(0).shape) } else { parts_out(out) })
    }

    /// Read a PLY (one mesh) or OBJ file (its models with their MTL materials), with the shading normals dropped
    /// (`flat`) or the winding reversed as asked.
    fn read_mesh_file(&self, path: &Path, ext: &str, flat: bool, reverse: bool) -> Result<LoadedMeshes> {
        let adjust = |mut mesh: prism_core::mesh::MeshData| {
            if flat {
                mesh.normals.clear();
            }
            if reverse {
                crate::inline_mesh::reverse_winding(&mut mesh);
            }
            std::sync::Arc::new(mesh)
        };
        if ext == "ply" {
            return Ok(vec![(adjust(crate::ply::load_ply(path)?), None, None)]);
        }
        Ok(load_obj(path)?.into_iter().map(|p| (adjust(p.mesh), p.material, p.emission)).collect())
    }
}

/// A mesh file's parts as a shape: one shape when it is a single part without material or emission.
fn parts_out(parts: Vec<MeshPart>) -> ShapeOut {
    if parts.len() == 1 && parts[0].emission.is_none() && parts[0].material.is_none() {
        return ShapeOut::One(parts[0].shape.clone());
    }
    ShapeOut::Parts(parts)
}

/// One material group of a mesh file: its own entity with the group's material (and emission).
#[derive(Clone)]
pub(super) struct MeshPart {
    pub(super) name: String,
    pub(super) shape: Shape,
    pub(super) material: Option<u32>,
    pub(super) emission: Option<Vec3>,
}

/// What an entity's shape description yields: one shape, or a mesh file's parts.
pub(super) enum ShapeOut {
    One(Shape),
    Parts(Vec<MeshPart>),
}
