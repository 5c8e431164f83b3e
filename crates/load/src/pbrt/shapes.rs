//! pbrt shapes as RON entities (one per `Shape`, with the current transform as a `Matrix`, the current material,
//! area light and the shape's alpha):
//!
//! | pbrt | Prism |
//! |---|---|
//! | `plymesh` `filename` | `Mesh(path: ...)`, loaded once per file and shared by every use |
//! | `trianglemesh` `P`, `indices`, `N`, `uv`/`st` | an inline mesh of the `meshes` table (stored once), `TriangleMesh(name)` |
//! | `bilinearmesh` (v4) | two triangles per patch |
//! | `sphere` `radius` | `Sphere(radius)` (partial spheres are made whole, with a warning) |
//! | `disk` `height`, `radius`, `innerradius`, `phimax` | a triangle ring (or its `phimax` sector), 64 segments a turn, pbrt's uv |
//! | `cylinder` `radius`, `zmin`, `zmax`, `phimax` | a triangle tube (or its `phimax` part), 64 segments a turn, outward vertex normals, pbrt's uv |
//! | `loopsubdiv` | its control mesh (not subdivided, with a warning) |
//! | `alpha` (float or texture) | an alpha cut-out: pbrt-v3 cuts where alpha is 0 (`Mask` with a tiny cutoff), pbrt-v4 is stochastic (`Blend`) |
//! | cones, paraboloids, hyperboloids, curves, NURBS, height fields | left out, with a warning |
//!
//! **Orientation** (which side an area light emits from, and the outside of a glass object): pbrt turns each
//! triangle of a mesh with normals to face them, and otherwise flips the winding's side when
//! `ReverseOrientation` xor the transform mirrors; Prism takes the side of the world-space winding. Inline
//! meshes are rewound per triangle to pbrt's side; PLY meshes are reversed when the transform mirrors (meshes
//! with normals, assumed wound like them) or when `ReverseOrientation` xor a mirror (meshes without normals).

use super::Version;
use super::convert::{Converter, matrix_op, num, quote, short};
use super::materials::{INTERFACE, TexValue};
use super::params::{FloatParam, Params};
use glam::DVec3;
use prism_core::error::{PrismError, Result, SourcePos};
use std::fmt::Write as _;

fn bad(pos: &SourcePos, m: String) -> PrismError {
    PrismError::Parse { pos: pos.clone(), message: m }
}

/// Does a PLY file declare vertex normals? (Reads the header only, of a regular file; false when files are not read.)
fn ply_has_normals(c: &Converter, path: &std::path::Path) -> bool {
    use std::io::Read;
    if !c.read_files {
        return false;
    }
    let mut buf = vec![0u8; 8192];
    let n =
        prism_core::io::open_regular(path, "PLY file").ok().and_then(|(mut f, _)| f.read(&mut buf).ok()).unwrap_or(0);
    let text = String::from_utf8_lossy(&buf[..n]);
    let header = text.split("end_header").next().unwrap_or("");
    header.lines().any(|l| {
        let w: Vec<&str> = l.split_whitespace().collect();
        w.len() == 3 && w[0] == "property" && w[2] == "nx"
    })
}

