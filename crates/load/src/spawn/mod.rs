//! Spawn a parsed RON scene into the ECS world: one entity per scene entity (children get a `Parent`), each with
//! only the components it uses; materials and meshes go to the resource tables. All semantic validation happens
//! here, with errors naming the file and the entity.

mod shape;

use super::material_tables::MaterialEntry;
use super::ron_scene::plugin_config;
use super::schema::{AccelDesc, CameraDesc, EntityDesc, LightDesc, SceneDesc, ShapeDesc, V3};
use super::transform::compose;
use glam::Vec3;
use hecs::{Entity, EntityBuilder, World};
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::material::Material;
use prism_core::sampling::{PixelFilter, PixelPattern, SamplerKind};
use prism_core::settings::{AccelKind, GridResolution, PluginConfig};
use prism_engine::Resources;
use prism_engine::components::{Camera, Light, MaterialId, Name, Parent, Projection, Transform};
use shape::{MeshPart, ShapeOut};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Render settings a scene file asked for (each may be overridden on the command line).
#[derive(Clone, Debug, Default)]
pub struct FileSettings {
    pub integrator: Option<PluginConfig>,
    pub accel: Option<AccelKind>,
    pub spp: Option<u32>,
    pub passes: Option<u32>,
    pub sampler: Option<SamplerKind>,
    pub pattern: Option<PixelPattern>,
    pub filter: Option<PixelFilter>,
    pub adaptive: Option<bool>,
    pub seed: Option<u64>,
    pub time: Option<f64>,
    pub noise: Option<f32>,
    pub exposure: Option<f32>,
    /// Where the file gives each of them (`render` fields by name, and the camera's `size`), so a bad value found
    /// when the settings are resolved is reported at its `file:line:column`.
    pub positions: Vec<(&'static str, SourcePos)>,
}

impl FileSettings {
    /// The file position of field `name` (a `render` field, or `size` for the camera's), if the file gives it.
    pub fn position(&self, name: &str) -> Option<&SourcePos> {
        self.positions.iter().find(|(n, _)| *n == name).map(|(_, p)| p)
    }
}

struct Spawner<'r> {
    file: PathBuf,
    base_dir: PathBuf,
    res: &'r mut Resources,
    materials: HashMap<String, MaterialEntry>,
    textures: HashMap<String, u32>,
    inline_meshes: HashMap<String, prism_engine::components::MeshHandle>,
    mtl_ids: HashMap<(PathBuf, String), u32>,
    part_cache: HashMap<(PathBuf, bool, bool), Vec<MeshPart>>,
    /// No camera yet: the first glTF entity brings its own (or one framing it).
    camera_wanted: bool,
    /// What each placed glTF file stored, so a file placed again stores nothing new.
    gltf_cache: HashMap<PathBuf, crate::gltf::PrimCache>,
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
        textures: HashMap::new(),
        inline_meshes: HashMap::new(),
        mtl_ids: HashMap::new(),
        part_cache: HashMap::new(),
        camera_wanted: desc.camera.is_none(),
        gltf_cache: HashMap::new(),
    };
    let textures = super::material_tables::load_textures(&desc.textures, base_dir, &ctx, sp.res)?;
    sp.materials = super::material_tables::load_materials(&desc.materials, &textures, &ctx, sp.res)?;
    sp.textures = textures;
    sp.inline_meshes = super::inline_mesh::load_meshes(&desc.meshes, &ctx, &mut sp.res.meshes)?;
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
        sampler: r.sampler,
        pattern: r.pattern,
        filter: match r.filter {
            Some(f) => Some(f.validate().map(|_| f).map_err(|e| PrismError::scene(&ctx, format!("render: {e}")))?),
            None => None,
        },
        adaptive: r.adaptive,
        seed: r.seed,
        time: r.time,
        noise: r.noise,
        exposure: r.exposure,
        positions: setting_positions(text, file),
    })
}

