//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, `.glb`) through the `gltf` crate's document
//! model; buffers, images and accessors are read by `data.rs` with every range checked.
//!
//! - The default scene's node hierarchy becomes nested entities (`Transform` from the node's matrix or TRS,
//!   `Parent`); each primitive of a node's mesh is a child entity with its `Shape::Mesh`, material, emission
//!   and alpha. A mesh used by several nodes is read once: its `MeshData` is stored once in the mesh table and
//!   every node refers to it (the world-space triangles the accelerator holds are still made per use; see
//!   `docs/guide/import-gltf.md` on instancing).
//! - Primitives: triangles (strips and fans are converted; points and lines are left out with a warning),
//!   indices, POSITION, NORMAL (flat shading without), TEXCOORD_0/1, TANGENT (MikkTSpace by the specification;
//!   generated with MikkTSpace when absent and a normal map needs them).
//! - Cameras: perspective (`yfov`, `aspectRatio`) and orthographic (`ymag`, `xmag`), looking down the node's -z;
//!   `--camera NAME|INDEX` picks one by camera or node name, or by its index in node order, default the first.
//!   Without a camera, one looks from the model's front (+z), right and above (direction (0.5, 0.4, 1)) at the
//!   bounding sphere of what is drawn, leaving out planar parts (grounds, backdrops) more than 3 times the size
//!   of the rest; 512 x 512. Images of a file's cameras are 480 pixels tall (the aspect ratio's width; 640
//!   without one).
//! - `KHR_lights_punctual`: photometric to radiometric with the luminous efficacy 683 lm/W (the candela's SI
//!   definition, and what Blender's exporter multiplies watts by): point and spot `intensity` (cd) x colour / 683
//!   = W/sr, directional (lux) / 683 = W/m^2; spot cones: `cone_angle` = outer, `falloff` = outer - inner, glTF's
//!   squared linear fall-off; `range` is ignored (inverse square everywhere, reported). Emission (`material.rs`)
//!   is taken as radiance 1:1, as viewers and Blender do.
//! - No light, or only emissive surfaces: a note, and a uniform white environment of radiance 1, so a bare model
//!   still renders (not with `--no-default-light`, `--env` or `--sky`).
//! - Skins, morph targets and animations are ignored with one warning each; an unknown *required* extension is
//!   an error naming it.

mod cameras;
mod data;
mod ktx2_image;
mod material;
mod to_ron;

pub use ktx2_image::{Ktx2, decode as decode_ktx2};
pub use to_ron::gltf_to_ron;

use crate::FileSettings;
use cameras::PartBound;
use data::{Buffers, read_accessor};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::DataType;
use hecs::{Entity, EntityBuilder, World};
use prism_core::alpha::AlphaMask;
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::lights::SpotProfile;
use prism_core::mesh::MeshData;
use prism_core::settings::PluginConfig;
use prism_engine::Resources;
use prism_engine::components::{Camera, Light, MaterialId, MeshHandle, Name, Parent, Shape, Transform};
use std::collections::{BTreeSet, HashMap};
use std::path::Path;

/// Luminous efficacy used to turn lumens into watts (lm/W).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Extensions Prism reads (an unknown one in `extensionsRequired` is an error).
const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_texture_transform",
];

struct Loader<'a> {
    file: &'a Path,
    buffers: &'a Buffers,
    mats: material::Materials<'a>,
    /// (mesh, primitive) -> the stored mesh and its resolved material.
    prim_cache: &'a mut PrimCache,
    warnings: BTreeSet<String>,
    cameras: Vec<(String, String, Camera, Entity)>,
    lights: usize,
    emitters: usize,
    /// World bounds of every primitive drawn, for the automatic camera.
    parts: Vec<PartBound>,
    placement: &'a Placement,
}

/// The primitives of one glTF file already stored (meshes, resolved materials), by (mesh, primitive) index: a
/// file placed several times in a scene stores its meshes and materials once.
#[derive(Default)]
pub struct PrimCache(HashMap<(usize, usize), Option<(MeshHandle, material::Resolved)>>);

