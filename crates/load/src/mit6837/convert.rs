//! 6.837 scene (as parsed) to the equivalent Prism RON scene: the course's conventions turned into Prism's units,
//! so the image comes out as the course intended. Loading a `.txt` scene spawns exactly this RON, and
//! `prism convert` writes it.
//!
//! | 6.837 | Prism |
//! |---|---|
//! | light colour `c` (diffuse `kd c max(n.l, 0)`) | irradiance `pi c` (the BRDF is `kd / pi`) |
//! | `PointLight` colour `c`, attenuation `(a0, a1, a2)` (default `(1, 0, 0)`) | `Point(intensity: pi c, attenuation: (a0, a1, a2))`: irradiance `pi c cos / (a0 + a1 d + a2 d^2)` |
//! | `Material`/`PhongMaterial` | `Mit6837(...)`: ambient reflectance = diffuse, Blinn-Phong specular `ks (n.h)^e c` without normalisation, mirror and refraction without Fresnel (`material.rs`) |
//! | `Background { color, ambientLight }` | `background`, `ambient` (white when there are no lights, as in the course) |
//! | `OrthographicCamera { center direction up size }` | `orthographic: size`, eye moved back behind all geometry (the course starts orthographic rays at t = -inf) |
//! | `PerspectiveCamera { ... angle }` | `fov: angle` |
//! | `Transform { ops object }`, nested | an entity with `transform: [ops]` and the object as its child |
//! | `MaterialIndex i` | the material of every following object, in file order |
//! | `Checkerboard`, `Noise`, `Marble`, `Wood` (a6) | a solid texture `t{i}` (`Checker3d`, `Noise`, `Marble`, `Wood` with the block's transform, octaves, frequency, amplitude) and `Blend` of the two materials weighted by it |
//! | `TriangleMesh { obj_file torus_high.obj }` (assignment 8, file missing) | `Splines(path: "spline8_06_torus.txt", tessellation: Some((curve: 30, revolution: 60, patch: 10)))`: the course's mesh, made on the fly; `tessellation: None` (exact surfaces) with `--exact-curves` |
//! | image size (a command-line option in the course) | 200 x 200, the course's usual `-size` |

use super::ast::{CameraTxt, LightTxt, MaterialTxt, ObjectTxt, OpTxt, PhongTxt, SceneTxt, SolidTxt, SolidTxtKind};
use super::spline::SplineTxt;
use crate::schema::TransformOp;
use crate::{compose, load_obj};
use glam::{Affine3A, Vec3, Vec3A};
use prism_core::error::Result;
use prism_core::geometry::Bounds;
use std::f32::consts::PI;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

/// The course's usual image size.
pub const DEFAULT_SIZE: u32 = 200;

fn v3(v: Vec3) -> String {
    format!("({:?}, {:?}, {:?})", v.x, v.y, v.z)
}

fn op_desc(op: &OpTxt) -> TransformOp {
    match op {
        OpTxt::Scale(s) => TransformOp::Scale(s.to_array()),
        OpTxt::UniformScale(s) => TransformOp::UniformScale(*s),
        OpTxt::Translate(t) => TransformOp::Translate(t.to_array()),
        OpTxt::Rotate { axis, degrees } => TransformOp::Rotate { axis: axis.to_array(), degrees: *degrees },
        OpTxt::Matrix(m) => TransformOp::Matrix(*m),
    }
}

fn op_ron(op: &OpTxt) -> String {
    match op {
        OpTxt::Scale(s) => format!("Scale({})", v3(*s)),
        OpTxt::UniformScale(s) => format!("UniformScale({s:?})"),
        OpTxt::Translate(t) => format!("Translate({})", v3(*t)),
        OpTxt::Rotate { axis, degrees } => format!("Rotate(axis: {}, degrees: {degrees:?})", v3(*axis)),
        OpTxt::Matrix(m) => {
            let rows: Vec<String> =
                m.iter().map(|r| format!("({:?}, {:?}, {:?}, {:?})", r[0], r[1], r[2], r[3])).collect();
            format!("Matrix(({}))", rows.join(", "))
        }
    }
}

