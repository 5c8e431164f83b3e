//! PLY meshes (Stanford polygon files: ASCII, binary little- and big-endian) through the `ply-rs-bw` crate:
//! vertex positions `x y z`, normals `nx ny nz`, texture coordinates (`u v`, `s t`, `texture_u texture_v` or
//! `texture_s texture_t`), and faces (`vertex_indices` or `vertex_index` lists; triangles, quads split along
//! 0-2, larger convex polygons as fans). Other elements and properties (colours, `face_indices`, edges) are read
//! past and ignored. Texture coordinates become `(u, 1 - v)`: PLY's v points up the image as OBJ's and pbrt's do,
//! Prism's down.
//!
//! Bad input never panics and never allocates from an untrusted header: before any element is read, the bytes
//! after the header must be able to hold what the header declares (each element at least its fixed-size part in
//! binary files, two characters per value in ASCII ones); a count the data does not fill is an error naming the
//! element and how many were read; out-of-range or negative indices, NaN or infinite coordinates, and faces of
//! fewer than 3 vertices are errors naming the face or vertex. NaN or infinite vertex normals (some exporters
//! write them at degenerate vertices) are replaced by the geometric normal of the vertex's faces, with one warning
//! naming the file and the count, as pbrt renders such files.

use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{BeginList, ElementDef, Encoding, Header, PropertyAccess, PropertyType, ScalarType};
use prism_core::error::{PrismError, Result};
use prism_core::mesh::MeshData;
use std::io::Cursor;
use std::path::Path;

/// One vertex as read (attributes the file lacks stay 0).
#[derive(Default)]
struct Vertex {
    p: [f64; 3],
    n: [f64; 3],
    uv: [f64; 2],
}

impl Vertex {
    fn set(&mut self, name: &str, v: f64) {
        match name {
            "x" => self.p[0] = v,
            "y" => self.p[1] = v,
            "z" => self.p[2] = v,
            "nx" => self.n[0] = v,
            "ny" => self.n[1] = v,
            "nz" => self.n[2] = v,
            "u" | "s" | "texture_u" | "texture_s" => self.uv[0] = v,
            "v" | "t" | "texture_v" | "texture_t" => self.uv[1] = v,
            _ => {}
        }
    }
}

use ply_rs_bw::ply::PropertyAccessResult as Set;

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex::default()
    }
    fn set_float(&mut self, name: &str, v: f32) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_double(&mut self, name: &str, v: f64) -> Set {
        self.set(name, v);
        Set::Set
    }
    fn set_char(&mut self, name: &str, v: i8) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_uchar(&mut self, name: &str, v: u8) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_short(&mut self, name: &str, v: i16) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_ushort(&mut self, name: &str, v: u16) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_int(&mut self, name: &str, v: i32) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
    fn set_uint(&mut self, name: &str, v: u32) -> Set {
        self.set(name, v as f64);
        Set::Set
    }
}

/// One face: its vertex indices (negative ones kept as such, to be reported).
#[derive(Default)]
struct Face {
    ints: Vec<i32>,
    uints: Vec<u32>,
    other: Vec<i64>,
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl Face {
    fn indices(&self) -> impl Iterator<Item = i64> + '_ {
        self.ints
            .iter()
            .map(|&i| i as i64)
            .chain(self.uints.iter().map(|&i| i as i64))
            .chain(self.other.iter().copied())
    }
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Face::default()
    }
    fn begin_list_int(&mut self, name: &str, _len: usize) -> BeginList<'_, i32> {
        if is_index_list(name) { BeginList::Fill(&mut self.ints) } else { BeginList::UseSetter }
    }
    fn begin_list_uint(&mut self, name: &str, _len: usize) -> BeginList<'_, u32> {
        if is_index_list(name) { BeginList::Fill(&mut self.uints) } else { BeginList::UseSetter }
    }
    fn set_list_short(&mut self, name: &str, v: Vec<i16>) -> Set {
        if is_index_list(name) {
            self.other = v.into_iter().map(|i| i as i64).collect();
        }
        Set::Set
    }
    fn set_list_ushort(&mut self, name: &str, v: Vec<u16>) -> Set {
        if is_index_list(name) {
            self.other = v.into_iter().map(|i| i as i64).collect();
        }
        Set::Set
    }
    fn set_list_char(&mut self, name: &str, v: Vec<i8>) -> Set {
        if is_index_list(name) {
            self.other = v.into_iter().map(|i| i as i64).collect();
        }
        Set::Set
    }
    fn set_list_uchar(&mut self, name: &str, v: Vec<u8>) -> Set {
        if is_index_list(name) {
            self.other = v.into_iter().map(|i| i as i64).collect();
        }
        Set::Set
    }
    fn set_list_int(&mut self, _name: &str, _v: Vec<i32>) -> Set {
        Set::Ignored
    }
    fn set_list_uint(&mut self, _name: &str, _v: Vec<u32>) -> Set {
        Set::Ignored
    }
}