/// An inline triangle mesh rewound to pbrt's orientation and stored in the `meshes` table; returns its name.
#[allow(clippy::too_many_arguments)]
fn inline_mesh(
    c: &mut Converter,
    p: &[[f64; 3]],
    tris: &[[u32; 3]],
    n: Option<&[[f64; 3]]>,
    uv: Option<&[[f64; 2]]>,
    mirror: bool,
    pos: &SourcePos,
) -> Result<String> {
    if let Some(i) = p.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        return Err(bad(pos, format!("vertex {i} is not finite: {:?}", p[i])));
    }
    let mut out = String::with_capacity(64 * p.len());
    out.push_str("(positions: [");
    for v in p {
        let _ = write!(out, "({}, {}, {}),", num(v[0]), num(v[1]), num(v[2]));
    }
    out.push_str("], indices: [");
    for t in tris {
        let [a, b, cc] = t.map(|i| DVec3::from_array(p[i as usize]));
        let winding = (b - a).cross(cc - a);
        let flip = match n {
            Some(n) => {
                let ns = t.iter().fold(DVec3::ZERO, |s, &i| s + DVec3::from_array(n[i as usize]));
                (winding.dot(ns) < 0.0) != mirror
            }
            None => c.reverse != mirror,
        };
        let t = if flip { [t[0], t[2], t[1]] } else { *t };
        let _ = write!(out, "({}, {}, {}),", t[0], t[1], t[2]);
    }
    out.push(']');
    if let Some(n) = n {
        out.push_str(", normals: [");
        for v in n {
            let v = if v.iter().all(|x| x.is_finite()) { *v } else { [0.0; 3] };
            let _ = write!(out, "({}, {}, {}),", num(v[0]), num(v[1]), num(v[2]));
        }
        out.push(']');
    }
    if let Some(uv) = uv {
        out.push_str(", uvs: [");
        for v in uv {
            let _ = write!(out, "({}, {}),", num(v[0]), num(1.0 - v[1]));
        }
        out.push(']');
    }
    out.push(')');
    let name = format!("mesh{}", c.next_id());
    c.meshes.insert(name.clone(), out);
    Ok(name)
}