/// The positions of the `render` fields and of the camera's `size` in scene text.
fn setting_positions(text: &str, file: &Path) -> Vec<(&'static str, SourcePos)> {
    let render =
        ["integrator", "accel", "grid", "spp", "passes", "sampler", "pattern", "filter", "seed", "time", "noise"];
    let fields = render.iter().chain(&["adaptive", "exposure"]).map(|f| ("render", *f)).chain([("camera", "size")]);
    fields
        .filter_map(|(block, field)| {
            let (line, col) = crate::ron_scene::field_position(text, block, field)?;
            Some((field, SourcePos { file: file.to_path_buf(), line, col }))
        })
        .collect()
}

/// The accelerator a scene's `render: (accel: ..., grid: ...)` asks for; `grid` alone implies the grid.
fn accel_kind(accel: Option<AccelDesc>, grid: Option<[u32; 3]>, ctx: &str) -> Result<Option<AccelKind>> {
    if let Some(r) = grid {
        prism_core::accel::grid::check_resolution(r).map_err(|e| PrismError::scene(ctx, format!("render: {e}")))?;
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
    if eye.abs().max(target.abs()).max_element() > prism_core::limits::MAX_COORDINATE {
        return Err(PrismError::scene(
            ctx,
            format!(
                "eye and target must lie within Prism's coordinate limit of {:e}",
                prism_core::limits::MAX_COORDINATE
            ),
        ));
    }
    let fwd = target - eye;
    let (fwd_unit, up_unit) = (prism_core::math::unit_vector(fwd), prism_core::math::unit_vector(up));
    if fwd_unit.zip(up_unit).is_none_or(|(f, u)| f.cross(u).length_squared() < 1e-12) {
        return Err(PrismError::scene(
            ctx,
            "eye, target and up do not define a view (eye == target or up parallel to the view)",
        ));
    }
    if !(c.aperture_radius.is_finite() && c.aperture_radius >= 0.0) {
        return Err(PrismError::scene(ctx, format!("aperture_radius must be >= 0, got {}", c.aperture_radius)));
    }
    if let Some(w) = c.crop
        && !(w.iter().all(|v| v.is_finite())
            && 0.0 <= w[0]
            && w[0] < w[2]
            && w[2] <= 1.0
            && 0.0 <= w[1]
            && w[1] < w[3]
            && w[3] <= 1.0)
    {
        return Err(PrismError::scene(
            ctx,
            format!("crop must be (x_min, y_min, x_max, y_max) with 0 <= min < max <= 1, got {w:?}"),
        ));
    }
    let focus_distance = c.focus_distance.unwrap_or(fwd.length());
    if !(focus_distance.is_finite() && focus_distance > 0.0) {
        return Err(PrismError::scene(ctx, format!("focus_distance must be positive, got {focus_distance}")));
    }
    Ok(Camera {
        eye,
        target,
        up,
        projection,
        width: c.size.0,
        height: c.size.1,
        aperture_radius: c.aperture_radius,
        focus_distance,
        mirror: c.mirror,
        crop: c.crop,
    })
}

impl Spawner<'_> {
    fn ctx(&self) -> String {
        self.file.display().to_string()
    }

    /// An image texture of `textures` for an area light's emission.
    fn emission_texture(&self, name: &str, ctx: &str) -> Result<prism_core::texture::ImageMap> {
        let id = self
            .textures
            .get(name)
            .ok_or_else(|| PrismError::scene(ctx, format!("area light: unknown texture '{name}'")))?;
        match self.res.textures.get(*id) {
            prism_core::texture::Texture::Image(m) => Ok(m.clone()),
            prism_core::texture::Texture::Solid(_) | prism_core::texture::Texture::UvChecker { .. } => {
                Err(PrismError::scene(ctx, format!("area light: texture '{name}' must be an image")))
            }
        }
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
            None => mat_emission.map(|(radiance, two_sided)| Light::Area { radiance, two_sided, texture: None }),
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
            Some(LightDesc::Spot { intensity, position, direction, target, cone_angle, falloff, profile }) => {
                let position = point(*position, "position", &ctx)?;
                let direction = match (direction, target) {
                    (Some(_), Some(_)) => {
                        return Err(PrismError::scene(&ctx, "spot light: give `direction` or `target`, not both"));
                    }
                    (Some(d), None) => point(*d, "direction", &ctx)?,
                    (None, Some(t)) => point(*t, "target", &ctx)? - position,
                    (None, None) => Vec3::NEG_Y,
                };
                let Some(direction) = prism_core::math::unit_vector(direction) else {
                    return Err(PrismError::scene(
                        &ctx,
                        "spot light direction is the zero vector (target == position)",
                    ));
                };
                if !(cone_angle.is_finite() && *cone_angle > 0.0 && *cone_angle <= 180.0) {
                    return Err(PrismError::scene(
                        &ctx,
                        format!("spot light cone_angle must be in (0, 180] degrees, got {cone_angle}"),
                    ));
                }
                if !(falloff.is_finite() && *falloff >= 0.0 && falloff <= cone_angle) {
                    return Err(PrismError::scene(
                        &ctx,
                        format!("spot light falloff must be in [0, cone_angle = {cone_angle}] degrees, got {falloff}"),
                    ));
                }
                Some(Light::Spot {
                    intensity: color(*intensity, "intensity", &ctx)?,
                    position,
                    direction,
                    cone_angle: *cone_angle,
                    falloff: *falloff,
                    profile: *profile,
                })
            }
            Some(LightDesc::Directional { irradiance, direction }) => {
                let Some(d) = prism_core::math::unit_vector(point(*direction, "direction", &ctx)?) else {
                    return Err(PrismError::scene(&ctx, "directional light direction is the zero vector"));
                };
                Some(Light::Directional { irradiance: color(*irradiance, "irradiance", &ctx)?, direction: d })
            }
            Some(LightDesc::Area { radiance, two_sided, texture }) => {
                let texture = match texture {
                    None => None,
                    Some(name) => Some(self.emission_texture(name, &ctx)?),
                };
                Some(Light::Area { radiance: color(*radiance, "radiance", &ctx)?, two_sided: *two_sided, texture })
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
                self.res.inputs.extend(paths.iter().cloned());
                let radiance = color(*radiance, "radiance", &ctx)? * *scale;
                Some(environment_light(&paths, *layout, radiance).map_err(|e| PrismError::scene(&ctx, e.to_string()))?)
            }
        };
        match (&light, &e.shape) {
            (Some(Light::Area { .. }), None) => {
                return Err(PrismError::scene(
                    &ctx,
                    "an area light needs a shape (sphere, triangle, quad, cube, mesh, revolution or Bézier patch)",
                ));
            }
            (
                Some(Light::Point { .. } | Light::Spot { .. } | Light::Directional { .. } | Light::Environment { .. }),
                Some(_),
            ) => {
                return Err(PrismError::scene(
                    &ctx,
                    "a point, spot, directional or environment light cannot have a shape; use an Area light or a child entity",
                ));
            }
            _ => {}
        }
        let gltf = match &e.shape {
            Some(ShapeDesc::Gltf { path, scene, materials }) => Some((path, *scene, Some(materials))),
            Some(ShapeDesc::Mesh { path, flat, reverse }) if is_gltf_path(path) => {
                if *flat || *reverse {
                    return Err(PrismError::scene(&ctx, "`flat` and `reverse` apply to OBJ and PLY meshes, not glTF"));
                }
                Some((path, None, None))
            }
            _ => None,
        };
        if gltf.is_some() && (e.light.is_some() || e.alpha.is_some()) {
            return Err(PrismError::scene(
                &ctx,
                "a glTF entity carries no light or alpha of its own (its emissive materials are its lights)",
            ));
        }
        let mut mesh_parts = Vec::new();
        if let Some(shape) = e.shape.as_ref().filter(|_| gltf.is_none()) {
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
        let alpha = match &e.alpha {
            Some(a) => Some(super::inline_mesh::alpha_mask(a, &self.textures, &self.res.textures, &ctx)?),
            None => None,
        };
        if let Some(a) = &alpha
            && mesh_parts.is_empty()
        {
            b.add(a.clone());
        }
        if let Some(l) = &light
            && mesh_parts.is_empty()
        {
            b.add(l.clone());
        }
        let entity = world.spawn(b.build());
        if let Some((path, scene, overrides)) = gltf {
            self.place_gltf(world, entity, path, scene, overrides, e.material.as_deref(), &ctx)?;
        }
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
            if let Some(a) = &alpha {
                cb.add(a.clone());
            }
            match (&light, part.emission) {
                (Some(l), _) => {
                    cb.add(l.clone());
                }
                (None, Some(radiance)) => {
                    cb.add(Light::Area { radiance, two_sided: false, texture: None });
                }
                _ => {}
            }
            world.spawn(cb.build());
        }
        for (i, c) in e.children.iter().enumerate() {
            self.spawn_entity(world, c, Some(entity), material_name, &child_path(path, i))?;
        }
        Ok(())
    }
}