/// `path` relative to `base` when they share a root, else absolute.
pub fn relative_path(path: &Path, base: &Path) -> PathBuf {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (p, b) = (abs(path), abs(base));
    let pc: Vec<Component> = p.components().collect();
    let bc: Vec<Component> = b.components().collect();
    let common = pc.iter().zip(&bc).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return p;
    }
    let mut out = PathBuf::new();
    for _ in common..bc.len() {
        out.push("..");
    }
    for c in &pc[common..] {
        out.push(c);
    }
    out
}

struct Writer<'a> {
    file: &'a Path,
    mesh_base: &'a Path,
    /// Replace assignment 8's meshes by the exact surfaces of their spline files.
    exact_curves: bool,
    out: String,
    /// World bounds of the bounded objects (for the orthographic camera).
    bounds: Bounds,
}

impl Writer<'_> {
    fn label(&self, what: &str, line: usize) -> String {
        let name =
            self.file.file_name().map_or_else(|| self.file.display().to_string(), |n| n.to_string_lossy().into());
        format!("{name}:{line} {what}")
    }

    fn object(&mut self, o: &ObjectTxt, m: &Affine3A, indent: usize) -> Result<()> {
        // Indentation stops growing after 16 levels: deep nesting must not make the text quadratic in size.
        let pad = " ".repeat(indent.min(64));
        match o {
            ObjectTxt::Group { line, children } => {
                let _ = writeln!(self.out, "{pad}(name: {:?}, children: [", self.label("Group", *line));
                for c in children {
                    self.object(c, m, indent + 4)?;
                }
                let _ = writeln!(self.out, "{pad}]),");
            }
            ObjectTxt::Transform { line, ops, child } => {
                let label = self.label("Transform", *line);
                let descs: Vec<TransformOp> = ops.iter().map(op_desc).collect();
                let local = compose(&descs, &format!("{}:{line}: Transform", self.file.display()))?;
                let ops: Vec<String> = ops.iter().map(op_ron).collect();
                let _ = writeln!(self.out, "{pad}(name: {label:?}, transform: [{}], children: [", ops.join(", "));
                self.object(child, &(*m * local), indent + 4)?;
                let _ = writeln!(self.out, "{pad}]),");
            }
            ObjectTxt::Sphere { line, center, radius, material } => {
                let local = Bounds::new(Vec3A::from(*center - *radius), Vec3A::from(*center + *radius));
                self.bounds = self.bounds.union(local.transformed(m));
                let _ = writeln!(
                    self.out,
                    "{pad}(name: {:?}, shape: Sphere(center: {}, radius: {radius:?}), material: \"m{material}\"),",
                    self.label("Sphere", *line),
                    v3(*center)
                );
            }
            ObjectTxt::Plane { line, normal, offset, material } => {
                let _ = writeln!(
                    self.out,
                    "{pad}(name: {:?}, shape: Plane(normal: {}, offset: {offset:?}), material: \"m{material}\"),",
                    self.label("Plane", *line),
                    v3(*normal)
                );
            }
            ObjectTxt::Triangle { line, vertices, material } => {
                for v in vertices {
                    self.bounds = self.bounds.with_point(m.transform_point3a(Vec3A::from(*v)));
                }
                let _ = writeln!(
                    self.out,
                    "{pad}(name: {:?}, shape: Triangle(vertices: ({}, {}, {})), material: \"m{material}\"),",
                    self.label("Triangle", *line),
                    v3(vertices[0]),
                    v3(vertices[1]),
                    v3(vertices[2])
                );
            }
            ObjectTxt::Mesh { line, path, material, splines } => {
                if let Some((spline, tess)) = splines
                    && (self.exact_curves || !path.is_file())
                {
                    for item in super::spline::parse_spline_file(spline)? {
                        let pts: Vec<glam::DVec3> = match &item {
                            SplineTxt::Curve { .. } => vec![],
                            SplineTxt::Revolution { profile, .. } => {
                                let (lo, hi) = profile.hull_bounds();
                                let r = lo.x.abs().max(hi.x.abs());
                                vec![glam::DVec3::new(-r, lo.y, -r), glam::DVec3::new(r, hi.y, r)]
                            }
                            SplineTxt::Patch { points, .. } => points.to_vec(),
                        };
                        for p in pts {
                            self.bounds = self.bounds.with_point(m.transform_point3a(Vec3A::from(p.as_vec3())));
                        }
                    }
                    let rel = relative_path(spline, self.mesh_base);
                    let tessellation = if self.exact_curves {
                        "None".to_string()
                    } else {
                        format!("Some((curve: {}, revolution: {}, patch: {}))", tess.curve, tess.revolution, tess.patch)
                    };
                    let _ = writeln!(
                        self.out,
                        "{pad}(name: {:?}, shape: Splines(path: {:?}, tessellation: {tessellation}), material: \"m{material}\"),",
                        self.label(
                            &format!("TriangleMesh {}", path.file_name().unwrap_or_default().to_string_lossy()),
                            *line
                        ),
                        rel.to_string_lossy()
                    );
                    return Ok(());
                }
                for part in load_obj(path)? {
                    for p in &part.mesh.positions {
                        self.bounds = self.bounds.with_point(m.transform_point3a(Vec3A::from(*p)));
                    }
                }
                let rel = relative_path(path, self.mesh_base);
                let _ = writeln!(
                    self.out,
                    "{pad}(name: {:?}, shape: Mesh(path: {:?}), material: \"m{material}\"),",
                    self.label("TriangleMesh", *line),
                    rel.to_string_lossy()
                );
            }
        }
        Ok(())
    }
}