/// A `curve` shape tessellated into an inline mesh (`curves.rs`); `None` when it has no segments to draw.
fn curve_mesh(c: &mut Converter, p: &Params, what: &str, mirror: bool, pos: &SourcePos) -> Result<Option<String>> {
    use super::curves::{CurveKind, MAX_CURVE_TRIANGLES, Segment, TRIANGLES_PER_SEGMENT, bezier_segments, tessellate};
    let at = |key: &str| p.pos_of(key).unwrap_or(pos.clone());
    let cp: Vec<DVec3> = p
        .vec3s("P")?
        .ok_or_else(|| bad(pos, format!("{what}: no \"point3 P\"")))?
        .into_iter()
        .map(DVec3::from_array)
        .collect();
    if let Some(i) = cp.iter().position(|v| !v.is_finite()) {
        return Err(bad(&at("P"), format!("{what}: control point {i} is not finite")));
    }
    let basis = p.string("basis")?.unwrap_or_else(|| "bezier".into());
    let degree = p.int("degree", 3)?;
    let kind = match p.string("type")?.as_deref() {
        None | Some("flat") => CurveKind::Flat,
        Some("cylinder") => CurveKind::Cylinder,
        Some("ribbon") => CurveKind::Ribbon,
        Some(other) => {
            return Err(bad(&at("type"), format!("{what}: unknown curve type \"{other}\" (flat, cylinder, ribbon)")));
        }
    };
    let width = p.float("width", 1.0)?;
    let (w0, w1) = (p.float("width0", width)?, p.float("width1", width)?);
    if !(w0.is_finite() && w1.is_finite() && w0 >= 0.0 && w1 >= 0.0) {
        return Err(bad(pos, format!("{what}: widths must be finite and >= 0, got {w0} and {w1}")));
    }
    let beziers =
        bezier_segments(&cp, &basis, degree.clamp(0, 8) as usize).map_err(|e| bad(pos, format!("{what}: {e}")))?;
    let normals = if kind == CurveKind::Ribbon {
        let n = p.vec3s("N")?.ok_or_else(|| bad(pos, format!("{what}: a ribbon needs \"normal N\"")))?;
        if n.len() != beziers.len() + 1 {
            return Err(bad(
                &at("N"),
                format!(
                    "{what}: a ribbon of {} segments needs {} normals, got {}",
                    beziers.len(),
                    beziers.len() + 1,
                    n.len()
                ),
            ));
        }
        Some(n.into_iter().map(DVec3::from_array).collect::<Vec<_>>())
    } else {
        None
    };
    p.has("splitdepth");
    c.curve_triangles = c.curve_triangles.saturating_add(beziers.len().saturating_mul(TRIANGLES_PER_SEGMENT));
    if c.curve_triangles > MAX_CURVE_TRIANGLES {
        return Err(bad(
            pos,
            format!("{what}: the file's curves would tessellate into more than {MAX_CURVE_TRIANGLES} triangles"),
        ));
    }
    let n = beziers.len() as f64;
    let segments: Vec<Segment> = beziers
        .iter()
        .enumerate()
        .map(|(i, cp)| Segment {
            cp: *cp,
            width: [w0 + (w1 - w0) * i as f64 / n, w0 + (w1 - w0) * (i + 1) as f64 / n],
            normal: normals.as_ref().map(|ns| [ns[i], ns[i + 1]]),
        })
        .collect();
    let (mut pts, mut nrm, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    tessellate(&segments, kind, &mut pts, &mut nrm, &mut tris);
    if tris.is_empty() {
        c.warn(format!("{what} without segments is left out"));
        return Ok(None);
    }
    Ok(Some(inline_mesh(c, &pts, &tris, Some(&nrm), None, mirror, pos)?))
}

/// Check per-vertex arrays and indices of a mesh shape.
fn check_mesh(
    np: usize,
    idx: &[u32],
    per: usize,
    n: &Option<Vec<[f64; 3]>>,
    uv: &Option<Vec<[f64; 2]>>,
    what: &str,
    pos: &SourcePos,
) -> Result<()> {
    if !idx.len().is_multiple_of(per) {
        return Err(bad(pos, format!("{what}: {} indices is not a multiple of {per}", idx.len())));
    }
    if let Some((k, i)) = idx.iter().enumerate().find(|(_, i)| **i as usize >= np) {
        return Err(bad(pos, format!("{what}: index {k} ({i}) is out of range: there are {np} vertices")));
    }
    if let Some(n) = n
        && n.len() != np
    {
        return Err(bad(pos, format!("{what}: {} normals for {np} vertices", n.len())));
    }
    if let Some(uv) = uv
        && uv.len() != np
    {
        return Err(bad(pos, format!("{what}: {} uvs for {np} vertices", uv.len())));
    }
    Ok(())
}

fn uvs(p: &Params) -> Result<Option<Vec<[f64; 2]>>> {
    let key = if p.has("uv") { "uv" } else { "st" };
    p.vec2s(key)
}

/// A `Shape` directive.
pub fn shape(c: &mut Converter, ty: &str, p: &Params, pos: &SourcePos) -> Result<()> {
    let mark_all = |p: &Params| {
        for q in &p.list {
            p.has(&q.name);
        }
    };
    if c.material == INTERFACE {
        mark_all(p);
        c.warn("shapes with the \"interface\" material (medium boundaries) are left out");
        return Ok(());
    }
    let det = c.ctm.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(bad(pos, format!("Shape \"{ty}\": the current transform is singular")));
    }
    let mirror = det < 0.0;
    let what = format!("Shape \"{ty}\"");
    let shape = match ty {
        "plymesh" => {
            let f = p.string("filename")?.ok_or_else(|| bad(pos, format!("{what}: no \"string filename\"")))?;
            let path = c.resolve(&f);
            if !path.is_file() {
                return Err(bad(
                    &p.pos_of("filename").unwrap_or(pos.clone()),
                    format!("{what}: file not found: {}", path.display()),
                ));
            }
            for q in ["displacement", "edgelength"] {
                if p.has(q) {
                    c.warn(format!("plymesh \"{q}\" is ignored"));
                }
            }
            let reverse = if ply_has_normals(c, &path) { mirror } else { c.reverse != mirror };
            format!("Mesh(path: {}, reverse: {reverse})", quote(&c.ron_path(&path)))
        }
        "trianglemesh" | "bilinearmesh" | "loopsubdiv" => {
            let pts = p.vec3s("P")?.ok_or_else(|| bad(pos, format!("{what}: no \"point3 P\"")))?;
            let per = if ty == "bilinearmesh" { 4 } else { 3 };
            let idx = match p.indices("indices")? {
                Some(i) => i,
                None if pts.len() == per => (0..per as u32).collect(),
                None => return Err(bad(pos, format!("{what}: no \"integer indices\""))),
            };
            let n = if ty == "loopsubdiv" { None } else { p.vec3s("N")? };
            let uv = if ty == "loopsubdiv" { None } else { uvs(p)? };
            check_mesh(pts.len(), &idx, per, &n, &uv, &what, pos)?;
            if ty == "loopsubdiv" {
                c.warn("loopsubdiv shapes are rendered as their control mesh (not subdivided)");
                p.has("levels");
            }
            for q in ["S", "faceIndices", "emission"] {
                p.has(q);
            }
            let tris: Vec<[u32; 3]> = if per == 4 {
                idx.chunks_exact(4).flat_map(|q| [[q[0], q[1], q[3]], [q[0], q[3], q[2]]]).collect()
            } else {
                idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
            };
            if tris.is_empty() {
                c.warn(format!("{what} without triangles is left out"));
                return Ok(());
            }
            let name = inline_mesh(c, &pts, &tris, n.as_deref(), uv.as_deref(), mirror, pos)?;
            format!("TriangleMesh({})", quote(&name))
        }
        "sphere" => {
            let r = p.float("radius", 1.0)?;
            if !(r > 0.0 && r.is_finite()) {
                return Err(bad(pos, format!("{what}: radius must be positive, got {r}")));
            }
            let partial = p.float("zmin", -r)? > -r || p.float("zmax", r)? < r || p.float("phimax", 360.0)? < 360.0;
            if partial {
                c.warn("partial spheres (zmin, zmax, phimax) are rendered whole");
            }
            if c.reverse && c.area.is_some() {
                c.warn("ReverseOrientation on a sphere area light is ignored (spheres emit outwards)");
            }
            format!("Sphere(radius: {})", num(r))
        }
        "disk" => {
            let (h, r, ri) = (p.float("height", 0.0)?, p.float("radius", 1.0)?, p.float("innerradius", 0.0)?);
            if !(r > 0.0 && ri >= 0.0 && ri < r) {
                return Err(bad(pos, format!("{what}: need 0 <= innerradius < radius, got {ri} and {r}")));
            }
            let phimax = phi_max(p, &what, pos)?;
            // pbrt's disk: (r cos phi, r sin phi, height) for phi in [0, phimax]; u = phi / phimax, v = 1 at the
            // inner radius; its normal is +z.
            let k = segments(phimax);
            let (mut pts, mut uv, mut tris) = (Vec::new(), Vec::new(), Vec::new());
            for i in 0..=k {
                let phi = phimax * i as f64 / k as f64;
                for (rad, v) in [(r, 0.0), (ri.max(r * 1e-6), 1.0)] {
                    pts.push([rad * phi.cos(), rad * phi.sin(), h]);
                    uv.push([i as f64 / k as f64, v]);
                }
            }
            for i in 0..k as u32 {
                let (o0, i0, o1, i1) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
                tris.push([o0, o1, i1]);
                tris.push([o0, i1, i0]);
            }
            let name = inline_mesh(c, &pts, &tris, None, Some(&uv), mirror, pos)?;
            format!("TriangleMesh({})", quote(&name))
        }
        "cylinder" => {
            let (r, z0, z1) = (p.float("radius", 1.0)?, p.float("zmin", -1.0)?, p.float("zmax", 1.0)?);
            if !(r > 0.0 && r.is_finite() && z0.is_finite() && z1.is_finite() && z0 != z1) {
                return Err(bad(pos, format!("{what}: need radius > 0 and zmin != zmax, got {r}, {z0}, {z1}")));
            }
            let (z0, z1) = (z0.min(z1), z0.max(z1));
            let phimax = phi_max(p, &what, pos)?;
            // pbrt's cylinder: (r cos phi, r sin phi, z), u = phi / phimax, v = (z - zmin) / (zmax - zmin), the
            // normal outwards; smooth vertex normals over 64 segments a turn.
            let k = segments(phimax);
            let (mut pts, mut nrm, mut uv, mut tris) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for i in 0..=k {
                let phi = phimax * i as f64 / k as f64;
                for (z, v) in [(z0, 0.0), (z1, 1.0)] {
                    pts.push([r * phi.cos(), r * phi.sin(), z]);
                    nrm.push([phi.cos(), phi.sin(), 0.0]);
                    uv.push([i as f64 / k as f64, v]);
                }
            }
            for i in 0..k as u32 {
                let (a0, a1, b0, b1) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
                // Counter-clockwise seen from outside: the geometric normal agrees with the vertex normals.
                tris.push([a0, b0, b1]);
                tris.push([a0, b1, a1]);
            }
            let name = inline_mesh(c, &pts, &tris, Some(&nrm), Some(&uv), mirror, pos)?;
            format!("TriangleMesh({})", quote(&name))
        }
        "curve" => {
            let Some(name) = curve_mesh(c, p, &what, mirror, pos)? else { return Ok(()) };
            format!("TriangleMesh({})", quote(&name))
        }
        other => {
            mark_all(p);
            c.warn(format!("Shape \"{other}\" is not supported and is left out"));
            return Ok(());
        }
    };
    let mut text = format!(
        "(name: {}, transform: [{}], shape: {shape}, material: {}",
        quote(&format!("{}:{} {what}", short(&pos.file), pos.line)),
        matrix_op(&c.ctm),
        quote(&c.material)
    );
    if let Some(a) = &c.area {
        if c.defining_object() {
            c.warn("area lights inside object definitions are ignored (as in pbrt)");
        } else {
            let _ = write!(
                text,
                ", light: Area(radiance: {}, two_sided: {}",
                super::convert::tuple3(a.radiance),
                a.two_sided
            );
            if let Some(t) = &a.texture {
                let _ = write!(text, ", texture: {}", quote(t));
            }
            text.push(')');
        }
    }
    if let Some(alpha) = alpha(c, p, pos)? {
        let _ = write!(text, ", alpha: {alpha}");
    }
    text.push(')');
    c.push_entity(text);
    Ok(())
}