/// A `.gltf` or `.glb` path.
fn is_gltf_path(path: &str) -> bool {
    let ext = Path::new(path).extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    ext == "gltf" || ext == "glb"
}

impl Spawner<'_> {
    /// A glTF file's scene nested under `entity`: glTF materials replaced by name (`overrides`), or all of them
    /// by the entity's `material`.
    #[allow(clippy::too_many_arguments)]
    fn place_gltf(
        &mut self,
        world: &mut World,
        entity: Entity,
        path: &str,
        scene: Option<usize>,
        overrides: Option<&std::collections::BTreeMap<String, String>>,
        material: Option<&str>,
        ctx: &str,
    ) -> Result<()> {
        let as_override = |m: &MaterialEntry| crate::gltf::MaterialOverride { id: m.id, emission: m.emission };
        let mut materials = HashMap::new();
        for (gltf_name, ron_name) in overrides.into_iter().flatten() {
            materials.insert(gltf_name.clone(), as_override(self.lookup_material(ron_name, ctx)?));
        }
        let all = material.map(|m| self.lookup_material(m, ctx).map(as_override)).transpose()?;
        let placement = crate::gltf::Placement {
            parent: Some(entity),
            scene,
            materials,
            all,
            camera: std::mem::take(&mut self.camera_wanted),
            default_light: false,
        };
        let full = self.base_dir.join(path);
        self.res.inputs.push(full.clone());
        let cache = self.gltf_cache.entry(full.clone()).or_default();
        crate::gltf::place_gltf(&full, world, self.res, &placement, cache)
            .map_err(|e| PrismError::scene(ctx, e.to_string()))?;
        Ok(())
    }
}

