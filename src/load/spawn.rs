//! Spawn a parsed RON scene into the ECS world: one entity per scene entity (children get a `Parent`), each with
//! only the components it uses; materials and meshes go to the resource tables. All semantic validation happens
//! here, with errors naming the file and the entity.

use super::curved;
use super::desc::{
    AccelDesc, CameraDesc, EntityDesc, LightDesc, MaterialDesc, SceneDesc, ShapeDesc, TessellationDesc, V3,
};
use super::obj::load_obj;
use super::ron_scene::plugin_config;
use super::transform::compose;
use crate::app::Resources;
use crate::components::{Camera, Light, MaterialId, Name, Parent, Projection, Shape, Transform};
use crate::error::{PrismError, Result};
use crate::material::{Material, Shading};
use crate::mesh::MeshData;
use crate::sampling::PixelPattern;
use crate::settings::{AccelKind, GridResolution, PluginConfig};
use glam::{Vec2, Vec3};
use hecs::{Entity, EntityBuilder, World};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Render settings a scene file asked for (each may be overridden on the command line).
#[derive(Clone, Debug, Default)]
pub struct FileSettings {
    pub integrator: Option<PluginConfig>,
    pub accel: Option<AccelKind>,
    pub spp: Option<u32>,
    pub passes: Option<u32>,
    pub pattern: Option<PixelPattern>,
    pub seed: Option<u64>,
    pub time: Option<f64>,
    pub exposure: Option<f32>,
}

struct MaterialEntry {
    id: u32,
    emission: Option<(Vec3, bool)>,
}

struct Spawner<'r> {
    file: PathBuf,
    base_dir: PathBuf,
    res: &'r mut Resources,
    materials: HashMap<String, MaterialEntry>,
    mtl_ids: HashMap<(PathBuf, String), u32>,
    part_cache: HashMap<(PathBuf, bool), Vec<MeshPart>>,
}

fn color(v: V3, what: &str, ctx: &str) -> Result<Vec3> {
    if v.iter().any(|x| !x.is_finite() || *x < 0.0) {
        return Err(PrismError::scene(ctx, format!("{what} must be finite and non-negative, got {v:?}")));
    }
    Ok(Vec3::from(v))
}

fn point(v: V3, what: &str, ctx: &str) -> Result<Vec3> {
    if v.iter().any(|x| !x.is_finite()) {
        return Err(PrismError::scene(ctx, format!("{what} contains NaN or infinity: {v:?}")));
    }
    Ok(Vec3::from(v))
}

/// Spawn everything; returns the settings the file asked for.
pub fn spawn_scene(
    desc: &SceneDesc,
    text: &str,
    file: &Path,
    base_dir: &Path,
    world: &mut World,
    res: &mut Resources,
) -> Result<FileSettings> {
    let ctx = file.display().to_string();
    res.globals.background = color(desc.background, "background", &ctx)?;
    res.globals.ambient = color(desc.ambient, "ambient", &ctx)?;
    if res.materials.is_empty() {
        res.materials.push(Material::default());
    }
    let mut sp = Spawner {
        file: file.to_path_buf(),
        base_dir: base_dir.to_path_buf(),
        res,
        materials: HashMap::new(),
        mtl_ids: HashMap::new(),
        part_cache: HashMap::new(),
    };
    for (name, m) in &desc.materials {
        sp.add_material(name, m)?;
    }
    if let Some(cam) = &desc.camera {
        let c = camera_component(cam, &format!("{ctx}: camera"))?;
        world.spawn((Name("camera".into()), c));
    }
    for (i, e) in desc.entities.iter().enumerate() {
        sp.spawn_entity(world, e, None, None, &format!("entities[{i}]"))?;
    }
    let r = &desc.render;
    Ok(FileSettings {
        integrator: r.integrator.map(|raw| plugin_config(raw, text, file)).transpose()?,
        accel: accel_kind(r.accel, r.grid, &ctx)?,
        spp: r.spp,
        passes: r.passes,
        pattern: r.pattern,
        seed: r.seed,
        time: r.time,
        exposure: r.exposure,
    })
}

