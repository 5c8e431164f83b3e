//! What a process that loads the same scene again and again (`prism watch`) keeps from one load to the next, so a
//! restart after an edit redoes only what the edit changed:
//!
//! - **meshes read from files** (PLY, OBJ with its MTL materials), by canonical path, file length, modification
//!   time and the flags applied to them: a camera, material or light edit reads no mesh again;
//! - **the accelerator** of the last build, with a key of everything it was built over (every world-space triangle
//!   bit for bit, the analytic shapes, alpha masks, the accelerator kind and its spatial-split setting): a build over
//!   the same key takes it instead of building.
//!
//! The cache is a plugin resource (`Resources::insert`): absent, nothing is kept, as in `prism render`.

use prism_core::accel::Accel;
use prism_core::material::Material;
use prism_core::mesh::MeshData;
use prism_core::primitives::Primitives;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// One mesh file's identity and the flags its meshes were loaded with.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MeshFileKey {
    path: PathBuf,
    len: u64,
    modified: Option<SystemTime>,
    flat: bool,
    reverse: bool,
}

impl MeshFileKey {
    /// The key of `path` as it is on disk now (`None` if it cannot be read).
    pub fn of(path: &Path, flat: bool, reverse: bool) -> Option<Self> {
        let meta = std::fs::metadata(path).ok()?;
        Some(MeshFileKey {
            path: path.canonicalize().ok()?,
            len: meta.len(),
            modified: meta.modified().ok(),
            flat,
            reverse,
        })
    }
}

/// A mesh file's meshes as loaded: each with its MTL material and emission (PLY: one, without either).
pub type LoadedMeshes = Vec<(Arc<MeshData>, Option<Material>, Option<glam::Vec3>)>;

/// The cache (see the module doc).
#[derive(Default)]
pub struct ReloadCache {
    meshes: HashMap<MeshFileKey, LoadedMeshes>,
    /// Mesh files used by the current load (the others are dropped when it ends).
    used: Vec<MeshFileKey>,
    accel: Option<(u64, Accel)>,
    /// The key of the current load's accelerator.
    accel_key: Option<u64>,
    /// Mesh files and accelerators taken from the cache so far (for tests and the terminal's restart line).
    pub hits: CacheHits,
}

/// What loads took from the cache.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheHits {
    /// Mesh files not read again.
    pub mesh_files: u32,
    /// Accelerators not built again.
    pub accels: u32,
}

impl ReloadCache {
    /// The meshes of a file loaded before with the same key.
    pub fn mesh_file(&mut self, key: &MeshFileKey) -> Option<LoadedMeshes> {
        let hit = self.meshes.get(key).cloned();
        if hit.is_some() {
            self.used.push(key.clone());
            self.hits.mesh_files += 1;
        }
        hit
    }

    /// Keep a file's meshes.
    pub fn keep_mesh_file(&mut self, key: MeshFileKey, meshes: LoadedMeshes) {
        self.used.push(key.clone());
        self.meshes.insert(key, meshes);
    }

    /// The accelerator built before over the same key, taken out of the cache; and the key is remembered as the
    /// current build's.
    pub fn take_accel(&mut self, key: u64) -> Option<Accel> {
        self.accel_key = Some(key);
        match self.accel.take() {
            Some((k, a)) if k == key => {
                self.hits.accels += 1;
                Some(a)
            }
            _ => None,
        }
    }

    /// After a render: keep its accelerator for the next load (the previous one stays when it built none) and,
    /// when its load succeeded (`loaded`), only the mesh files it used.
    pub fn finish(&mut self, accel: Option<Accel>, loaded: bool) {
        if let (Some(a), Some(k)) = (accel, self.accel_key) {
            self.accel = Some((k, a));
        }
        self.accel_key = None;
        let used: std::collections::HashSet<MeshFileKey> = self.used.drain(..).collect();
        if loaded {
            self.meshes.retain(|k, _| used.contains(k));
        }
    }
}

/// A key of everything an accelerator is built over (FNV-style mixing of 64-bit words: about 10 ms per million
/// triangles).
pub fn geometry_key(prims: &Primitives, settings: &str) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut mix = |w: u64| h = (h ^ w).wrapping_mul(0x0000_0100_0000_01b3).rotate_left(29);
    for t in &prims.tris {
        for v in t {
            mix(v.x.to_bits() as u64 | (v.y.to_bits() as u64) << 32);
            mix(v.z.to_bits() as u64);
        }
    }
    for a in &prims.tri_alpha {
        mix(*a as u64);
    }
    let analytic =
        format!("{:?} {:?} {:?} {:?} {settings}", prims.spheres, prims.revolutions, prims.patches, prims.analytic);
    for b in analytic.bytes() {
        mix(b as u64);
    }
    mix(prims.tris.len() as u64);
    h
}