/// A material that replaces a glTF material: its index in the scene's materials and its emission (radiance,
/// two-sided), if it emits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialOverride {
    /// Index in `Resources::materials`.
    pub id: u32,
    /// The emission of the material, which becomes an area light on the primitive.
    pub emission: Option<(Vec3, bool)>,
}

/// How a glTF file enters a scene: on its own (`prism render model.glb`: its camera, or one framing it, and the
/// default sky when it has no light), or under an entity of a RON scene (`Gltf(path, ...)`).
#[derive(Clone, Debug, Default)]
pub struct Placement {
    /// The entity the file's root nodes (and its cameras) are nested under.
    pub parent: Option<Entity>,
    /// The glTF scene to place, by index (default: the file's default scene, else the first).
    pub scene: Option<usize>,
    /// Materials replacing the glTF materials of these names.
    pub materials: HashMap<String, MaterialOverride>,
    /// A material replacing every glTF material not in `materials`.
    pub all: Option<MaterialOverride>,
    /// Spawn a camera: the one `--camera` picks, the first, or one framing the model.
    pub camera: bool,
    /// Add the default sky when the file has no light (subject to `--no-default-light`, `--env`, `--sky`).
    pub default_light: bool,
}

impl Placement {
    /// A file rendered on its own.
    pub fn standalone() -> Self {
        Placement { camera: true, default_light: true, ..Placement::default() }
    }
}

/// Load a glTF file into the world as the whole scene.
pub fn load_gltf(path: &Path, world: &mut World, res: &mut Resources) -> Result<FileSettings> {
    place_gltf(path, world, res, &Placement::standalone(), &mut PrimCache::default())
}

/// Place a glTF file in the world as `placement` says; `cache` holds what earlier placements of the same file
/// stored (start with an empty one per file).
pub fn place_gltf(
    path: &Path,
    world: &mut World,
    res: &mut Resources,
    placement: &Placement,
    cache: &mut PrimCache,
) -> Result<FileSettings> {
    let bytes = prism_core::io::read_regular(path, "glTF file")?;
    place_gltf_bytes(&bytes, path, Some(path.parent().unwrap_or(Path::new("."))), world, res, placement, cache)
}

/// Load glTF JSON or GLB bytes into the world as the whole scene; `path` names them in messages. External
/// buffers and images resolve against `base`; with `None` they resolve to nothing (an error when the scene needs
/// one).
pub fn load_gltf_bytes(
    bytes: &[u8],
    path: &Path,
    base: Option<&Path>,
    world: &mut World,
    res: &mut Resources,
) -> Result<FileSettings> {
    place_gltf_bytes(bytes, path, base, world, res, &Placement::standalone(), &mut PrimCache::default())
}

