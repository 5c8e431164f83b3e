//! Recursive-descent parser of 6.837 scene files (Fall 2004, assignments 1-5 and 8; the course's `scene_parser.C`
//! grammar): top-level `OrthographicCamera`, `PerspectiveCamera`, `Background`, `Lights`, `Materials` and one
//! `Group`; objects `Group`, `Transform`, `Sphere`, `Plane`, `Triangle`, `TriangleMesh`. It checks what the course
//! only asserted: braces, declared counts (`numObjects`, `numMaterials`, `numLights`), keywords, numbers, material
//! indices and that mesh files exist (or, for assignment 8's meshes, the spline file they are made from), each
//! failure a one-line error `file:line:col: message`.

use super::ast::{CameraTxt, LightTxt, MaterialTxt, ObjectTxt, OpTxt, PhongTxt, SceneTxt};
use super::lexer::{Token, tokenize};
use glam::Vec3;
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::limits::MAX_NESTING_DEPTH;
use std::path::{Path, PathBuf};

pub(super) struct Parser<'a> {
    tokens: Vec<Token>,
    next: usize,
    file: &'a Path,
    base_dir: PathBuf,
    /// The material of the objects read from now on (`MaterialIndex`).
    current_material: Option<usize>,
    num_materials: Option<usize>,
    /// `Group`/`Transform` blocks open around the current token (at most [`MAX_NESTING_DEPTH`]).
    depth: usize,
}

/// Parse 6.837 scene text. `file` names it in errors; mesh paths resolve against `base_dir`.
pub fn parse_txt(text: &str, file: &Path, base_dir: &Path) -> Result<SceneTxt> {
    let mut p = Parser {
        tokens: tokenize(text),
        next: 0,
        file,
        base_dir: base_dir.to_path_buf(),
        current_material: None,
        num_materials: None,
        depth: 0,
    };
    p.scene()
}