fn phong_ron(m: &PhongTxt) -> String {
    format!(
        "Mit6837(diffuse: {}, specular: {}, exponent: {:?}, reflective: {}, transparent: {}, ior: {:?})",
        v3(m.diffuse),
        v3(m.specular),
        m.exponent,
        v3(m.reflective),
        v3(m.transparent),
        m.ior
    )
}

/// A solid material `i` as a texture `t{i}` and a blend of its two materials.
fn solid_ron(i: usize, s: &SolidTxt) -> (String, String) {
    let ops: Vec<String> = s.ops.iter().map(op_ron).collect();
    let transform = format!("transform: [{}]", ops.join(", "));
    let (f, a, o) = (s.frequency, s.amplitude, s.octaves);
    let texture = match s.kind {
        SolidTxtKind::Checkerboard => format!("Checker3d({transform})"),
        SolidTxtKind::Noise => format!("Noise({transform}, octaves: {o})"),
        SolidTxtKind::Marble => format!("Marble({transform}, octaves: {o}, frequency: {f:?}, amplitude: {a:?})"),
        SolidTxtKind::Wood => format!("Wood({transform}, octaves: {o}, frequency: {f:?}, amplitude: {a:?})"),
    };
    let [m1, m2] = s.materials;
    // Checkerboard: even cells (value 0) show the first material. Noise, marble, wood: the value weighs the first.
    let blend = match s.kind {
        SolidTxtKind::Checkerboard => format!("Blend(a: \"m{m1}\", b: \"m{m2}\", weight: Texture(\"t{i}\"))"),
        _ => format!("Blend(a: \"m{m2}\", b: \"m{m1}\", weight: Texture(\"t{i}\"))"),
    };
    (texture, blend)
}

/// A 6.837 scene as RON.
#[derive(Clone, Debug)]
pub struct Converted {
    pub ron: String,
    /// How far the eye was moved back along the view direction (orthographic cameras; 0 otherwise): course
    /// depths (from the course's camera centre) are Prism distances minus this.
    pub eye_back: f32,
}

