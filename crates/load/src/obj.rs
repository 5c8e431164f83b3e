//! Wavefront OBJ import through tobj: triangulated, one index per vertex, each OBJ model (one material each)
//! becomes one part. The MTL file's diffuse (Kd), specular (Ks), shininess (Ns) and emission (Ke) map onto Prism's
//! physically based material (Kd is an albedo; Ka is ignored because ambient light is not physical); a part with
//! a non-zero Ke becomes an area light of that radiance. The MTL illumination models that ask for ray tracing
//! map onto Prism's delta lobes: `illum 3`/`5` make Ks a mirror reflectance, `illum 4`/`6`/`7`/`9` make the
//! surface a smooth dielectric with index Ni and transmittance Tf (1 when absent). Texture coordinates are flipped
//! to `v = 1 - v_obj` (OBJ's v points up the image, Prism's down; Mitsuba does the same).

use super::obj_check::{diagnose_mtl, diagnose_obj, mtl_line};
use glam::{Vec2, Vec3};
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::material::{Material, PhongParams};
use prism_core::mesh::MeshData;
use prism_core::texture::{ColorParam, ScalarParam};
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// One OBJ model: its mesh, the MTL material it uses (if the file has one) and its emission.
pub struct ObjPart {
    pub mesh: MeshData,
    pub material: Option<Material>,
    pub emission: Option<Vec3>,
}

/// Load every model of an OBJ file (and its MTL libraries, relative to it). A missing or broken MTL file is
/// reported on stderr and ignored; bad values in it are errors naming the MTL file and line.
pub fn load_obj(path: &Path) -> Result<Vec<ObjPart>> {
    let (file, _) = prism_core::io::open_regular(path, "mesh file")?;
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut std::io::BufReader::new(file), &mut bytes).map_err(|e| PrismError::io(path, e))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    parse_obj(&bytes, path, |mtl| {
        let p = dir.join(mtl);
        match prism_core::io::open_regular(&p, "material library") {
            Ok((f, _)) => {
                let mut b = Vec::new();
                std::io::Read::read_to_end(&mut std::io::BufReader::new(f), &mut b).ok().map(|_| (p, b))
            }
            Err(_) => None,
        }
    })
}