impl Parser<'_> {
    pub(super) fn error_at(&self, line: usize, col: usize, message: impl Into<String>) -> PrismError {
        PrismError::Parse { pos: SourcePos { file: self.file.to_path_buf(), line, col }, message: message.into() }
    }

    /// An error at the token just read (or the end of the file).
    pub(super) fn error(&self, message: impl Into<String>) -> PrismError {
        match self.tokens.get(self.next.saturating_sub(1)) {
            Some(t) => self.error_at(t.line, t.col, message),
            None => self.error_at(1, 1, message),
        }
    }

    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.next)
    }

    /// The next token; `what` says what was expected, for the end-of-file message.
    pub(super) fn token(&mut self, what: &str) -> Result<Token> {
        match self.tokens.get(self.next) {
            Some(t) => {
                self.next += 1;
                Ok(t.clone())
            }
            None => {
                let (line, col) = self.tokens.last().map_or((1, 1), |t| (t.line, t.col + t.text.len()));
                Err(self.error_at(line, col, format!("unexpected end of file: expected {what}")))
            }
        }
    }

    pub(super) fn expect(&mut self, word: &str, context: &str) -> Result<()> {
        let t = self.token(&format!("`{word}` {context}"))?;
        if t.text != word {
            return Err(self.error_at(t.line, t.col, format!("expected `{word}` {context}, found `{}`", t.text)));
        }
        Ok(())
    }

    pub(super) fn float(&mut self, what: &str) -> Result<f32> {
        let t = self.token(&format!("a number for {what}"))?;
        match t.text.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error_at(t.line, t.col, format!("expected a number for {what}, found `{}`", t.text))),
        }
    }

    pub(super) fn int(&mut self, what: &str) -> Result<usize> {
        let t = self.token(&format!("a count for {what}"))?;
        t.text.parse::<usize>().map_err(|_| {
            self.error_at(t.line, t.col, format!("expected a non-negative integer for {what}, found `{}`", t.text))
        })
    }

    pub(super) fn vec3(&mut self, what: &str) -> Result<Vec3> {
        Ok(Vec3::new(self.float(what)?, self.float(what)?, self.float(what)?))
    }

    /// `keyword x y z`.
    fn keyed_vec3(&mut self, keyword: &str, block: &str) -> Result<Vec3> {
        self.expect(keyword, &format!("in {block}"))?;
        self.vec3(&format!("`{keyword}` of {block}"))
    }

    fn keyed_float(&mut self, keyword: &str, block: &str) -> Result<f32> {
        self.expect(keyword, &format!("in {block}"))?;
        self.float(&format!("`{keyword}` of {block}"))
    }

    fn scene(&mut self) -> Result<SceneTxt> {
        let mut camera = None;
        let mut background = None;
        let mut ambient = None;
        let mut lights: Option<Vec<LightTxt>> = None;
        let mut materials = None;
        let mut root = None;
        while let Some(t) = self.peek().cloned() {
            self.next += 1;
            let once = |seen: bool, p: &Self| {
                if seen { Err(p.error_at(t.line, t.col, format!("`{}` appears twice", t.text))) } else { Ok(()) }
            };
            match t.text.as_str() {
                "OrthographicCamera" | "PerspectiveCamera" => {
                    once(camera.is_some(), self)?;
                    camera = Some(self.camera(&t.text)?);
                }
                "Background" => {
                    once(background.is_some(), self)?;
                    let (c, a) = self.background()?;
                    background = Some(c);
                    ambient = a;
                }
                "Lights" => {
                    once(lights.is_some(), self)?;
                    lights = Some(self.lights()?);
                }
                "Materials" => {
                    once(materials.is_some(), self)?;
                    materials = Some(self.materials()?);
                }
                "Group" => {
                    once(root.is_some(), self)?;
                    root = Some(self.group(t.line)?);
                }
                other => {
                    return Err(self.error_at(
                        t.line,
                        t.col,
                        format!(
                            "unknown keyword `{other}` at the top level (expected OrthographicCamera, \
                             PerspectiveCamera, Background, Lights, Materials or Group)"
                        ),
                    ));
                }
            }
        }
        let camera = camera.ok_or_else(|| self.error_at(1, 1, "the scene has no camera"))?;
        let lights = lights.unwrap_or_default();
        // Course rule: without lights, the ambient light is white (flat colours).
        let ambient = if lights.is_empty() { Vec3::ONE } else { ambient.unwrap_or(Vec3::ZERO) };
        Ok(SceneTxt {
            camera,
            background: background.unwrap_or(Vec3::splat(0.5)),
            ambient,
            lights,
            materials: materials.unwrap_or_default(),
            root,
        })
    }

    fn camera(&mut self, kind: &str) -> Result<CameraTxt> {
        self.expect("{", &format!("after {kind}"))?;
        let center = self.keyed_vec3("center", kind)?;
        let direction = self.keyed_vec3("direction", kind)?;
        let up = self.keyed_vec3("up", kind)?;
        let cam = if kind == "OrthographicCamera" {
            let size = self.keyed_float("size", kind)?;
            if size <= 0.0 {
                return Err(self.error(format!("{kind} size must be positive, got {size}")));
            }
            CameraTxt::Orthographic { center, direction, up, size }
        } else {
            let angle = self.keyed_float("angle", kind)?;
            if !(angle > 0.0 && angle < 180.0) {
                return Err(self.error(format!("{kind} angle must be between 0 and 180 degrees, got {angle}")));
            }
            CameraTxt::Perspective { center, direction, up, angle }
        };
        self.expect("}", &format!("to close {kind}"))?;
        if direction == Vec3::ZERO || direction.cross(up) == Vec3::ZERO {
            return Err(self.error(format!("{kind}: direction is zero or parallel to up")));
        }
        Ok(cam)
    }

    fn background(&mut self) -> Result<(Vec3, Option<Vec3>)> {
        self.expect("{", "after Background")?;
        let (mut color, mut ambient) = (Vec3::splat(0.5), None);
        loop {
            let t = self.token("`color`, `ambientLight` or `}` in Background")?;
            match t.text.as_str() {
                "}" => return Ok((color, ambient)),
                "color" => color = self.vec3("`color` of Background")?,
                "ambientLight" => ambient = Some(self.vec3("`ambientLight` of Background")?),
                other => {
                    return Err(self.error_at(
                        t.line,
                        t.col,
                        format!("unknown keyword `{other}` in Background (expected color or ambientLight)"),
                    ));
                }
            }
        }
    }

    /// `{ numX N  Item {...} x N }` where every item is one of `kinds`.
    fn counted_block<T>(
        &mut self,
        block: &str,
        count_word: &str,
        kinds: &[&str],
        mut item: impl FnMut(&mut Self, &str) -> Result<T>,
    ) -> Result<Vec<T>> {
        self.expect("{", &format!("after {block}"))?;
        self.expect(count_word, &format!("at the start of {block}"))?;
        let n = self.int(&format!("`{count_word}`"))?;
        let mut out = Vec::new();
        loop {
            let t = self.token(&format!("`}}` to close {block}"))?;
            if t.text == "}" {
                if out.len() != n {
                    return Err(self.error_at(
                        t.line,
                        t.col,
                        format!("{block} declares {count_word} {n} but lists {}", out.len()),
                    ));
                }
                return Ok(out);
            }
            if !kinds.contains(&t.text.as_str()) {
                return Err(self.error_at(
                    t.line,
                    t.col,
                    format!("unknown keyword `{}` in {block} (expected {} or `}}`)", t.text, kinds.join(", ")),
                ));
            }
            if out.len() == n {
                return Err(self.error_at(
                    t.line,
                    t.col,
                    format!("{block} declares {count_word} {n} but lists more (`{}`)", t.text),
                ));
            }
            out.push(item(self, &t.text)?);
        }
    }

    fn lights(&mut self) -> Result<Vec<LightTxt>> {
        self.counted_block("Lights", "numLights", &["DirectionalLight", "PointLight"], |p, kind| {
            p.expect("{", &format!("after {kind}"))?;
            let light = if kind == "DirectionalLight" {
                let direction = p.keyed_vec3("direction", kind)?;
                if direction == Vec3::ZERO {
                    return Err(p.error("DirectionalLight direction is the zero vector"));
                }
                let color = p.keyed_vec3("color", kind)?;
                p.expect("}", "to close DirectionalLight")?;
                LightTxt::Directional { direction, color }
            } else {
                let position = p.keyed_vec3("position", kind)?;
                let color = p.keyed_vec3("color", kind)?;
                let mut attenuation = [1.0, 0.0, 0.0];
                let t = p.token("`attenuation` or `}` in PointLight")?;
                if t.text == "attenuation" {
                    for a in attenuation.iter_mut() {
                        *a = p.float("`attenuation` of PointLight")?;
                    }
                    if attenuation.iter().any(|&a| a < 0.0) || attenuation.iter().all(|&a| a == 0.0) {
                        return Err(p.error(format!(
                            "PointLight attenuation {attenuation:?} must be non-negative and not all zero"
                        )));
                    }
                    p.expect("}", "to close PointLight")?;
                } else if t.text != "}" {
                    return Err(p.error_at(
                        t.line,
                        t.col,
                        format!("expected `attenuation` or `}}` in PointLight, found `{}`", t.text),
                    ));
                }
                LightTxt::Point { position, color, attenuation }
            };
            Ok(light)
        })
    }

    fn materials(&mut self) -> Result<Vec<MaterialTxt>> {
        const KINDS: [&str; 6] = ["Material", "PhongMaterial", "Checkerboard", "Noise", "Marble", "Wood"];
        let m = self.counted_block("Materials", "numMaterials", &KINDS, |p, kind| match kind {
            "Material" | "PhongMaterial" => Ok(MaterialTxt::Phong(p.phong_material(kind)?)),
            _ => Ok(MaterialTxt::Solid(p.solid_material(kind)?)),
        })?;
        // Solid materials refer to materials of the same block, by index.
        for (i, mat) in m.iter().enumerate() {
            if let MaterialTxt::Solid(s) = mat
                && let Some(bad) = s.materials.iter().find(|&&j| j >= m.len() || j == i)
            {
                return Err(self.error(format!(
                    "material {i} ({:?}) uses materialIndex {bad}: the block defines {} materials{}",
                    s.kind,
                    m.len(),
                    if *bad == i { " and a material cannot contain itself" } else { "" }
                )));
            }
        }
        self.num_materials = Some(m.len());
        Ok(m)
    }

    fn phong_material(&mut self, kind: &str) -> Result<PhongTxt> {
        self.expect("{", &format!("after {kind}"))?;
        let mut m = PhongTxt::default();
        loop {
            let t = self.token(&format!("a property or `}}` in {kind}"))?;
            let what = format!("`{}` of {kind}", t.text);
            match t.text.as_str() {
                "}" => return Ok(m),
                "diffuseColor" => m.diffuse = self.vec3(&what)?,
                "specularColor" => m.specular = self.vec3(&what)?,
                "exponent" => m.exponent = self.float(&what)?,
                "reflectiveColor" => m.reflective = self.vec3(&what)?,
                "transparentColor" => m.transparent = self.vec3(&what)?,
                "indexOfRefraction" => m.ior = self.float(&what)?,
                other => {
                    return Err(self.error_at(
                        t.line,
                        t.col,
                        format!(
                            "unknown keyword `{other}` in {kind} (expected diffuseColor, specularColor, exponent, \
                             reflectiveColor, transparentColor or indexOfRefraction)"
                        ),
                    ));
                }
            }
            let colors = [m.diffuse, m.specular, m.reflective, m.transparent];
            if colors.iter().any(|c| c.min_element() < 0.0) || m.exponent < 0.0 || m.ior <= 0.0 {
                return Err(self.error(format!("{what}: colours and exponent must be >= 0 and the index > 0")));
            }
        }
    }

    fn group(&mut self, line: usize) -> Result<ObjectTxt> {
        self.expect("{", "after Group")?;
        self.expect("numObjects", "at the start of Group")?;
        let n = self.int("`numObjects`")?;
        let mut children = Vec::new();
        loop {
            let t = self.token("an object, `MaterialIndex` or `}` to close Group")?;
            match t.text.as_str() {
                "}" => {
                    if children.len() != n {
                        return Err(self.error_at(
                            t.line,
                            t.col,
                            format!("Group declares numObjects {n} but contains {}", children.len()),
                        ));
                    }
                    return Ok(ObjectTxt::Group { line, children });
                }
                "MaterialIndex" => {
                    let i = self.int("`MaterialIndex`")?;
                    let available = self.num_materials.unwrap_or(0);
                    if i >= available {
                        return Err(self.error(format!(
                            "MaterialIndex {i} is out of range (the scene defines {available} materials{})",
                            if self.num_materials.is_none() { "; Materials must come before Group" } else { "" }
                        )));
                    }
                    self.current_material = Some(i);
                }
                _ => {
                    if children.len() == n {
                        return Err(self.error_at(
                            t.line,
                            t.col,
                            format!("Group declares numObjects {n} but contains more (`{}`)", t.text),
                        ));
                    }
                    children.push(self.object(&t)?);
                }
            }
        }
    }

    fn material_for(&self, t: &Token) -> Result<usize> {
        self.current_material.ok_or_else(|| {
            self.error_at(t.line, t.col, format!("{} comes before any MaterialIndex (it has no material)", t.text))
        })
    }

    fn object(&mut self, t: &Token) -> Result<ObjectTxt> {
        let line = t.line;
        Ok(match t.text.as_str() {
            "Group" | "Transform" => {
                if self.depth >= MAX_NESTING_DEPTH {
                    return Err(self.error_at(
                        t.line,
                        t.col,
                        format!("Group and Transform blocks nested deeper than {MAX_NESTING_DEPTH} levels"),
                    ));
                }
                self.depth += 1;
                let o = if t.text == "Group" { self.group(line) } else { self.transform(line) };
                self.depth -= 1;
                o?
            }
            "Sphere" => {
                self.expect("{", "after Sphere")?;
                let center = self.keyed_vec3("center", "Sphere")?;
                let radius = self.keyed_float("radius", "Sphere")?;
                if radius <= 0.0 {
                    return Err(self.error(format!("Sphere radius must be positive, got {radius}")));
                }
                self.expect("}", "to close Sphere")?;
                ObjectTxt::Sphere { line, center, radius, material: self.material_for(t)? }
            }
            "Plane" => {
                self.expect("{", "after Plane")?;
                let normal = self.keyed_vec3("normal", "Plane")?;
                if normal == Vec3::ZERO {
                    return Err(self.error("Plane normal is the zero vector"));
                }
                let offset = self.keyed_float("offset", "Plane")?;
                self.expect("}", "to close Plane")?;
                ObjectTxt::Plane { line, normal, offset, material: self.material_for(t)? }
            }
            "Triangle" => {
                self.expect("{", "after Triangle")?;
                let vertices = [
                    self.keyed_vec3("vertex0", "Triangle")?,
                    self.keyed_vec3("vertex1", "Triangle")?,
                    self.keyed_vec3("vertex2", "Triangle")?,
                ];
                if (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]) == Vec3::ZERO {
                    return Err(self.error("Triangle has zero area"));
                }
                self.expect("}", "to close Triangle")?;
                ObjectTxt::Triangle { line, vertices, material: self.material_for(t)? }
            }
            "TriangleMesh" => {
                self.expect("{", "after TriangleMesh")?;
                self.expect("obj_file", "in TriangleMesh")?;
                let name = self.token("the file name after obj_file")?;
                if name.text == "}" {
                    return Err(self.error_at(name.line, name.col, "obj_file has no file name"));
                }
                let path = self.base_dir.join(&name.text);
                if !name.text.to_ascii_lowercase().ends_with(".obj") {
                    return Err(self.error_at(name.line, name.col, format!("obj_file `{}` is not .obj", name.text)));
                }
                // A mesh assignment 8's curve editor made: its spline file, if it is there.
                let splines = super::course_meshes::course_mesh(&name.text)
                    .map(|(spline, tess)| (self.base_dir.join(spline), tess))
                    .filter(|(spline, _)| spline.is_file());
                if splines.is_none()
                    && let Err(e) = prism_core::io::open_regular(&path, "obj_file")
                {
                    return Err(self.error_at(name.line, name.col, e.to_string()));
                }
                self.expect("}", "to close TriangleMesh")?;
                ObjectTxt::Mesh { line, path, material: self.material_for(t)?, splines }
            }
            other => {
                return Err(self.error_at(
                    t.line,
                    t.col,
                    format!(
                        "unknown object `{other}` (expected Group, Transform, Sphere, Plane, Triangle, TriangleMesh \
                         or MaterialIndex)"
                    ),
                ));
            }
        })
    }

    /// `Transform { op* object }`: operations compose as the course's `matrix *= op` (first listed is applied
    /// last to the object), except `Matrix`, which the course pre-multiplies (`matrix = M * matrix`).
    fn transform(&mut self, line: usize) -> Result<ObjectTxt> {
        self.expect("{", "after Transform")?;
        let mut ops: Vec<OpTxt> = Vec::new();
        loop {
            let t = self.token("a transformation or an object in Transform")?;
            match self.transform_op(&t)? {
                Some(op @ OpTxt::Matrix(_)) => ops.insert(0, op),
                Some(op) => ops.push(op),
                None => {
                    let child = self.object(&t)?;
                    self.expect("}", "to close Transform (one object per Transform)")?;
                    return Ok(ObjectTxt::Transform { line, ops, child: Box::new(child) });
                }
            }
        }
    }

    /// The transformation named by the token just read (its arguments follow), or `None` when the token is not a
    /// transformation. `Matrix` is returned as is: the caller pre-multiplies it as the course does.
    pub(super) fn transform_op(&mut self, t: &Token) -> Result<Option<OpTxt>> {
        let op = match t.text.as_str() {
            "Scale" => OpTxt::Scale(self.vec3("`Scale`")?),
            "UniformScale" => OpTxt::UniformScale(self.float("`UniformScale`")?),
            "Translate" => OpTxt::Translate(self.vec3("`Translate`")?),
            "XRotate" => OpTxt::Rotate { axis: Vec3::X, degrees: self.float("`XRotate`")? },
            "YRotate" => OpTxt::Rotate { axis: Vec3::Y, degrees: self.float("`YRotate`")? },
            "ZRotate" => OpTxt::Rotate { axis: Vec3::Z, degrees: self.float("`ZRotate`")? },
            "Rotate" => {
                self.expect("{", "after Rotate")?;
                let axis = self.vec3("the axis of `Rotate`")?;
                let degrees = self.float("the angle of `Rotate`")?;
                self.expect("}", "to close Rotate")?;
                if axis == Vec3::ZERO {
                    return Err(self.error("Rotate axis is the zero vector"));
                }
                OpTxt::Rotate { axis, degrees }
            }
            "Matrix" => {
                self.expect("{", "after Matrix")?;
                let mut rows = [[0.0; 4]; 4];
                for row in rows.iter_mut() {
                    for v in row.iter_mut() {
                        *v = self.float("`Matrix` (16 numbers, row by row)")?;
                    }
                }
                self.expect("}", "to close Matrix (after 16 numbers)")?;
                if rows[3] != [0.0, 0.0, 0.0, 1.0] {
                    return Err(self.error(format!("Matrix last row must be 0 0 0 1 (affine), got {:?}", rows[3])));
                }
                OpTxt::Matrix(rows)
            }
            _ => return Ok(None),
        };
        let singular = match &op {
            OpTxt::Scale(s) => s.x * s.y * s.z == 0.0,
            OpTxt::UniformScale(s) => *s == 0.0,
            _ => false,
        };
        if singular {
            return Err(self.error("a zero scale makes the transform singular"));
        }
        Ok(Some(op))
    }
}
