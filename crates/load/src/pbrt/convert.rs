//! The pbrt directive stream, interpreted with pbrt's graphics state (current transform, material, area light,
//! reverse orientation; `AttributeBegin`/`End` and `TransformBegin`/`End` scopes; named coordinate systems;
//! object definitions and instances; included files) and written as a Prism RON scene. The scene-wide
//! directives (camera, film, sampler, integrator) are in `scene_wide.rs`, shapes in `shapes.rs`, lights in
//! `lights.rs`, materials and textures in `materials.rs`.

use super::Version;
use super::lexer::{Tok, Token, bracketed_nums, nums, string, tokenize};
use super::params::{Params, parse_params};
use super::scene_wide::SceneWide;
use glam::{DMat4, DVec3};
use prism_core::error::{PrismError, Result, SourcePos};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A number for RON (finite by construction of every caller).
pub fn num(v: f64) -> String {
    let f = v as f32;
    if f.is_finite() { format!("{f:?}") } else { "0.0".into() }
}

pub fn tuple3(v: [f64; 3]) -> String {
    format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]))
}

/// A RON string literal.
pub fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A `Matrix(...)` transform op of a 4x4 matrix.
pub fn matrix_op(m: &DMat4) -> String {
    let r = |i: usize| {
        let row = m.row(i);
        format!("({}, {}, {}, {})", num(row.x), num(row.y), num(row.z), num(row.w))
    };
    format!(
        "Matrix(({}, {}, {}, {}))",
        r(0),
        r(1),
        r(2),
        if m.row(3) == glam::DVec4::W { "(0, 0, 0, 1)".into() } else { r(3) }
    )
}

/// The area light of the current attribute scope.
#[derive(Clone, Debug)]
pub struct AreaSpec {
    pub radiance: [f64; 3],
    pub two_sided: bool,
    pub texture: Option<String>,
}

/// What `AttributeBegin` saves and `AttributeEnd` restores (`TransformBegin` saves only the transform).
#[derive(Clone, Debug)]
struct GState {
    ctm: DMat4,
    reverse: bool,
    material: String,
    area: Option<AreaSpec>,
    /// True for a `TransformBegin` scope.
    transform_only: bool,
    pos: SourcePos,
}

/// The converter: graphics state plus the RON being written.
pub struct Converter {
    pub version: Version,
    /// Relative paths in the scene resolve against this directory (the main file's, as pbrt does).
    pub search_dir: PathBuf,
    /// Paths are written relative to this directory (where the RON scene lives).
    pub ron_dir: PathBuf,
    /// Whether files the scene names are read (`Include`, `.spd` spectra, PLY headers); false for scene text
    /// converted in memory (fuzzing), where such files are reported missing.
    pub read_files: bool,
    pub warnings: BTreeSet<String>,
    pub ctm: DMat4,
    pub reverse: bool,
    /// RON name of the current material.
    pub material: String,
    pub area: Option<AreaSpec>,
    stack: Vec<GState>,
    named_coords: HashMap<String, DMat4>,
    pub in_world: bool,
    pub wide: SceneWide,
    /// RON text of the textures, materials and meshes tables, by RON name.
    pub textures: BTreeMap<String, String>,
    pub materials: BTreeMap<String, String>,
    pub meshes: BTreeMap<String, String>,
    /// Texture values by (kind, pbrt name) (see `materials.rs`).
    pub tex_values: HashMap<(bool, String), super::materials::TexValue>,
    /// pbrt named materials -> RON name.
    pub named_materials: HashMap<String, String>,
    /// Material RON text -> RON name (identical anonymous materials are shared).
    pub material_dedupe: HashMap<String, String>,
    pub entities: Vec<String>,
    objects: HashMap<String, Vec<String>>,
    current_object: Option<(String, Vec<String>)>,
    pub environment: Option<super::lights::EnvSpec>,
    pub counter: usize,
    include_depth: usize,
    /// Files included so far (every `Include` and `Import`, nested ones too).
    includes: usize,
    /// Every file read besides the main one (included files, spectra), for the scene's inputs.
    pub files_read: std::cell::RefCell<Vec<std::path::PathBuf>>,
    /// Bytes of object descriptions copied by `ObjectInstance` so far.
    instanced_bytes: usize,
    /// Triangles the file's `curve` shapes have been tessellated into so far (bounded: `curves.rs`).
    pub curve_triangles: usize,
}