/// The accelerator a scene's `render: (accel: ..., grid: ...)` asks for; `grid` alone implies the grid.
fn accel_kind(accel: Option<AccelDesc>, grid: Option<[u32; 3]>, ctx: &str) -> Result<Option<AccelKind>> {
    if let Some(r) = grid {
        crate::accel::grid::check_resolution(r).map_err(|e| PrismError::scene(ctx, format!("render: {e}")))?;
    }
    let resolution = grid.map_or(GridResolution::Auto, GridResolution::Fixed);
    Ok(match (accel, grid) {
        (None, None) => None,
        (None | Some(AccelDesc::Grid), _) => Some(AccelKind::Grid(resolution)),
        (Some(a), Some(_)) => {
            return Err(PrismError::scene(
                ctx,
                format!("render: a `grid` resolution needs accel: grid, not {}", format!("{a:?}").to_lowercase()),
            ));
        }
        (Some(AccelDesc::Bvh), None) => Some(AccelKind::Bvh),
        (Some(AccelDesc::Kdtree), None) => Some(AccelKind::KdTree),
        (Some(AccelDesc::Brute), None) => Some(AccelKind::Brute),
    })
}

/// The camera component of a camera description (validated).
pub fn camera_component(c: &CameraDesc, ctx: &str) -> Result<Camera> {
    let eye = point(c.eye, "eye", ctx)?;
    let target = point(c.target, "target", ctx)?;
    let up = point(c.up, "up", ctx)?;
    let projection = match c.orthographic {
        Some(h) if h.is_finite() && h > 0.0 => Projection::Orthographic { height: h },
        Some(h) => {
            return Err(PrismError::scene(ctx, format!("orthographic height must be positive, got {h}")));
        }
        None if c.fov.is_finite() && c.fov > 0.0 && c.fov < 180.0 => Projection::Perspective { fov_y: c.fov },
        None => {
            return Err(PrismError::scene(ctx, format!("fov must be between 0 and 180 degrees, got {}", c.fov)));
        }
    };
    let fwd = target - eye;
    if fwd.length_squared() == 0.0 || fwd.cross(up).length_squared() == 0.0 {
        return Err(PrismError::scene(
            ctx,
            "eye, target and up do not define a view (eye == target or up parallel to the view)",
        ));
    }
    Ok(Camera { eye, target, up, projection, width: c.size.0, height: c.size.1 })
}

