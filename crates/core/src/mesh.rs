//! Triangle meshes shared by entities (`Shape::Mesh(handle)`), plus the built-in unit quad and cube.

use glam::{Vec2, Vec3};
use std::sync::Arc;

/// Index of a mesh in [`MeshStore`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeshHandle(pub u32);

/// An indexed triangle mesh in its local frame. `normals`, `uvs` and `tangents` are either empty or one per
/// position.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// A name for messages and statistics (the file name, or `quad` / `cube`).
    pub name: String,
    /// Vertex positions, local frame.
    pub positions: Vec<Vec3>,
    /// Vertex normals (one per position, or none: flat shading).
    pub normals: Vec<Vec3>,
    /// Vertex texture coordinates (one per position, or none).
    pub uvs: Vec<Vec2>,
    /// Triangles as three indices into the vertex arrays; counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
    /// Tangents supplied by the file (glTF `TANGENT`: xyz along increasing u, w the bitangent sign); normal maps
    /// use them instead of generating MikkTSpace tangents.
    pub tangents: Vec<glam::Vec4>,
}

impl MeshData {
    /// Bytes held by the mesh's arrays (for memory reports).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.positions.len() * size_of::<Vec3>()
            + self.normals.len() * size_of::<Vec3>()
            + self.uvs.len() * size_of::<Vec2>()
            + self.indices.len() * size_of::<[u32; 3]>()
            + self.tangents.len() * size_of::<glam::Vec4>()
    }
}

impl MeshData {
    /// The square [-1,1]^2 in the z = 0 plane, front face (normal) +z, as two triangles (0,1,2), (0,2,3).
    pub fn unit_quad() -> Self {
        Self::quad(
            "quad",
            [Vec3::new(-1., -1., 0.), Vec3::new(1., -1., 0.), Vec3::new(1., 1., 0.), Vec3::new(-1., 1., 0.)],
        )
    }

    /// A quad from four corners in counter-clockwise order seen from its front; triangles (0,1,2), (0,2,3).
    pub fn quad(name: &str, corners: [Vec3; 4]) -> Self {
        MeshData {
            name: name.to_string(),
            positions: corners.to_vec(),
            normals: vec![],
            uvs: vec![Vec2::new(0., 0.), Vec2::new(1., 0.), Vec2::new(1., 1.), Vec2::new(0., 1.)],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            tangents: vec![],
        }
    }

    /// The cube [-1,1]^3 as 12 triangles with outward normals (flat faces). Each face carries the whole texture
    /// upright as seen from outside: u grows to the right and v downwards (image rows) with +y up on the side
    /// faces; the top face has v growing towards +z (its image top towards -z), the bottom face towards -z.
    pub fn unit_cube() -> Self {
        let mut positions = Vec::with_capacity(24);
        let mut uvs = Vec::with_capacity(24);
        let mut indices = Vec::with_capacity(12);
        // Each face: outward axis n and two in-plane axes (u, v) with u x v = n (the corners and triangles), then
        // "right" and "up" as seen from outside (right x up = n) for the texture coordinates.
        let faces = [
            (Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Z, Vec3::Y),
            (-Vec3::X, Vec3::Z, Vec3::Y, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::Z, Vec3::X, Vec3::X, -Vec3::Z),
            (-Vec3::Y, Vec3::X, Vec3::Z, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y, Vec3::X, Vec3::Y),
            (-Vec3::Z, Vec3::Y, Vec3::X, -Vec3::X, Vec3::Y),
        ];
        for (n, u, v, right, up) in faces {
            let base = positions.len() as u32;
            for (a, b) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let c = n + u * a + v * b;
                positions.push(c);
                uvs.push(Vec2::new((c.dot(right) + 1.0) * 0.5, (1.0 - c.dot(up)) * 0.5));
            }
            indices.push([base, base + 1, base + 2]);
            indices.push([base, base + 2, base + 3]);
        }
        MeshData { name: "cube".into(), positions, normals: vec![], uvs, indices, tangents: vec![] }
    }
}

/// All meshes of a scene (the loader shares one mesh between entities that reference the same file).
#[derive(Default, Debug)]
pub struct MeshStore {
    meshes: Vec<Arc<MeshData>>,
}

impl MeshStore {
    /// Store `mesh` and return its handle (handles are never reused).
    pub fn add(&mut self, mesh: MeshData) -> MeshHandle {
        self.meshes.push(Arc::new(mesh));
        MeshHandle(self.meshes.len() as u32 - 1)
    }

    /// Store a mesh shared with others (a reload cache's) and return its handle.
    pub fn add_shared(&mut self, mesh: Arc<MeshData>) -> MeshHandle {
        self.meshes.push(mesh);
        MeshHandle(self.meshes.len() as u32 - 1)
    }

    /// The mesh of handle `h` (a handle of this store; panics otherwise).
    pub fn get(&self, h: MeshHandle) -> &MeshData {
        &self.meshes[h.0 as usize]
    }

    /// Number of meshes stored.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// True when no mesh is stored.
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }
}
