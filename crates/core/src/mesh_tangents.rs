//! Per-vertex tangents of a triangle mesh by MikkTSpace (Mikkelsen 2008, through `bevy_mikktspace`, a safe Rust
//! port that reproduces the reference implementation), so that tangent-space normal maps baked by other tools
//! (Blender, xNormal, Substance; what glTF prescribes when a file has no tangents) look right. Mirrored uvs give a
//! negative bitangent sign. Computed only for meshes whose material has a normal map.

use crate::mesh::MeshData;
use glam::{Vec3, Vec4};

struct Geometry<'a> {
    mesh: &'a MeshData,
    /// Face normals, used where the mesh has no vertex normals.
    face_normals: Vec<Vec3>,
    out: Vec<[Vec4; 3]>,
}

impl Geometry<'_> {
    fn index(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[face][vert] as usize
    }
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.index(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        if self.mesh.normals.is_empty() {
            self.face_normals[face].to_array()
        } else {
            self.mesh.normals[self.index(face, vert)].to_array()
        }
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        if self.mesh.uvs.is_empty() {
            // The per-triangle default parameterisation of meshes without uvs.
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][vert]
        } else {
            self.mesh.uvs[self.index(face, vert)].to_array()
        }
    }

    fn set_tangent(&mut self, ts: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        let t = ts.unwrap_or_default().tangent_encoded();
        self.out[face][vert] = Vec4::from(t);
    }
}

/// The tangent frame at each corner of each triangle: the file's tangents when the mesh has them (glTF
/// `TANGENT`, MikkTSpace by the specification), MikkTSpace tangents generated here otherwise.
pub fn corner_tangents(mesh: &MeshData) -> Vec<[Vec4; 3]> {
    if mesh.tangents.len() == mesh.positions.len() && !mesh.tangents.is_empty() {
        return mesh.indices.iter().map(|f| f.map(|i| mesh.tangents[i as usize])).collect();
    }
    mikktspace_tangents(mesh)
}

/// MikkTSpace tangent (xyz) and bitangent sign (w, +1 or -1) at each corner of each triangle of `mesh`, in the
/// mesh's frame; the bitangent is `sign * cross(normal, tangent)` and points along increasing v.
pub fn mikktspace_tangents(mesh: &MeshData) -> Vec<[Vec4; 3]> {
    let face_normals = mesh
        .indices
        .iter()
        .map(|f| {
            let p = f.map(|i| mesh.positions[i as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
        })
        .collect();
    let mut g = Geometry { mesh, face_normals, out: vec![[Vec4::new(1.0, 0.0, 0.0, 1.0); 3]; mesh.indices.len()] };
    // The generator has no failure cases (its error type is empty).
    let _ = bevy_mikktspace::generate_tangents(&mut g);
    g.out
}