impl Spawner<'_> {
    fn ctx(&self) -> String {
        self.file.display().to_string()
    }

    fn add_material(&mut self, name: &str, m: &MaterialDesc) -> Result<()> {
        let ctx = format!("{}: material '{name}'", self.ctx());
        let mut emission = None;
        let mat = match m {
            MaterialDesc::Lambert { albedo, two_sided } => {
                Material { two_sided: *two_sided, ..Material::lambert(name, color(*albedo, "albedo", &ctx)?) }
            }
            MaterialDesc::Phong { ambient, diffuse, specular, exponent, reflective, transparent, ior, two_sided } => {
                let colors = [*ambient, *diffuse, *specular, *reflective, *transparent];
                phong_material(name, &ctx, colors, *exponent, *ior, *two_sided, Shading::Physical)?
            }
            // The course's ambient term is ambientLight times the diffuse colour.
            MaterialDesc::Mit6837 { diffuse, specular, exponent, reflective, transparent, ior, two_sided } => {
                let colors = [*diffuse, *diffuse, *specular, *reflective, *transparent];
                phong_material(name, &ctx, colors, *exponent, *ior, *two_sided, Shading::Mit6837)?
            }
            MaterialDesc::Mirror { reflectance } => {
                Material { reflective: color(*reflectance, "reflectance", &ctx)?, ..Material::black(name) }
            }
            MaterialDesc::Glass { ior, transmittance } => Material {
                transparent: color(*transmittance, "transmittance", &ctx)?,
                ior: check_ior(*ior, &ctx)?,
                ..Material::black(name)
            },
            MaterialDesc::Emissive { radiance, two_sided } => {
                emission = Some((color(*radiance, "radiance", &ctx)?, *two_sided));
                Material::black(name)
            }
        };
        self.res.materials.push(mat);
        let id = self.res.materials.len() as u32 - 1;
        self.materials.insert(name.to_string(), MaterialEntry { id, emission });
        Ok(())
    }

    fn lookup_material(&self, name: &str, ctx: &str) -> Result<&MaterialEntry> {
        self.materials.get(name).ok_or_else(|| {
            let mut known: Vec<&str> = self.materials.keys().map(String::as_str).collect();
            known.sort();
            PrismError::scene(
                ctx,
                format!(
                    "unknown material '{name}' (defined: {})",
                    if known.is_empty() { "none".into() } else { known.join(", ") }
                ),
            )
        })
    }

    fn spawn_entity(
        &mut self,
        world: &mut World,
        e: &EntityDesc,
        parent: Option<Entity>,
        inherited: Option<&str>,
        path: &str,
    ) -> Result<()> {
        let label = e.name.clone().unwrap_or_else(|| path.to_string());
        let ctx = format!("{}: entity '{label}'", self.ctx());
        let mut b = EntityBuilder::new();
        b.add(Name(label.clone()));
        if !e.transform.is_empty() {
            b.add(Transform(compose(&e.transform, &ctx)?));
        }
        if let Some(p) = parent {
            b.add(Parent(p));
        }
        let material_name = e.material.as_deref().or(inherited);
        let entry = material_name.map(|n| self.lookup_material(n, &ctx)).transpose()?;
        let (mat_id, mat_emission) = match entry {
            Some(m) => (Some(m.id), m.emission),
            None => (None, None),
        };
        let light = match &e.light {
            None => mat_emission.map(|(radiance, two_sided)| Light::Area { radiance, two_sided }),
            Some(_) if mat_emission.is_some() && e.material.is_some() => {
                return Err(PrismError::scene(&ctx, "has both an emissive material and a light; use one"));
            }
            Some(LightDesc::Point { intensity, position, attenuation }) => {
                let attenuation = color(*attenuation, "attenuation", &ctx)?;
                if attenuation == Vec3::ZERO {
                    return Err(PrismError::scene(&ctx, "point light attenuation (a0, a1, a2) is all zero"));
                }
                Some(Light::Point {
                    intensity: color(*intensity, "intensity", &ctx)?,
                    position: point(*position, "position", &ctx)?,
                    attenuation,
                })
            }
            Some(LightDesc::Directional { irradiance, direction }) => {
                let d = point(*direction, "direction", &ctx)?;
                if d == Vec3::ZERO {
                    return Err(PrismError::scene(&ctx, "directional light direction is the zero vector"));
                }
                Some(Light::Directional { irradiance: color(*irradiance, "irradiance", &ctx)?, direction: d })
            }
            Some(LightDesc::Area { radiance, two_sided }) => {
                Some(Light::Area { radiance: color(*radiance, "radiance", &ctx)?, two_sided: *two_sided })
            }
            Some(LightDesc::Environment { map, faces, layout, radiance, scale }) => {
                if !(scale.is_finite() && *scale >= 0.0) {
                    return Err(PrismError::scene(&ctx, format!("environment scale must be >= 0, got {scale}")));
                }
                let paths: Vec<PathBuf> = match (map, faces) {
                    (Some(_), Some(_)) => {
                        return Err(PrismError::scene(&ctx, "give either `map` or `faces`, not both"));
                    }
                    (Some(m), None) => vec![self.base_dir.join(m)],
                    (None, Some(f)) => f.iter().map(|p| self.base_dir.join(p)).collect(),
                    (None, None) => vec![],
                };
                let map = if paths.is_empty() {
                    None
                } else {
                    Some(std::sync::Arc::new(
                        crate::envmap::EnvMap::load(&paths, *layout)
                            .map_err(|e| PrismError::scene(&ctx, e.to_string()))?,
                    ))
                };
                Some(Light::Environment { radiance: color(*radiance, "radiance", &ctx)? * *scale, map })
            }
        };
        match (&light, &e.shape) {
            (Some(Light::Area { .. }), None) => {
                return Err(PrismError::scene(
                    &ctx,
                    "an area light needs a shape (sphere, triangle, quad, cube, mesh, revolution or Bézier patch)",
                ));
            }
            (Some(Light::Point { .. } | Light::Directional { .. } | Light::Environment { .. }), Some(_)) => {
                return Err(PrismError::scene(
                    &ctx,
                    "a point, directional or environment light cannot have a shape; use an Area light or a child entity",
                ));
            }
            _ => {}
        }
        let mut mesh_parts = Vec::new();
        if let Some(shape) = &e.shape {
            match self.shape(shape, &ctx)? {
                ShapeOut::One(s) => {
                    b.add(s);
                }
                ShapeOut::Parts(parts) => mesh_parts = parts,
            }
        }
        if let Some(id) = mat_id {
            b.add(MaterialId(id));
        }
        if let Some(l) = &light
            && mesh_parts.is_empty()
        {
            b.add(l.clone());
        }
        let entity = world.spawn(b.build());
        // A multi-part OBJ: one child entity per part, each with the MTL material unless the entity names one.
        for part in mesh_parts {
            let mut cb = EntityBuilder::new();
            cb.add(Name(format!("{label}/{}", part.name)));
            cb.add(Parent(entity));
            cb.add(part.shape);
            match (mat_id, part.material) {
                (Some(id), _) => cb.add(MaterialId(id)),
                (None, Some(id)) => cb.add(MaterialId(id)),
                (None, None) => &mut cb,
            };
            match (&light, part.emission) {
                (Some(l), _) => {
                    cb.add(l.clone());
                }
                (None, Some(radiance)) => {
                    cb.add(Light::Area { radiance, two_sided: false });
                }
                _ => {}
            }
            world.spawn(cb.build());
        }
        for (i, c) in e.children.iter().enumerate() {
            self.spawn_entity(world, c, Some(entity), material_name, &format!("{path}.children[{i}]"))?;
        }
        Ok(())
    }

    fn shape(&mut self, s: &ShapeDesc, ctx: &str) -> Result<ShapeOut> {
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
                let len = n.length();
                Shape::Plane { normal: n / len, offset: offset / len }
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
                            *o = point(v, "normal", ctx)?
                                .try_normalize()
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
            ShapeDesc::Mesh { path, flat } => {
                let full = self.base_dir.join(path);
                return self.mesh_file(&full, *flat, ctx);
            }
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

    fn mesh_file(&mut self, path: &Path, flat: bool, ctx: &str) -> Result<ShapeOut> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if ext != "obj" {
            return Err(PrismError::scene(
                ctx,
                format!("mesh '{}': unsupported format (expected .obj)", path.display()),
            ));
        }
        if !path.is_file() {
            return Err(PrismError::scene(ctx, format!("mesh file not found: {}", path.display())));
        }
        let key = path.to_path_buf();
        let parts = if let Some(p) = self.part_cache.get(&(key.clone(), flat)) {
            // Referenced before: share the meshes and materials.
            p.clone()
        } else {
            let loaded = load_obj(path)?;
            let mut out = Vec::with_capacity(loaded.len());
            for mut part in loaded {
                if flat {
                    part.mesh.normals.clear();
                }
                let material = part.material.map(|m| {
                    let k = (key.clone(), m.name.clone());
                    *self.mtl_ids.entry(k).or_insert_with(|| {
                        self.res.materials.push(Material { name: format!("{}:{}", path.display(), m.name), ..m });
                        self.res.materials.len() as u32 - 1
                    })
                });
                let name = part.mesh.name.clone();
                let h = self.res.meshes.add(part.mesh);
                out.push(MeshPart { name, shape: Shape::Mesh(h), material, emission: part.emission });
            }
            self.part_cache.insert((key.clone(), flat), out.clone());
            out
        };
        if parts.len() == 1 && parts[0].emission.is_none() && parts[0].material.is_none() {
            return Ok(ShapeOut::One(parts[0].shape.clone()));
        }
        Ok(ShapeOut::Parts(parts))
    }
}

