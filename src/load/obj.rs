//! Wavefront OBJ import through tobj: triangulated, one index per vertex, each OBJ model (one material each)
//! becomes one part. The MTL file's diffuse (Kd), specular (Ks), shininess (Ns) and emission (Ke) map onto Prism's
//! physically based material (Kd is an albedo; Ka is ignored because ambient light is not physical); a part with
//! a non-zero Ke becomes an area light of that radiance. The MTL illumination models that ask for ray tracing
//! map onto Prism's delta lobes: `illum 3`/`5` make Ks a mirror reflectance, `illum 4`/`6`/`7`/`9` make the
//! surface a smooth dielectric with index Ni and transmittance Tf (1 when absent). Texture coordinates are flipped
//! to `v = 1 - v_obj` (OBJ's v points up the image, Prism's down; Mitsuba does the same).

use crate::error::{PrismError, Result};
use crate::material::{Material, PhongParams};
use crate::mesh::MeshData;
use crate::texture::{ColorParam, ScalarParam};
use glam::{Vec2, Vec3};
use std::path::Path;

/// One OBJ model: its mesh, the MTL material it uses (if the file has one) and its emission.
pub struct ObjPart {
    pub mesh: MeshData,
    pub material: Option<Material>,
    pub emission: Option<Vec3>,
}

/// Load every model of an OBJ file. A missing or broken MTL file is reported on stderr and ignored.
pub fn load_obj(path: &Path) -> Result<Vec<ObjPart>> {
    if !path.is_file() {
        return Err(PrismError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, "mesh file not found")));
    }
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let (models, materials) =
        tobj::load_obj(path, &opts).map_err(|e| PrismError::format(path, format!("cannot read OBJ: {e}")))?;
    let materials = match materials {
        Ok(m) => m,
        Err(e) => {
            eprintln!("warning: {}: material library not loaded ({e}); using the entity's material", path.display());
            Vec::new()
        }
    };
    let mut parts = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
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
            return Err(PrismError::format(path, format!("model '{}': vertex index {bad} out of range", model.name)));
        }
        let (material, emission) = match m.material_id.and_then(|id| materials.get(id)) {
            Some(mtl) => {
                let c = |v: Option<[f32; 3]>| v.map(Vec3::from).unwrap_or(Vec3::ZERO);
                let mut p = PhongParams {
                    diffuse: ColorParam::Const(c(mtl.diffuse)),
                    specular: ColorParam::Const(c(mtl.specular)),
                    exponent: ScalarParam::Const(mtl.shininess.unwrap_or(1.0).max(0.0)),
                    ..PhongParams::default()
                };
                match mtl.illumination_model {
                    Some(3 | 5) => {
                        p.reflective = p.specular;
                        p.specular = ColorParam::ZERO;
                    }
                    Some(4 | 6 | 7 | 9) => {
                        let tf = mtl.unknown_param.get("Tf").and_then(|t| parse_rgb(t)).unwrap_or(Vec3::ONE);
                        p.transparent = ColorParam::Const(tf);
                        p.ior = mtl.optical_density.filter(|n| *n > 0.0).unwrap_or(1.5);
                        p.specular = ColorParam::ZERO;
                    }
                    _ => {}
                }
                let mat = Material::phong(&mtl.name, p);
                let ke = c(mtl.emissive);
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
        return Err(PrismError::format(path, "OBJ file holds no triangles"));
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