/// [`load_gltf_bytes`] as `placement` says, reusing what `cache` holds of the same file.
pub fn place_gltf_bytes(
    bytes: &[u8],
    path: &Path,
    base: Option<&Path>,
    world: &mut World,
    res: &mut Resources,
    placement: &Placement,
    cache: &mut PrimCache,
) -> Result<FileSettings> {
    // A GLB header whose total length is below the header's own 12 bytes makes the gltf crate subtract with
    // overflow (a panic with overflow checks; fuzzing).
    if bytes.starts_with(b"glTF") && bytes.len() >= 12 {
        let stated = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as u64;
        if stated < 12 {
            return Err(PrismError::format(
                path,
                "GLB header: the file length it states is below the header's 12 bytes",
            ));
        }
        if stated != bytes.len() as u64 {
            return Err(PrismError::format(
                path,
                format!(
                    "GLB header: the file length it states ({stated} bytes) is not the file's ({} bytes)",
                    bytes.len()
                ),
            ));
        }
    }
    let g = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| gltf_error(e, path))?;
    let doc = g.document;
    for ext in doc.extensions_required() {
        if !SUPPORTED.contains(&ext) {
            return Err(PrismError::format(
                path,
                format!("requires the glTF extension {ext}, which Prism does not support"),
            ));
        }
    }
    let json = doc.clone().into_json();
    check_before_validation(&json, path)?;
    let validated = gltf::Document::from_json(json).map_err(|e| gltf_error(e, path))?;
    if let Some(base) = base {
        res.inputs.extend(data::external_files(&validated, base));
    }
    let buffers = Buffers::load(&validated, g.blob, base, path)?;
    let mut l = Loader {
        file: path,
        buffers: &buffers,
        mats: material::Materials::new(path, base, &buffers),
        prim_cache: cache,
        warnings: BTreeSet::new(),
        cameras: Vec::new(),
        lights: 0,
        emitters: 0,
        parts: Vec::new(),
        placement,
    };
    // An override naming no material of the file is a typo: say which names there are.
    for name in placement.materials.keys() {
        if !validated.materials().any(|m| m.name() == Some(name.as_str())) {
            let mut names: Vec<&str> = validated.materials().filter_map(|m| m.name()).collect();
            names.sort_unstable();
            return Err(PrismError::format(
                path,
                format!(
                    "no material named '{name}' to override (materials: {})",
                    if names.is_empty() { "none with a name".into() } else { names.join(", ") }
                ),
            ));
        }
    }
    for ext in validated.extensions_used() {
        if !SUPPORTED.contains(&ext) {
            l.warnings.insert(format!("extension {ext} is ignored"));
        }
    }
    if validated.animations().count() > 0 {
        l.warnings
            .insert(format!("{} animation(s) ignored: the scene is rendered at rest", validated.animations().count()));
    }
    if validated.skins().count() > 0 {
        l.warnings.insert(format!(
            "{} skin(s) ignored: skinned meshes are rendered in their bind pose",
            validated.skins().count()
        ));
    }
    let scene = match placement.scene {
        Some(i) => Some(validated.scenes().nth(i).ok_or_else(|| {
            PrismError::format(path, format!("no scene {i} (the file has {})", validated.scenes().count()))
        })?),
        None => validated.default_scene().or_else(|| validated.scenes().next()),
    };
    if let Some(scene) = scene {
        for node in scene.nodes() {
            l.node(&node, placement.parent, Mat4::IDENTITY, world, res, 0)?;
        }
    } else {
        l.warnings.insert("the file has no scene: nothing to render".into());
    }
    if placement.camera {
        let want = res.overrides.camera.clone();
        l.spawn_camera(world, want.as_deref())?;
    }
    // Emissive surfaces alone (decals, screens) rarely light a model: the sky is added then too.
    if placement.default_light && l.lights == 0 && crate::scene_overrides::default_light_allowed(&res.overrides) {
        let what = if l.emitters == 0 { "no lights" } else { "no lights but emissive surfaces" };
        eprintln!(
            "note: {}: the scene has {what}; it is lit by a uniform white environment of radiance 1 \
             (--no-default-light leaves it out, --env or --sky sets another)",
            path.display()
        );
        world.spawn((Name("default environment".into()), Light::Environment { radiance: Vec3::ONE, map: None }));
    }
    for w in l.warnings.iter().chain(l.mats.warnings.iter()) {
        eprintln!("warning: {}: {w}", path.display());
    }
    Ok(FileSettings { integrator: Some(PluginConfig::from_spec("envlight")?), ..FileSettings::default() })
}

/// A `gltf` crate error as a one-line Prism error (JSON errors with line and column).
fn gltf_error(e: gltf::Error, path: &Path) -> PrismError {
    match e {
        gltf::Error::Deserialize(j) => PrismError::Parse {
            pos: SourcePos { file: path.to_path_buf(), line: j.line(), col: j.column() },
            message: format!("invalid glTF JSON: {j}"),
        },
        gltf::Error::Validation(list) => {
            let first: Vec<String> = list.iter().take(3).map(|(p, e)| format!("{}: {e}", p.as_str())).collect();
            let more = if list.len() > 3 { format!(" (and {} more)", list.len() - 3) } else { String::new() };
            PrismError::format(path, format!("invalid glTF: {}{more}", first.join("; ")))
        }
        gltf::Error::Binary(b) => PrismError::format(path, format!("invalid GLB (truncated or corrupt): {b}")),
        other => PrismError::format(path, format!("cannot read glTF: {other}")),
    }
}