#[derive(Clone)]
struct MeshPart {
    name: String,
    shape: Shape,
    material: Option<u32>,
    emission: Option<Vec3>,
}

enum ShapeOut {
    One(Shape),
    Parts(Vec<MeshPart>),
}

/// A Phong material from `[ambient, diffuse, specular, reflective, transparent]` colours (validated).
#[allow(clippy::too_many_arguments)]
fn phong_material(
    name: &str,
    ctx: &str,
    colors: [V3; 5],
    exponent: f32,
    ior: f32,
    two_sided: bool,
    shading: Shading,
) -> Result<Material> {
    if !(exponent.is_finite() && exponent >= 0.0) {
        return Err(PrismError::scene(ctx, format!("exponent must be >= 0, got {exponent}")));
    }
    let [ambient, diffuse, specular, reflective, transparent] = colors;
    Ok(Material {
        name: name.to_string(),
        ambient: color(ambient, "ambient", ctx)?,
        diffuse: color(diffuse, "diffuse", ctx)?,
        specular: color(specular, "specular", ctx)?,
        exponent,
        reflective: color(reflective, "reflective", ctx)?,
        transparent: color(transparent, "transparent", ctx)?,
        ior: check_ior(ior, ctx)?,
        two_sided,
        shading,
    })
}

fn check_ior(ior: f32, ctx: &str) -> Result<f32> {
    if ior.is_finite() && ior > 0.0 {
        Ok(ior)
    } else {
        Err(PrismError::scene(ctx, format!("ior must be positive, got {ior}")))
    }
}