/// Parse OBJ text (`name` names it in errors); `mtl` returns the path and bytes of a material library named by an
/// `mtllib` line, or `None` if it cannot be read. Never touches the disk itself.
pub fn parse_obj(obj: &[u8], name: &Path, mtl: impl Fn(&Path) -> Option<(PathBuf, Vec<u8>)>) -> Result<Vec<ObjPart>> {
    let at = |line: usize, message: String| PrismError::Parse {
        pos: SourcePos { file: name.to_path_buf(), line, col: 1 },
        message,
    };
    let text = String::from_utf8_lossy(obj);
    // Every line is checked before tobj sees it: tobj 4.0.5 overflows on huge face indices (and would index with
    // the wrapped value in release builds), and its errors name no line.
    if let Some((line, message)) = diagnose_obj(&text) {
        return Err(at(line, message));
    }
    // Where tobj fails anyway, or returns values Prism rejects, the first offending line is named if there is one.
    let diagnose = |fallback: String| match diagnose_obj(&text) {
        Some((line, message)) => at(line, message),
        None => PrismError::format(name, fallback),
    };
    let libraries: RefCell<Vec<(PathBuf, String)>> = RefCell::new(Vec::new());
    // A library tobj cannot read safely is an error at its line (not handed to tobj, which panics on it).
    let mtl_problem: RefCell<Option<PrismError>> = RefCell::new(None);
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let (models, materials) = tobj::load_obj_buf(&mut std::io::Cursor::new(obj), &opts, |p| match mtl(p) {
        Some((path, bytes)) => {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            if let Some((line, message)) = diagnose_mtl(&text) {
                mtl_problem
                    .borrow_mut()
                    .get_or_insert(PrismError::Parse { pos: SourcePos { file: path, line, col: 1 }, message });
                return Err(tobj::LoadError::MaterialParseError);
            }
            let r = tobj::load_mtl_buf(&mut std::io::Cursor::new(&bytes));
            libraries.borrow_mut().push((path, text));
            r
        }
        None => Err(tobj::LoadError::OpenFileFailed),
    })
    .map_err(|e| diagnose(format!("cannot read OBJ: {e}")))?;
    if let Some(e) = mtl_problem.into_inner() {
        return Err(e);
    }
    let materials = match materials {
        Ok(m) => m,
        Err(e) => {
            prism_core::error::warn(&format!(
                "{}: material library not loaded ({e}); using the entity's material",
                name.display()
            ));
            Vec::new()
        }
    };
    let libraries = libraries.into_inner();
    let mtl_error = |material: &str, key: &str, message: String| {
        let place = libraries.iter().find(|(_, t)| {
            t.lines().any(|l| {
                let mut w = l.split_whitespace();
                w.next() == Some("newmtl") && w.collect::<Vec<_>>().join(" ") == material
            })
        });
        match place {
            Some((p, t)) => PrismError::Parse {
                pos: SourcePos { file: p.clone(), line: mtl_line(t, material, key), col: 1 },
                message,
            },
            None => PrismError::format(name, message),
        }
    };
    let mut parts = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
        if !finite(&m.positions) || !finite(&m.normals) || !finite(&m.texcoords) {
            return Err(diagnose(format!("model '{}': a vertex has a non-finite coordinate", model.name)));
        }
        let positions: Vec<Vec3> = m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        let n = positions.len();
        let normals: Vec<Vec3> = if m.normals.len() == 3 * n {
            m.normals.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect()
        } else {
            vec![]
        };
        let uvs: Vec<Vec2> = if m.texcoords.len() == 2 * n {
            m.texcoords.chunks_exact(2).map(|p| Vec2::new(p[0], 1.0 - p[1])).collect()
        } else {
            vec![]
        };
        let indices: Vec<[u32; 3]> = m.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        if let Some(bad) = indices.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(diagnose(format!("model '{}': vertex index {bad} out of range", model.name)));
        }
        let (material, emission) = match m.material_id.and_then(|id| materials.get(id)) {
            Some(mtl) => {
                let color = |v: Option<[f32; 3]>, key: &str| -> Result<Vec3> {
                    let c = v.map(Vec3::from).unwrap_or(Vec3::ZERO);
                    if c.is_finite() && c.min_element() >= 0.0 {
                        Ok(c)
                    } else {
                        Err(mtl_error(
                            &mtl.name,
                            key,
                            format!("{key} of material '{}' must be finite and non-negative, got {c}", mtl.name),
                        ))
                    }
                };
                let (kd, ks, ke) = (color(mtl.diffuse, "Kd")?, color(mtl.specular, "Ks")?, color(mtl.emissive, "Ke")?);
                let ns = mtl.shininess.unwrap_or(1.0);
                if !(ns.is_finite() && ns >= 0.0) {
                    return Err(mtl_error(
                        &mtl.name,
                        "Ns",
                        format!("Ns of material '{}' must be finite and non-negative, got {ns}", mtl.name),
                    ));
                }
                let mut p = PhongParams {
                    diffuse: ColorParam::Const(kd),
                    specular: ColorParam::Const(ks),
                    exponent: ScalarParam::Const(ns),
                    ..PhongParams::default()
                };
                match mtl.illumination_model {
                    Some(3 | 5) => {
                        p.reflective = p.specular;
                        p.specular = ColorParam::ZERO;
                    }
                    Some(4 | 6 | 7 | 9) => {
                        let tf = match mtl.unknown_param.get("Tf") {
                            None => Vec3::ONE,
                            Some(t) => {
                                parse_rgb(t).filter(|c| c.is_finite() && c.min_element() >= 0.0).ok_or_else(|| {
                                    mtl_error(
                                        &mtl.name,
                                        "Tf",
                                        format!(
                                            "Tf of material '{}' must be a finite non-negative colour, got `{}`",
                                            mtl.name,
                                            prism_core::error::printable(t)
                                        ),
                                    )
                                })?
                            }
                        };
                        let ior = mtl.optical_density.unwrap_or(1.5);
                        if !(ior.is_finite() && ior > 0.0) {
                            return Err(mtl_error(
                                &mtl.name,
                                "Ni",
                                format!("Ni of material '{}' must be a finite positive index, got {ior}", mtl.name),
                            ));
                        }
                        p.transparent = ColorParam::Const(tf);
                        p.ior = ior;
                        p.specular = ColorParam::ZERO;
                    }
                    _ => {}
                }
                let mat = Material::phong(&mtl.name, p);
                (Some(mat), (ke != Vec3::ZERO).then_some(ke))
            }
            None => (None, None),
        };
        parts.push(ObjPart {
            mesh: MeshData { name: model.name, positions, normals, uvs, indices, tangents: vec![] },
            material,
            emission,
        });
    }
    if parts.is_empty() {
        return Err(PrismError::format(name, "OBJ file holds no triangles"));
    }
    Ok(parts)
}

/// "r g b" or "v" (grey) as a colour.
fn parse_rgb(s: &str) -> Option<Vec3> {
    let v: Vec<f32> = s.split_whitespace().map(str::parse).collect::<Result<_, _>>().ok()?;
    match v.as_slice() {
        [g] => Some(Vec3::splat(*g)),
        [r, g, b] => Some(Vec3::new(*r, *g, *b)),
        _ => None,
    }
}