/// Most node instances a glTF scene may expand to (a node shared by several parents counts once per path).
pub const MAX_NODE_INSTANCES: u64 = 1 << 20;
/// Most bytes the accessors without a buffer view may decode to, together.
pub const MAX_UNBACKED_ACCESSOR_BYTES: u64 = 256 << 20;

fn node_label(n: &gltf::Node) -> String {
    match n.name() {
        Some(s) => format!("node {} '{s}'", n.index()),
        None => format!("node {}", n.index()),
    }
}

impl Loader<'_> {
    fn err(&self, m: String) -> PrismError {
        PrismError::format(self.file, m)
    }

    fn node(
        &mut self,
        n: &gltf::Node,
        parent: Option<Entity>,
        parent_m: Mat4,
        world: &mut World,
        res: &mut Resources,
        depth: usize,
    ) -> Result<()> {
        let label = node_label(n);
        if depth > 256 {
            return Err(self.err(format!("{label}: nodes nested more than 256 deep (a cycle?)")));
        }
        let local = Mat4::from_cols_array_2d(&n.transform().matrix());
        if !local.is_finite() {
            return Err(self.err(format!("{label}: the transform is not finite")));
        }
        if local.row(3) != glam::Vec4::W {
            return Err(self.err(format!(
                "{label}: the matrix's bottom row is {:?}, not [0, 0, 0, 1] (glTF node matrices are affine)",
                local.row(3).to_array()
            )));
        }
        if local.determinant() == 0.0 {
            self.warnings.insert(format!("{label}: a transform with zero scale hides the node and its children"));
            return Ok(());
        }
        let m = parent_m * local;
        let mut b = EntityBuilder::new();
        b.add(Name(n.name().map_or_else(|| label.clone(), str::to_string)));
        b.add(Transform(Affine3A::from_mat4(local)));
        if let Some(p) = parent {
            b.add(Parent(p));
        }
        let e = world.spawn(b.build());
        if let Some(mesh) = n.mesh() {
            if n.weights().is_some() || mesh.primitives().any(|p| p.morph_targets().next().is_some()) {
                self.warnings.insert("morph targets ignored: meshes are rendered with their base shape".into());
            }
            for prim in mesh.primitives() {
                let Some((h, mut mat)) = self.primitive(&mesh, &prim, res)? else { continue };
                let name = prim.material().name().unwrap_or("");
                if let Some(o) = self.placement.materials.get(name).or(self.placement.all.as_ref()) {
                    mat.id = o.id;
                    mat.emission = o.emission.map(|(radiance, two_sided)| (radiance, two_sided, None));
                }
                self.parts.push(PartBound::of(&res.meshes.get(h).positions, &m));
                let mut cb = EntityBuilder::new();
                cb.add(Name(format!(
                    "{}/{}#{}",
                    n.name().unwrap_or(&label),
                    mesh.name().unwrap_or("mesh"),
                    prim.index()
                )));
                cb.add(Parent(e));
                cb.add(Shape::Mesh(h));
                cb.add(MaterialId(mat.id));
                if let Some((radiance, two_sided, texture)) = &mat.emission {
                    cb.add(Light::Area { radiance: *radiance, two_sided: *two_sided, texture: texture.clone() });
                    self.emitters += 1;
                }
                if let Some(a) = &mat.alpha {
                    cb.add::<AlphaMask>(a.clone());
                }
                world.spawn(cb.build());
            }
        }
        if let Some(cam) = n.camera() {
            let c = self.camera(&cam, &label)?;
            let ce = world.spawn((Name(format!("{label} camera")), Parent(e)));
            self.cameras.push((cam.name().unwrap_or("").to_string(), n.name().unwrap_or("").to_string(), c, ce));
        }
        if let Some(light) = n.light() {
            let l = self.light(&light, &label)?;
            world.spawn((Name(format!("{label} light")), Parent(e), l));
            self.lights += 1;
        }
        for c in n.children() {
            self.node(&c, Some(e), m, world, res, depth + 1)?;
        }
        Ok(())
    }

    fn light(&mut self, light: &gltf::khr_lights_punctual::Light, label: &str) -> Result<Light> {
        let color = Vec3::from(light.color());
        let i = light.intensity();
        if !(color.is_finite() && color.min_element() >= 0.0 && i.is_finite() && i >= 0.0) {
            return Err(self.err(format!("{label}: light colour and intensity must be finite and non-negative")));
        }
        if light.range().is_some() {
            self.warnings.insert("light range is ignored (lights fall off with the inverse square everywhere)".into());
        }
        let power = color * (i / LUMENS_PER_WATT);
        Ok(match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => {
                Light::Point { intensity: power, position: Vec3::ZERO, attenuation: Vec3::Z }
            }
            gltf::khr_lights_punctual::Kind::Directional => {
                Light::Directional { irradiance: power, direction: Vec3::NEG_Z }
            }
            gltf::khr_lights_punctual::Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                let (inner, outer) = (inner_cone_angle.to_degrees(), outer_cone_angle.to_degrees());
                if !(outer > 0.0 && outer <= 90.0 + 1e-3 && inner >= 0.0 && inner <= outer) {
                    return Err(self.err(format!("{label}: spot cone angles must satisfy 0 <= inner <= outer <= pi/2, got {inner_cone_angle} and {outer_cone_angle}")));
                }
                Light::Spot {
                    intensity: power,
                    position: Vec3::ZERO,
                    direction: Vec3::NEG_Z,
                    cone_angle: outer.min(90.0),
                    falloff: outer.min(90.0) - inner,
                    profile: SpotProfile::Gltf,
                }
            }
        })
    }

    /// A primitive as a stored mesh with its material; `None` for primitives Prism leaves out.
    fn primitive(
        &mut self,
        mesh: &gltf::Mesh,
        prim: &gltf::Primitive,
        res: &mut Resources,
    ) -> Result<Option<(MeshHandle, material::Resolved)>> {
        let key = (mesh.index(), prim.index());
        if let Some(c) = self.prim_cache.0.get(&key) {
            return Ok(c.clone());
        }
        let what = format!(
            "mesh {}{} primitive {}",
            mesh.index(),
            mesh.name().map_or(String::new(), |n| format!(" '{n}'")),
            prim.index()
        );
        let out = self.read_primitive(prim, &what, res)?;
        self.prim_cache.0.insert(key, out.clone());
        Ok(out)
    }

    fn read_primitive(
        &mut self,
        prim: &gltf::Primitive,
        what: &str,
        res: &mut Resources,
    ) -> Result<Option<(MeshHandle, material::Resolved)>> {
        use gltf::mesh::{Mode, Semantic};
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.warnings.insert(format!("{what}: {mode:?} primitives are not surfaces and are left out"));
            return Ok(None);
        }
        let mat = self.mats.resolve(&prim.material(), res)?;
        let f32_only: &[(DataType, bool)] = &[(DataType::F32, false)];
        let pos_acc =
            prim.get(&Semantic::Positions).ok_or_else(|| self.err(format!("{what}: no POSITION attribute")))?;
        let p = read_accessor(&pos_acc, self.buffers, 3, f32_only, &format!("{what} POSITION"), self.file)?;
        let positions: Vec<Vec3> =
            p.chunks_exact(3).map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)).collect();
        if let Some(i) = positions.iter().position(|v| !v.is_finite()) {
            return Err(self.err(format!("{what}: vertex {i} has a NaN or infinite position {:?}", positions[i])));
        }
        let n = positions.len();
        let same_count = |v: usize, attr: &str| -> Result<()> {
            if v == n {
                Ok(())
            } else {
                Err(PrismError::format(self.file, format!("{what}: {attr} has {v} elements for {n} positions")))
            }
        };
        let normals: Vec<Vec3> = match prim.get(&Semantic::Normals) {
            Some(a) => {
                let v = read_accessor(&a, self.buffers, 3, f32_only, &format!("{what} NORMAL"), self.file)?;
                same_count(v.len() / 3, "NORMAL")?;
                v.chunks_exact(3)
                    .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
                    .map(|v| if v.is_finite() { v } else { Vec3::ZERO })
                    .collect()
            }
            None => vec![],
        };
        let uv_ok: &[(DataType, bool)] = &[(DataType::F32, false), (DataType::U8, true), (DataType::U16, true)];
        let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(mat.uv_set)) {
            Some(a) => {
                let v =
                    read_accessor(&a, self.buffers, 2, uv_ok, &format!("{what} TEXCOORD_{}", mat.uv_set), self.file)?;
                same_count(v.len() / 2, "TEXCOORD")?;
                v.chunks_exact(2)
                    .map(|c| Vec2::new(c[0] as f32, c[1] as f32))
                    .map(|v| if v.is_finite() { v } else { Vec2::ZERO })
                    .collect()
            }
            None => vec![],
        };
        let tangents: Vec<Vec4> = match prim.get(&Semantic::Tangents) {
            Some(a) if mat.normal_mapped => {
                let v = read_accessor(&a, self.buffers, 4, f32_only, &format!("{what} TANGENT"), self.file)?;
                same_count(v.len() / 4, "TANGENT")?;
                // glTF's bitangent (w cross(n, t)) points up the image; Prism's along increasing v, down it.
                v.chunks_exact(4)
                    .map(|c| Vec4::new(c[0] as f32, c[1] as f32, c[2] as f32, if c[3] < 0.0 { 1.0 } else { -1.0 }))
                    .collect()
            }
            _ => vec![],
        };
        if prim.get(&Semantic::Colors(0)).is_some() {
            self.warnings.insert("vertex colours (COLOR_0) are ignored".into());
        }
        let idx: Vec<u32> = match prim.indices() {
            Some(a) => {
                let ok: &[(DataType, bool)] = &[(DataType::U8, false), (DataType::U16, false), (DataType::U32, false)];
                let v = read_accessor(&a, self.buffers, 1, ok, &format!("{what} indices"), self.file)?;
                let mut out = Vec::with_capacity(v.len());
                for (k, x) in v.into_iter().enumerate() {
                    if x as usize >= n {
                        return Err(self.err(format!("{what}: index {k} is {x}, but there are only {n} vertices")));
                    }
                    out.push(x as u32);
                }
                out
            }
            None => (0..n as u32).collect(),
        };
        let indices: Vec<[u32; 3]> = match mode {
            Mode::TriangleStrip => (2..idx.len())
                .map(|i| if i % 2 == 0 { [idx[i - 2], idx[i - 1], idx[i]] } else { [idx[i - 1], idx[i - 2], idx[i]] })
                .collect(),
            Mode::TriangleFan => (2..idx.len()).map(|i| [idx[0], idx[i - 1], idx[i]]).collect(),
            _ => {
                if !idx.len().is_multiple_of(3) {
                    return Err(self.err(format!("{what}: {} indices is not a multiple of 3", idx.len())));
                }
                idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
        };
        if indices.is_empty() {
            self.warnings.insert(format!("{what}: no triangles"));
            return Ok(None);
        }
        let md = MeshData { name: what.to_string(), positions, normals, uvs, indices, tangents };
        Ok(Some((res.meshes.add(md), mat)))
    }
}