/// The RON text of a parsed 6.837 scene. `file` names the source (entity names carry its lines); mesh paths
/// are written relative to `mesh_base` (the folder the RON file will live in). A mesh assignment 8's curve editor
/// made becomes `Splines(path: spline file, tessellation: ...)`: the course's tessellation when the mesh file is
/// missing, the exact surfaces (`tessellation: None`) with `exact_curves`.
pub fn to_ron(scene: &SceneTxt, file: &Path, mesh_base: &Path, exact_curves: bool) -> Result<Converted> {
    let mut w = Writer { file, mesh_base, exact_curves, out: String::new(), bounds: Bounds::EMPTY };
    if let Some(root) = &scene.root {
        w.object(root, &Affine3A::IDENTITY, 8)?;
    }
    let entities = std::mem::take(&mut w.out);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "// {} converted by `prism convert`: 6.837 conventions in Prism's units (Prism's book: docs/guide/mit6837.md).",
        file.file_name().map_or_else(String::new, |n| n.to_string_lossy().into())
    );
    s += "(\n";
    let size = format!("size: ({DEFAULT_SIZE}, {DEFAULT_SIZE})");
    let mut eye_back = 0.0;
    match &scene.camera {
        CameraTxt::Perspective { center, direction, up, angle } => {
            let _ = writeln!(
                s,
                "    camera: (eye: {}, target: {}, up: {}, fov: {angle:?}, {size}),",
                v3(*center),
                v3(*center + *direction),
                v3(*up)
            );
        }
        CameraTxt::Orthographic { center, direction, up, size: height } => {
            // The course's orthographic rays start at t = -inf: move the eye back behind every bounded object.
            let d = direction.normalize();
            let back = if w.bounds.is_empty() {
                0.0
            } else {
                let b = w.bounds;
                let mut behind: f32 = 0.0;
                for i in 0..8 {
                    let c = Vec3::new(
                        if i & 1 == 0 { b.min.x } else { b.max.x },
                        if i & 2 == 0 { b.min.y } else { b.max.y },
                        if i & 4 == 0 { b.min.z } else { b.max.z },
                    );
                    behind = behind.max((*center - c).dot(d));
                }
                behind + 0.01 * b.diagonal().length() + 1e-3
            };
            let eye = *center - d * back;
            eye_back = back;
            let _ = writeln!(
                s,
                "    camera: (eye: {}, target: {}, up: {}, orthographic: {height:?}, {size}),",
                v3(eye),
                v3(eye + d),
                v3(*up)
            );
        }
    }
    let _ = writeln!(s, "    background: {},", v3(scene.background));
    let _ = writeln!(s, "    ambient: {},", v3(scene.ambient));
    let solids: Vec<(usize, (String, String))> = scene
        .materials
        .iter()
        .enumerate()
        .filter_map(|(i, m)| match m {
            MaterialTxt::Solid(sd) => Some((i, solid_ron(i, sd))),
            MaterialTxt::Phong(_) => None,
        })
        .collect();
    if !solids.is_empty() {
        s += "    textures: {\n";
        for (i, (tex, _)) in &solids {
            let _ = writeln!(s, "        \"t{i}\": {tex},");
        }
        s += "    },\n";
    }
    s += "    materials: {\n";
    for (i, m) in scene.materials.iter().enumerate() {
        let ron = match m {
            MaterialTxt::Phong(p) => phong_ron(p),
            MaterialTxt::Solid(_) => {
                solids.iter().find(|(j, _)| *j == i).map(|(_, (_, b))| b.clone()).unwrap_or_default()
            }
        };
        let _ = writeln!(s, "        \"m{i}\": {ron},");
    }
    s += "    },\n    entities: [\n";
    for (i, l) in scene.lights.iter().enumerate() {
        let light = match l {
            LightTxt::Directional { direction, color } => {
                format!("Directional(irradiance: {}, direction: {})", v3(*color * PI), v3(*direction))
            }
            LightTxt::Point { position, color, attenuation: [a0, a1, a2] } => format!(
                "Point(intensity: {}, position: {}, attenuation: ({a0:?}, {a1:?}, {a2:?}))",
                v3(*color * PI),
                v3(*position)
            ),
        };
        let _ = writeln!(s, "        (name: \"light{i}\", light: {light}),");
    }
    s += &entities;
    s += "    ],\n)\n";
    Ok(Converted { ron: s, eye_back })
}