impl Converter {
    pub fn new(version: Version, search_dir: &Path, ron_dir: &Path) -> Self {
        let mut c = Converter {
            version,
            search_dir: search_dir.to_path_buf(),
            ron_dir: ron_dir.to_path_buf(),
            read_files: true,
            warnings: BTreeSet::new(),
            ctm: DMat4::IDENTITY,
            reverse: false,
            material: String::new(),
            area: None,
            stack: Vec::new(),
            named_coords: HashMap::new(),
            in_world: false,
            wide: SceneWide::default(),
            textures: BTreeMap::new(),
            materials: BTreeMap::new(),
            meshes: BTreeMap::new(),
            tex_values: HashMap::new(),
            named_materials: HashMap::new(),
            material_dedupe: HashMap::new(),
            entities: Vec::new(),
            objects: HashMap::new(),
            current_object: None,
            environment: None,
            counter: 0,
            include_depth: 0,
            includes: 0,
            files_read: Default::default(),
            instanced_bytes: 0,
            curve_triangles: 0,
        };
        c.materials.insert("default".into(), "Lambert(albedo: 0.5)".into());
        c.material = "default".into();
        c
    }

    /// Record a warning (printed once).
    pub fn warn(&mut self, msg: impl Into<String>) {
        self.warnings.insert(msg.into());
    }

    pub fn next_id(&mut self) -> usize {
        self.counter += 1;
        self.counter
    }

    /// Add an entity (RON text) to the world or to the object being defined.
    pub fn push_entity(&mut self, text: String) {
        match &mut self.current_object {
            Some((_, list)) => list.push(text),
            None => self.entities.push(text),
        }
    }

    pub fn defining_object(&self) -> bool {
        self.current_object.is_some()
    }

    /// A path of the scene resolved against the search directory.
    pub fn resolve(&self, p: &str) -> PathBuf {
        let path = Path::new(p);
        if path.is_absolute() { path.to_path_buf() } else { self.search_dir.join(path) }
    }

    /// A resolved path written relative to the RON file's directory.
    pub fn ron_path(&self, p: &Path) -> String {
        crate::mit6837::relative_path(&normalize(p), &normalize(&self.ron_dir)).to_string_lossy().replace('\\', "/")
    }

    /// The text of a file the scene names (a regular file only: never a device or a pipe); an error when files
    /// are not read.
    pub fn read_text(&self, path: &Path, what: &str) -> Result<String> {
        if !self.read_files {
            return Err(PrismError::io(
                path,
                std::io::Error::new(std::io::ErrorKind::NotFound, format!("{what} not read")),
            ));
        }
        self.files_read.borrow_mut().push(path.to_path_buf());
        prism_core::io::read_regular_text(path, what)
    }

    /// Run the directives of scene text; `file` names it in errors.
    pub fn run_text(&mut self, text: &str, file: &Path) -> Result<()> {
        let tokens = tokenize(text, file)?;
        self.run(&tokens, file)
    }

    fn run(&mut self, tokens: &[Token], file: &Path) -> Result<()> {
        let mut i = 0;
        while i < tokens.len() {
            let t = &tokens[i];
            let pos = SourcePos { file: file.to_path_buf(), line: t.line, col: t.col };
            let Tok::Word(name) = &t.tok else {
                return Err(PrismError::Parse { pos, message: format!("expected a directive, got {}", t.describe()) });
            };
            i += 1;
            self.directive(name, tokens, &mut i, file, pos)?;
        }
        Ok(())
    }