/// The label of an unnamed child: `entities[0].children[2]`; deep paths keep their start and the nesting level
/// (`entities[0].children[0]....children[2] (level 5000)`) so labels stay short at any depth.
fn child_path(path: &str, i: usize) -> String {
    const KEEP: usize = 120;
    let level = match path.rfind(" (level ") {
        Some(at) => path[at + 8..].trim_end_matches(')').parse::<usize>().unwrap_or(0) + 1,
        None => path.matches(".children[").count() + 1,
    };
    if path.len() < KEEP {
        return format!("{path}.children[{i}]");
    }
    let head: String = path.chars().take(KEEP / 2).collect();
    let head = head.rsplit_once(".children[").map_or(head.as_str(), |(h, _)| h).to_string();
    format!("{head}....children[{i}] (level {level})")
}

/// An environment light of `radiance` (times the map of `paths`, if any: one file in any layout, or six faces).
/// Errors when the map cannot be read, or when its brightest texel times `radiance` overflows single precision.
pub(crate) fn environment_light(
    paths: &[PathBuf],
    layout: Option<prism_core::envmap::SourceLayout>,
    radiance: glam::Vec3,
) -> Result<Light> {
    let map = if paths.is_empty() {
        None
    } else {
        Some(std::sync::Arc::new(prism_core::envmap::EnvMap::load(paths, layout)?))
    };
    // The brightest texel times radiance and scale must stay finite (power and sampling sum them).
    let peak = map
        .as_ref()
        .map_or(1.0, |m| m.images.iter().flat_map(|i| &i.texels).fold(0.0f32, |a, t| a.max(t.max_element())));
    if !(radiance * peak * 4.0 * std::f32::consts::PI).is_finite() {
        return Err(PrismError::invalid(format!(
            "environment radiance x scale ({radiance}) times the map's brightest texel ({peak}) overflows single \
             precision"
        )));
    }
    Ok(Light::Environment { radiance, map })
}