/// An element nobody reads (edges, materials ...): parsed past.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The fewest bytes one element of `e` can take in the file.
fn min_element_bytes(e: &ElementDef, encoding: Encoding) -> u64 {
    e.properties
        .values()
        .map(|p| match (&p.data_type, encoding) {
            // A number and a separator.
            (_, Encoding::Ascii) => 2,
            (PropertyType::Scalar(t), _) => scalar_size(t),
            // An empty list is just its count.
            (PropertyType::List(c, _), _) => scalar_size(c),
        })
        .sum()
}

/// A header error in Prism's words: the crate's message carries its parser's Debug structures and the offending
/// line's text, neither of which belongs in a one-line error.
fn header_error(e: &ply_rs_bw::parser::ParseError) -> String {
    let text = one_line(e);
    let line = text.strip_prefix("Line ").and_then(|r| r.split(':').next()).and_then(|n| n.trim().parse::<u64>().ok());
    match line {
        Some(n) => format!(
            "line {n} is not a PLY header line (`format ascii|binary_little_endian|binary_big_endian 1.0`, \
             `element NAME COUNT`, `property TYPE NAME`, `property list TYPE TYPE NAME`, `comment ...`, `end_header`; \
             TYPE is char, uchar, short, ushort, int, uint, float, double or a sized name such as float32)"
        ),
        // Messages without a line (a missing `ply` magic, the end of the file) are short and plain.
        None => text.split(" Error:").next().unwrap_or(&text).to_string(),
    }
}

