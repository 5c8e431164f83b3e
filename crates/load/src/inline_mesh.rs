//! The RON scene's inline meshes (`meshes: {"name": (positions, indices, normals, uvs)}`, referred to by
//! `TriangleMesh("name")`) and entity alpha cut-outs, validated into the resource tables. Errors name the file
//! and the mesh or entity.

use super::schema::{AlphaDesc, AlphaModeDesc, MeshDesc};
use glam::{Vec2, Vec3};
use prism_core::alpha::{AlphaMask, AlphaMode};
use prism_core::error::{PrismError, Result};
use prism_core::mesh::{MeshData, MeshStore};
use prism_core::texture::{Texture, TextureSet};
use prism_engine::components::MeshHandle;
use std::collections::{BTreeMap, HashMap};

/// Validate and store every inline mesh once; returns name -> handle.
pub(super) fn load_meshes(
    descs: &BTreeMap<String, MeshDesc>,
    file: &str,
    store: &mut MeshStore,
) -> Result<HashMap<String, MeshHandle>> {
    let mut out = HashMap::new();
    for (name, d) in descs {
        let err = |m: String| PrismError::scene(format!("{file}: mesh '{name}'"), m);
        let n = d.positions.len();
        if let Some(i) = d.positions.iter().position(|p| !Vec3::from(*p).is_finite()) {
            return Err(err(format!("position {i} is NaN or infinite: {:?}", d.positions[i])));
        }
        if !d.normals.is_empty() && d.normals.len() != n {
            return Err(err(format!("{} normals for {n} positions (give one per position, or none)", d.normals.len())));
        }
        if !d.uvs.is_empty() && d.uvs.len() != n {
            return Err(err(format!("{} uvs for {n} positions (give one per position, or none)", d.uvs.len())));
        }
        if let Some(i) = d.normals.iter().position(|p| !Vec3::from(*p).is_finite()) {
            return Err(err(format!("normal {i} is NaN or infinite")));
        }
        if let Some(i) = d.uvs.iter().position(|p| !Vec2::from(*p).is_finite()) {
            return Err(err(format!("uv {i} is NaN or infinite")));
        }
        if let Some((t, tri)) = d.indices.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= n)) {
            return Err(err(format!("triangle {t} {tri:?} refers to a vertex beyond the {n} positions")));
        }
        if d.indices.is_empty() {
            return Err(err("has no triangles".into()));
        }
        let mesh = MeshData {
            name: name.clone(),
            positions: d.positions.iter().map(|p| Vec3::from(*p)).collect(),
            normals: d.normals.iter().map(|p| Vec3::from(*p)).collect(),
            uvs: d.uvs.iter().map(|p| Vec2::from(*p)).collect(),
            indices: d.indices.clone(),
            tangents: vec![],
        };
        out.insert(name.clone(), store.add(mesh));
    }
    Ok(out)
}

/// An entity's alpha cut-out; `textures` maps texture names to the scene's texture table.
pub(super) fn alpha_mask(
    a: &AlphaDesc,
    textures: &HashMap<String, u32>,
    set: &TextureSet,
    ctx: &str,
) -> Result<AlphaMask> {
    if !(a.factor.is_finite() && (0.0..=1.0).contains(&a.factor)) {
        return Err(PrismError::scene(ctx, format!("alpha factor must be in [0, 1], got {}", a.factor)));
    }
    let mode = match a.mode {
        AlphaModeDesc::Blend => AlphaMode::Blend,
        AlphaModeDesc::Mask { cutoff } if cutoff.is_finite() => AlphaMode::Mask { cutoff },
        AlphaModeDesc::Mask { cutoff } => {
            return Err(PrismError::scene(ctx, format!("alpha cutoff must be finite, got {cutoff}")));
        }
    };
    let texture = match &a.texture {
        None => None,
        Some(name) => {
            let id =
                textures.get(name).ok_or_else(|| PrismError::scene(ctx, format!("alpha: unknown texture '{name}'")))?;
            match set.get(*id) {
                Texture::Image(m) => Some(m.clone()),
                Texture::Solid(_) | Texture::UvChecker { .. } => {
                    return Err(PrismError::scene(ctx, format!("alpha: texture '{name}' must be an image")));
                }
            }
        }
    };
    Ok(AlphaMask { texture, factor: a.factor, mode })
}

/// Reverse the winding of every triangle (the front face becomes the back).
pub(super) fn reverse_winding(mesh: &mut MeshData) {
    for t in &mut mesh.indices {
        t.swap(1, 2);
    }
}