/// What the `gltf` crate (1.4) assumes without checking, found by fuzzing: its validation reads each primitive's
/// POSITION accessor by index (a panic when out of range), and `Image::source` unwraps a `mimeType` for images in
/// a buffer view and a `uri` otherwise. Checked here first, as one-line errors.
fn check_before_validation(json: &gltf::json::Root, path: &Path) -> Result<()> {
    for (i, img) in json.images.iter().enumerate() {
        let problem = match (&img.buffer_view, &img.uri, &img.mime_type) {
            (Some(_), _, None) => Some("is stored in a buffer view but has no mimeType"),
            (None, None, _) => Some("has neither a uri nor a bufferView"),
            _ => None,
        };
        if let Some(p) = problem {
            return Err(PrismError::format(path, format!("image {i} {p}")));
        }
    }
    check_accessor_sizes(json, path)?;
    check_node_instances(json, path)?;
    let n = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (k, prim) in mesh.primitives.iter().enumerate() {
            let bad = prim.attributes.values().chain(prim.indices.iter()).find(|i| i.value() >= n);
            if let Some(i) = bad {
                return Err(PrismError::format(
                    path,
                    format!("mesh {m} primitive {k} names accessor {} but the file has {n} accessors", i.value()),
                ));
            }
        }
    }
    Ok(())
}