    fn directive(&mut self, name: &str, tokens: &[Token], i: &mut usize, file: &Path, pos: SourcePos) -> Result<()> {
        let perr = |pos: &SourcePos, m: String| PrismError::Parse { pos: pos.clone(), message: m };
        match name {
            "LookAt" => {
                let v = nums(tokens, i, 9, name, &pos)?;
                let (eye, at, up) =
                    (DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]), DVec3::new(v[6], v[7], v[8]));
                let m = look_at(eye, at, up).ok_or_else(|| {
                    perr(
                        &pos,
                        "LookAt: eye, target and up do not define a view (eye == target or up along the view)".into(),
                    )
                })?;
                self.ctm *= m;
            }
            "Translate" => {
                let v = nums(tokens, i, 3, name, &pos)?;
                self.ctm *= DMat4::from_translation(DVec3::new(v[0], v[1], v[2]));
            }
            "Scale" => {
                let v = nums(tokens, i, 3, name, &pos)?;
                self.ctm *= DMat4::from_scale(DVec3::new(v[0], v[1], v[2]));
            }
            "Rotate" => {
                let v = nums(tokens, i, 4, name, &pos)?;
                let axis = DVec3::new(v[1], v[2], v[3]);
                let axis =
                    axis.try_normalize().ok_or_else(|| perr(&pos, "Rotate: the axis is the zero vector".into()))?;
                self.ctm *= DMat4::from_axis_angle(axis, v[0].to_radians());
            }
            "Transform" | "ConcatTransform" => {
                let v = bracketed_nums(tokens, i, 16, name, &pos)?;
                let m = DMat4::from_cols_array(&v.try_into().expect("16 values"));
                if name == "Transform" {
                    self.ctm = m;
                } else {
                    self.ctm *= m;
                }
            }
            "Identity" => self.ctm = DMat4::IDENTITY,
            "CoordinateSystem" => {
                let n = string(tokens, i, name, &pos)?;
                self.named_coords.insert(n, self.ctm);
            }
            "CoordSysTransform" => {
                let n = string(tokens, i, name, &pos)?;
                match self.named_coords.get(&n) {
                    Some(m) => self.ctm = *m,
                    None => return Err(perr(&pos, format!("CoordSysTransform: unknown coordinate system \"{n}\""))),
                }
            }
            "ReverseOrientation" => self.reverse = !self.reverse,
            "ActiveTransform" => {
                *i += 1;
                self.warn(
                    "ActiveTransform / TransformTimes (motion blur) are ignored: every shape uses its start transform",
                );
            }
            "TransformTimes" => {
                nums(tokens, i, 2, name, &pos)?;
            }
            "WorldBegin" => {
                self.in_world = true;
                self.named_coords
                    .insert("camera".into(), self.wide.camera_from_world.map_or(DMat4::IDENTITY, |m| m.inverse()));
                self.ctm = DMat4::IDENTITY;
                self.named_coords.insert("world".into(), DMat4::IDENTITY);
            }
            "WorldEnd" => {}
            "AttributeBegin" | "TransformBegin" => {
                self.stack.push(GState {
                    ctm: self.ctm,
                    reverse: self.reverse,
                    material: self.material.clone(),
                    area: self.area.clone(),
                    transform_only: name == "TransformBegin",
                    pos,
                });
            }
            "AttributeEnd" | "TransformEnd" => {
                let Some(s) = self.stack.pop() else {
                    return Err(perr(
                        &pos,
                        format!(
                            "{name} without a matching {}",
                            if name == "AttributeEnd" { "AttributeBegin" } else { "TransformBegin" }
                        ),
                    ));
                };
                if s.transform_only != (name == "TransformEnd") {
                    return Err(perr(
                        &pos,
                        format!(
                            "{name} closes the {} opened at line {}",
                            if s.transform_only { "TransformBegin" } else { "AttributeBegin" },
                            s.pos.line
                        ),
                    ));
                }
                self.ctm = s.ctm;
                if !s.transform_only {
                    self.reverse = s.reverse;
                    self.material = s.material;
                    self.area = s.area;
                }
            }
            "ObjectBegin" => {
                let n = string(tokens, i, name, &pos)?;
                if self.current_object.is_some() {
                    return Err(perr(&pos, "ObjectBegin inside another object definition".into()));
                }
                self.stack.push(GState {
                    ctm: self.ctm,
                    reverse: self.reverse,
                    material: self.material.clone(),
                    area: self.area.clone(),
                    transform_only: false,
                    pos,
                });
                self.current_object = Some((n, Vec::new()));
            }
            "ObjectEnd" => {
                let Some((n, list)) = self.current_object.take() else {
                    return Err(perr(&pos, "ObjectEnd without ObjectBegin".into()));
                };
                self.objects.insert(n, list);
                if let Some(s) = self.stack.pop() {
                    self.ctm = s.ctm;
                    self.reverse = s.reverse;
                    self.material = s.material;
                    self.area = s.area;
                }
            }
            "ObjectInstance" => {
                let n = string(tokens, i, name, &pos)?;
                let Some(children) = self.objects.get(&n) else {
                    return Err(perr(&pos, format!("ObjectInstance: unknown object \"{n}\"")));
                };
                // Each instance copies its object's description (an object may instance others), so copies are
                // counted before they are made: objects instancing each other twice per level would double them.
                let bytes: usize = children.iter().map(String::len).sum();
                self.instanced_bytes = self.instanced_bytes.saturating_add(bytes);
                if self.instanced_bytes > MAX_INSTANCED_BYTES {
                    return Err(perr(
                        &pos,
                        format!(
                            "ObjectInstance \"{n}\": the instances expand to more than {} MiB of scene description \
                             (objects instancing others; each instance is a copy)",
                            MAX_INSTANCED_BYTES >> 20
                        ),
                    ));
                }
                let text = format!(
                    "(name: {}, transform: [{}], children: [\n{}\n])",
                    quote(&format!("{}:{} instance {n}", short(file), pos.line)),
                    matrix_op(&self.ctm),
                    children.join(",\n")
                );
                self.push_entity(text);
            }
            "Include" | "Import" => {
                let f = string(tokens, i, name, &pos)?;
                let path = self.resolve(&f);
                if self.include_depth >= 32 {
                    return Err(perr(&pos, format!("{name}: files included more than 32 deep (a cycle?)")));
                }
                self.includes += 1;
                if self.includes > MAX_INCLUDES {
                    return Err(perr(&pos, format!("{name}: more than {MAX_INCLUDES} files included in all")));
                }
                // A missing, unreadable or irregular file (a directory, a pipe, a device) is an error naming it.
                let text = self.read_text(&path, "included file").map_err(|e| perr(&pos, format!("{name}: {e}")))?;
                self.include_depth += 1;
                self.run_text(&text, &path)?;
                self.include_depth -= 1;
            }
            "Camera" | "Film" | "Sampler" | "Integrator" | "SurfaceIntegrator" | "PixelFilter" | "Accelerator"
            | "ColorSpace" | "Option" => {
                let ty = if name == "Option" { String::new() } else { string(tokens, i, name, &pos)? };
                let params = parse_params(tokens, i, file)?;
                if self.in_world {
                    return Err(perr(&pos, format!("{name} must come before WorldBegin")));
                }
                let ctm = self.ctm;
                let mut wide = std::mem::take(&mut self.wide);
                let r = wide.directive(self, name, &ty, &params, &pos, ctm);
                self.wide = wide;
                r?;
                self.report_unused(name, &ty, &params);
                if name == "Camera" {
                    self.named_coords.insert("camera".into(), ctm.inverse());
                }
            }
            "Shape" => {
                let ty = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                self.require_world(name, &pos)?;
                super::shapes::shape(self, &ty, &params, &pos)?;
                self.report_unused(name, &ty, &params);
            }
            "LightSource" => {
                let ty = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                self.require_world(name, &pos)?;
                super::lights::light_source(self, &ty, &params, &pos)?;
                self.report_unused(name, &ty, &params);
            }
            "AreaLightSource" => {
                let ty = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                self.require_world(name, &pos)?;
                super::lights::area_light_source(self, &ty, &params, &pos)?;
                self.report_unused(name, &ty, &params);
            }
            "Material" => {
                let ty = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                self.material = super::materials::material(self, &ty, &params, &pos, None)?;
                self.report_unused(name, &ty, &params);
            }
            "MakeNamedMaterial" => {
                let n = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                let ty = params
                    .string("type")?
                    .ok_or_else(|| perr(&pos, format!("MakeNamedMaterial \"{n}\": no \"string type\"")))?;
                let ron = super::materials::material(self, &ty, &params, &pos, Some(&n))?;
                self.named_materials.insert(n, ron);
                self.report_unused(name, &ty, &params);
            }
            "NamedMaterial" => {
                let n = string(tokens, i, name, &pos)?;
                match self.named_materials.get(&n) {
                    Some(m) => self.material = m.clone(),
                    None => return Err(perr(&pos, format!("NamedMaterial: unknown material \"{n}\""))),
                }
            }
            "Texture" => {
                let n = string(tokens, i, name, &pos)?;
                let kind = string(tokens, i, name, &pos)?;
                let class = string(tokens, i, name, &pos)?;
                let params = parse_params(tokens, i, file)?;
                super::textures::texture(self, &n, &kind, &class, &params, &pos)?;
                self.report_unused(name, &class, &params);
            }
            "MakeNamedMedium" | "Attribute" => {
                string(tokens, i, name, &pos)?;
                parse_params(tokens, i, file)?;
                self.warn(format!("{name} is ignored (participating media and attribute defaults are not supported)"));
            }
            "MediumInterface" => {
                while let Some(Tok::Str(_)) = tokens.get(*i).map(|t| &t.tok) {
                    *i += 1;
                }
                self.warn("MediumInterface is ignored (participating media are not supported)");
            }
            other => return Err(perr(&pos, unknown_directive(other))),
        }
        Ok(())
    }

    fn require_world(&self, name: &str, pos: &SourcePos) -> Result<()> {
        if self.in_world {
            Ok(())
        } else {
            Err(PrismError::Parse { pos: pos.clone(), message: format!("{name} before WorldBegin") })
        }
    }

    fn report_unused(&mut self, directive: &str, ty: &str, params: &Params) {
        let unused: Vec<String> =
            params.unused().iter().map(|(n, p)| format!("\"{n}\" ({}:{})", short(&p.file), p.line)).collect();
        if !unused.is_empty() {
            self.warn(format!("{directive} \"{ty}\": parameters ignored: {}", unused.join(", ")));
        }
    }

    /// Check the scopes are closed at the end of the main file.
    pub fn finish(&self) -> Result<()> {
        if let Some(s) = self.stack.last() {
            return Err(PrismError::Parse {
                pos: s.pos.clone(),
                message: format!(
                    "{} is never closed",
                    if s.transform_only { "TransformBegin" } else { "AttributeBegin" }
                ),
            });
        }
        Ok(())
    }

    /// The RON scene.
    pub fn to_ron(&self) -> String {
        let mut out = String::from("(\n");
        out.push_str(&self.wide.ron());
        let table = |out: &mut String, name: &str, t: &BTreeMap<String, String>| {
            if t.is_empty() {
                return;
            }
            let _ = writeln!(out, "    {name}: {{");
            for (k, v) in t {
                let _ = writeln!(out, "        {}: {v},", quote(k));
            }
            out.push_str("    },\n");
        };
        table(&mut out, "textures", &self.textures);
        table(&mut out, "materials", &self.materials);
        table(&mut out, "meshes", &self.meshes);
        out.push_str("    entities: [\n");
        for e in &self.entities {
            out.push_str(e);
            out.push_str(",\n");
        }
        if let Some(env) = &self.environment {
            out.push_str(&env.ron());
            out.push_str(",\n");
        }
        out.push_str("    ],\n)\n");
        out
    }
}