/// The shape's `alpha` as a RON `AlphaDesc`, or `None` when it is opaque.
fn alpha(c: &mut Converter, p: &Params, pos: &SourcePos) -> Result<Option<String>> {
    p.has("shadowalpha");
    let mode = if c.version == Version::V3 { "Mask(cutoff: 1e-6)" } else { "Blend" };
    let value = match p.float_or_texture("alpha")? {
        None => return Ok(None),
        Some(FloatParam::Value(a)) => TexValue::Const([a; 3]),
        Some(FloatParam::Texture(t)) => c.tex_values.get(&(true, t.clone())).cloned().ok_or_else(|| {
            bad(&p.pos_of("alpha").unwrap_or(pos.clone()), format!("alpha: unknown float texture \"{t}\""))
        })?,
    };
    Ok(match value {
        TexValue::Const(a) if a[0] >= 1.0 => None,
        TexValue::Const(a) => Some(format!("(factor: {}, mode: {mode})", num(a[0].clamp(0.0, 1.0)))),
        TexValue::Image { ron, scale } => {
            Some(format!("(texture: {}, factor: {}, mode: {mode})", quote(&ron), num(scale[0].clamp(0.0, 1.0))))
        }
        TexValue::Mix { a, b, .. } => {
            c.warn("a checkerboard alpha is approximated by its mean");
            Some(format!("(factor: {}, mode: {mode})", num(((a[0] + b[0]) / 2.0).clamp(0.0, 1.0))))
        }
    })
}

/// `phimax` in radians, checked to lie in (0, 360] degrees.
fn phi_max(p: &Params, what: &str, pos: &SourcePos) -> Result<f64> {
    let d = p.float("phimax", 360.0)?;
    if !(d > 0.0 && d <= 360.0) {
        return Err(bad(pos, format!("{what}: phimax must be in (0, 360] degrees, got {d}")));
    }
    Ok(d.to_radians())
}

/// Segments for an arc of `phi` radians: 64 a full turn, at least 4.
fn segments(phi: f64) -> usize {
    ((64.0 * phi / std::f64::consts::TAU).ceil() as usize).max(4)
}