/// Bytes of the accessors that no buffer view backs (sparse ones without a base, which decode to zeros plus their
/// sparse values): what a small file can make the reader allocate. Accessors backed by a buffer view are bounded
/// by the buffers, which are read whole and checked for size.
fn check_accessor_sizes(json: &gltf::json::Root, path: &Path) -> Result<()> {
    let mut unbacked: u64 = 0;
    for (i, a) in json.accessors.iter().enumerate() {
        use gltf::json::validation::Checked;
        let (Checked::Valid(t), Checked::Valid(c)) = (&a.type_, &a.component_type) else { continue };
        let (components, size) = (t.multiplicity() as u64, c.0.size() as u64);
        let bytes = a.count.0.saturating_mul(components).saturating_mul(size);
        if a.buffer_view.is_none() {
            unbacked = unbacked.saturating_add(bytes);
        }
        if unbacked > MAX_UNBACKED_ACCESSOR_BYTES {
            return Err(PrismError::format(
                path,
                format!(
                    "accessor {i}: accessors without a buffer view would decode to {unbacked} bytes, more than Prism \
                     reads ({MAX_UNBACKED_ACCESSOR_BYTES})"
                ),
            ));
        }
    }
    Ok(())
}

/// The node instances the default scene expands to: a node listed under several parents (or several times under
/// one) is instanced once per path from a root, so a small file of shared nodes can describe exponentially many.
/// Counted before anything is spawned.
fn check_node_instances(json: &gltf::json::Root, path: &Path) -> Result<()> {
    fn count(json: &gltf::json::Root, node: usize, depth: usize, memo: &mut HashMap<usize, u64>) -> u64 {
        if let Some(&c) = memo.get(&node) {
            return c;
        }
        // Deeper than the loader nests is an error there (a cycle, most likely); count it as one.
        let Some(n) = json.nodes.get(node).filter(|_| depth <= 256) else { return 1 };
        let mut c: u64 = 1;
        for child in n.children.iter().flatten() {
            c = c.saturating_add(count(json, child.value(), depth + 1, memo));
        }
        memo.insert(node, c);
        c
    }
    let scene = json.scene.map(|s| s.value()).unwrap_or(0);
    let Some(roots) = json.scenes.get(scene) else { return Ok(()) };
    let mut memo = HashMap::new();
    let total = roots.nodes.iter().fold(0u64, |t, r| t.saturating_add(count(json, r.value(), 0, &mut memo)));
    if total > MAX_NODE_INSTANCES {
        return Err(PrismError::format(
            path,
            format!(
                "the scene's node graph expands to {total} node instances (nodes listed under several parents), \
                 more than Prism instances ({MAX_NODE_INSTANCES})"
            ),
        ));
    }
    Ok(())
}