/// The crate's (multi-line) error as one line.
fn one_line(e: &ply_rs_bw::parser::ParseError) -> String {
    e.to_string().split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Read a PLY file into a mesh (local frame; the file name as the mesh name).
pub fn load_ply(path: &Path) -> Result<MeshData> {
    let bytes = prism_core::io::read_regular(path, "PLY file")?;
    let mesh = parse_ply(&bytes, path)?;
    Ok(mesh)
}

/// Parse PLY bytes; `path` names the file in errors.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<MeshData> {
    let err = |m: String| PrismError::format(path, m);
    let mut reader = Reader::new(Cursor::new(bytes));
    let header: Header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| err(format!("bad PLY header: {}", header_error(&e))))?;
    let after_header = bytes.len() as u64 - reader.get_ref().position();
    // Everything the header declares must fit in the bytes that follow it, before anything is allocated.
    let mut needed: u64 = 0;
    for e in header.elements.values() {
        // An element without properties takes no bytes, so its count is bounded by nothing the file holds.
        if e.properties.is_empty() && e.count > 0 {
            return Err(err(format!("the `{}` element has no properties but a count of {}", e.name, e.count)));
        }
        let per = min_element_bytes(e, header.encoding);
        needed = (e.count as u64).checked_mul(per).and_then(|b| needed.checked_add(b)).unwrap_or(u64::MAX);
    }
    if needed > after_header {
        let counts: Vec<String> = header.elements.values().map(|e| format!("{} {}", e.count, e.name)).collect();
        return Err(err(format!(
            "the header declares {} elements, which need at least {needed} bytes, but only {after_header} bytes \
             follow the header (truncated file, or a header that lies about its counts)",
            counts.join(" and ")
        )));
    }
    let vertex_def = header.elements.get("vertex").ok_or_else(|| err("no `vertex` element".into()))?;
    let has = |names: &[&str]| names.iter().all(|n| vertex_def.properties.contains_key(*n));
    if !has(&["x", "y", "z"]) {
        return Err(err("the `vertex` element has no x, y, z properties".into()));
    }
    let has_normals = has(&["nx", "ny", "nz"]);
    let has_uvs =
        has(&["u", "v"]) || has(&["s", "t"]) || has(&["texture_u", "texture_v"]) || has(&["texture_s", "texture_t"]);
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    let mut face_seen = false;
    for (name, def) in &header.elements {
        let short = |e: ply_rs_bw::parser::ParseError, _done: usize| {
            err(format!("`{name}` element data (the header declares {}): {}", def.count, one_line(&e)))
        };
        match name.as_str() {
            "vertex" => {
                vertices = Parser::<Vertex>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| short(e, 0))?;
            }
            "face" => {
                if !def.properties.keys().any(|k| is_index_list(k)) {
                    return Err(err("the `face` element has no `vertex_indices` list".into()));
                }
                face_seen = true;
                faces = Parser::<Face>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| short(e, 0))?;
            }
            _ => {
                Parser::<Skip>::new().read_payload_for_element(&mut reader, def, &header).map_err(|e| short(e, 0))?;
            }
        }
    }
    if !face_seen {
        return Err(err("no `face` element: a point cloud is not a surface".into()));
    }
    let n = vertices.len();
    let mut positions = Vec::with_capacity(n);
    let mut normals = Vec::with_capacity(if has_normals { n } else { 0 });
    let mut uvs = Vec::with_capacity(if has_uvs { n } else { 0 });
    // Vertices whose normal is NaN or infinite: given the geometric normal of their faces once those are read.
    let mut bad_normals = Vec::new();
    for (i, v) in vertices.iter().enumerate() {
        let p = Vec3::new(v.p[0] as f32, v.p[1] as f32, v.p[2] as f32);
        if !p.is_finite() {
            return Err(err(format!("vertex {i} has a NaN or infinite coordinate {:?}", v.p)));
        }
        positions.push(p);
        if has_normals {
            let nn = Vec3::new(v.n[0] as f32, v.n[1] as f32, v.n[2] as f32);
            if !nn.is_finite() {
                bad_normals.push(i);
            }
            normals.push(nn);
        }
        if has_uvs {
            let uv = Vec2::new(v.uv[0] as f32, 1.0 - v.uv[1] as f32);
            if !uv.is_finite() {
                return Err(err(format!("vertex {i} has NaN or infinite texture coordinates {:?}", v.uv)));
            }
            uvs.push(uv);
        }
    }
    drop(vertices);
    let mut indices = Vec::with_capacity(faces.len());
    let mut poly: Vec<u32> = Vec::with_capacity(8);
    for (f, face) in faces.iter().enumerate() {
        poly.clear();
        for i in face.indices() {
            if i < 0 || i >= n as i64 {
                return Err(err(format!("face {f} refers to vertex {i}, but there are {n} vertices")));
            }
            poly.push(i as u32);
        }
        if poly.len() < 3 {
            return Err(err(format!("face {f} has {} vertices (at least 3 needed)", poly.len())));
        }
        for k in 1..poly.len() - 1 {
            indices.push([poly[0], poly[k], poly[k + 1]]);
        }
    }
    if !bad_normals.is_empty() {
        geometric_normals_at(&bad_normals, &positions, &indices, &mut normals);
        prism_core::error::warn(&format!(
            "{}: {} vertex normal(s) NaN or infinite (the first: vertex {}), replaced by the geometric normal of \
             their faces",
            path.display(),
            bad_normals.len(),
            bad_normals[0]
        ));
    }
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "ply".into());
    Ok(MeshData { name, positions, normals, uvs, indices, tangents: vec![] })
}

/// Set the normals of the vertices `bad` to the area-weighted mean of the geometric normals (by winding) of the
/// triangles around them; a vertex on no triangle, or only on degenerate ones, gets +z (it shades nothing).
fn geometric_normals_at(bad: &[usize], positions: &[Vec3], indices: &[[u32; 3]], normals: &mut [Vec3]) {
    let mut sum: std::collections::HashMap<u32, glam::DVec3> =
        bad.iter().map(|&i| (i as u32, glam::DVec3::ZERO)).collect();
    for t in indices {
        if !t.iter().any(|v| sum.contains_key(v)) {
            continue;
        }
        let [a, b, c] = t.map(|v| positions[v as usize].as_dvec3());
        // Twice the area times the unit normal: area-weighted.
        let n = (b - a).cross(c - a);
        for v in t {
            if let Some(s) = sum.get_mut(v) {
                *s += n;
            }
        }
    }
    for (v, s) in sum {
        let n = s.normalize_or_zero().as_vec3();
        normals[v as usize] = if n == Vec3::ZERO || !n.is_finite() { Vec3::Z } else { n };
    }
}
