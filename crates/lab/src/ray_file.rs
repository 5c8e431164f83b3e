//! The ray-set file `prism bench --export-rays DIR` writes (one `SCENE.prism-rays` per scene): the scene's
//! world-space triangles, the three ray sets of `prism bench` (camera, bounce and shadow rays, `ray_sets.rs`) and
//! Prism's answers for them, so that another traversal engine (`benches/embree/`) can be timed on exactly the same
//! queries and checked against the same hits. Written atomically (a `.partial` file renamed into place).
//!
//! Layout, all little-endian, no padding (`f32` is IEEE 754 binary32):
//!
//! | field | type | meaning |
//! |---|---|---|
//! | magic | 8 bytes | `PRSMRAYS` |
//! | version | u32 | 1 |
//! | triangles | u32 | T |
//! | camera, bounce, shadow | 3 x u32 | ray counts C, B, S |
//! | vertices | T x 9 f32 | v0.xyz, v1.xyz, v2.xyz of each triangle, world space; triangle i is primitive i |
//! | rays | (C + B + S) x 7 f32 | origin.xyz, direction.xyz (unit), tmax (+inf for camera and bounce rays); tmin is 0 |
//! | closest hits | (C + B) x (u32, f32) | primitive index and t of the closest hit, or (0xffffffff, +inf) for a miss |
//! | occlusion | S x u32 | 1 if something blocks the shadow ray before tmax, else 0 |
//!
//! Only triangle scenes can be exported (spheres and planes have no equivalent in a plain triangle engine).

use glam::Vec3A;
use prism_core::accel::Accel;
use prism_core::error::{PrismError, Result};
use prism_core::geometry::Ray;
use prism_core::primitives::Primitives;
use std::io::Write;
use std::path::Path;

/// The file's first eight bytes.
pub const MAGIC: &[u8; 8] = b"PRSMRAYS";
/// The format version this module writes and reads.
pub const VERSION: u32 = 1;
/// The primitive index of a miss.
pub const MISS: u32 = u32::MAX;

/// The content of a ray-set file.
#[derive(Clone, Debug, Default)]
pub struct RaySetFile {
    pub tris: Vec<[Vec3A; 3]>,
    /// Camera, bounce and shadow rays.
    pub sets: [Vec<Ray>; 3],
    /// (primitive, t) of the closest hit of each camera and bounce ray ([`MISS`], +inf for none).
    pub hits: [Vec<(u32, f32)>; 2],
    /// Whether each shadow ray is blocked.
    pub occluded: Vec<bool>,
}

impl RaySetFile {
    /// Trace the three sets with `accel` over `prims` (triangles only) and collect the answers.
    pub fn trace(prims: &Primitives, accel: &Accel, sets: [&[Ray]; 3]) -> Result<Self> {
        if !prims.spheres.is_empty() || !prims.planes.is_empty() {
            return Err(PrismError::invalid(format!(
                "--export-rays: only triangle scenes can be exported (this one has {} sphere(s) and {} plane(s))",
                prims.spheres.len(),
                prims.planes.len()
            )));
        }
        let closest = |rays: &[Ray]| -> Vec<(u32, f32)> {
            rays.iter().map(|r| accel.intersect(prims, r).map_or((MISS, f32::INFINITY), |h| (h.prim, h.t))).collect()
        };
        Ok(RaySetFile {
            tris: prims.tris.clone(),
            sets: sets.map(<[Ray]>::to_vec),
            hits: [closest(sets[0]), closest(sets[1])],
            occluded: sets[2].iter().map(|r| accel.occluded(prims, r)).collect(),
        })
    }

    /// Write the file atomically (see the module doc for the layout).
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut b: Vec<u8> = Vec::new();
        b.extend_from_slice(MAGIC);
        let counts = [VERSION, self.tris.len() as u32, self.sets[0].len() as u32, self.sets[1].len() as u32];
        for v in counts.into_iter().chain([self.sets[2].len() as u32]) {
            b.extend_from_slice(&v.to_le_bytes());
        }
        let f32s = |b: &mut Vec<u8>, v: &[f32]| v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
        for t in &self.tris {
            for v in t {
                f32s(&mut b, &v.to_array());
            }
        }
        for r in self.sets.iter().flatten() {
            f32s(&mut b, &r.origin.to_array());
            f32s(&mut b, &r.dir.to_array());
            f32s(&mut b, &[r.tmax]);
        }
        for &(prim, t) in self.hits.iter().flatten() {
            b.extend_from_slice(&prim.to_le_bytes());
            b.extend_from_slice(&t.to_le_bytes());
        }
        for &o in &self.occluded {
            b.extend_from_slice(&u32::from(o).to_le_bytes());
        }
        let mut tmp_name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
        tmp_name.push(".partial");
        let tmp = path.with_file_name(tmp_name);
        let write = || -> std::io::Result<()> {
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(&b)?;
            f.sync_all()
        };
        write().map_err(|e| PrismError::io(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| PrismError::io(path, e))
    }

    /// Read a file written by [`RaySetFile::write`], checking its header against its length before allocating.
    pub fn read(path: &Path) -> Result<Self> {
        Self::from_bytes(&prism_core::io::read_regular(path, "ray-set file")?, path)
    }

    /// Decode the bytes of a ray-set file (`path` only names it in errors), checking its header against its length
    /// before allocating.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        let bad = |m: &str| PrismError::format(path, m.to_string());
        if bytes.len() < 28 || &bytes[..8] != MAGIC {
            return Err(bad("not a Prism ray-set file (bad magic)"));
        }
        let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
        if u32_at(8) != VERSION {
            return Err(bad(&format!("unsupported version {} (expected {VERSION})", u32_at(8))));
        }
        let [t, c, bn, s] = [12, 16, 20, 24].map(|o| u32_at(o) as u64);
        let expected = 28 + t * 36 + (c + bn + s) * 28 + (c + bn) * 8 + s * 4;
        if bytes.len() as u64 != expected {
            return Err(bad(&format!("length {} does not match its header (expected {expected})", bytes.len())));
        }
        let mut at = 28;
        let mut next = || {
            let v = u32_at(at);
            at += 4;
            v
        };
        let vec3 = |next: &mut dyn FnMut() -> u32| {
            Vec3A::new(f32::from_bits(next()), f32::from_bits(next()), f32::from_bits(next()))
        };
        let tris = (0..t).map(|_| [vec3(&mut next), vec3(&mut next), vec3(&mut next)]).collect();
        let sets = [c, bn, s].map(|n| {
            (0..n).map(|_| Ray::with_tmax(vec3(&mut next), vec3(&mut next), f32::from_bits(next()))).collect::<Vec<_>>()
        });
        let hits = [c, bn].map(|n| (0..n).map(|_| (next(), f32::from_bits(next()))).collect::<Vec<_>>());
        let occluded = (0..s).map(|_| next() != 0).collect();
        Ok(RaySetFile { tris, sets, hits, occluded })
    }
}