/// `p` made absolute with `.` and `..` components resolved lexically.
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// A file's name for entity labels.
pub fn short(file: &Path) -> String {
    file.file_name().map_or_else(|| file.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// pbrt's `LookAt`: the camera-from-world matrix (camera +z along the view, +y up, +x = up x view: pbrt's
/// left-handed screen).
pub fn look_at(eye: DVec3, at: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (at - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0));
    Some(world_from_camera.inverse())
}

/// Most bytes of object descriptions `ObjectInstance` may copy in all.
pub const MAX_INSTANCED_BYTES: usize = 256 << 20;

/// Most files a pbrt scene may include in all (`Include` and `Import`, nested ones counted each time): a few files
/// that include each other several times would otherwise describe exponentially many shapes.
pub const MAX_INCLUDES: usize = 10_000;

/// pbrt-v3's and pbrt-v4's directives.
const DIRECTIVES: [&str; 40] = [
    "Accelerator",
    "ActiveTransform",
    "AreaLightSource",
    "Attribute",
    "AttributeBegin",
    "AttributeEnd",
    "Camera",
    "ColorSpace",
    "ConcatTransform",
    "CoordinateSystem",
    "CoordSysTransform",
    "Film",
    "Identity",
    "Import",
    "Include",
    "Integrator",
    "LightSource",
    "LookAt",
    "MakeNamedMaterial",
    "MakeNamedMedium",
    "Material",
    "MediumInterface",
    "NamedMaterial",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Option",
    "PixelFilter",
    "ReverseOrientation",
    "Rotate",
    "Sampler",
    "Scale",
    "Shape",
    "SurfaceIntegrator",
    "Texture",
    "Transform",
    "TransformBegin",
    "TransformEnd",
    "TransformTimes",
    "Translate",
];

/// The message for a word where a directive should be: the word is named only when it is within two edits of a
/// directive (a typo of the scene's own), so a file that is no pbrt scene is never quoted.
fn unknown_directive(word: &str) -> String {
    let near = DIRECTIVES.iter().map(|d| (edit_distance(word, d), *d)).min();
    match near {
        Some((d, directive)) if d <= 2 && word.len() <= 32 => {
            format!("unknown directive `{word}` (did you mean `{directive}`?)")
        }
        _ => "expected a pbrt directive here (is this file a pbrt scene?)".into(),
    }
}

/// Levenshtein distance of two short strings.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().take(64).collect(), b.chars().collect());
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + (ca != cb) as usize).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()] + a.len().saturating_sub(64)
}
