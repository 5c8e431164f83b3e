//! Cube-map geometry in Prism's convention (faces seen from inside, frames listed in `mod.rs`), and conversion of
//! the two cube file layouts (vertical cross, six GL/three.js faces) into it.

use super::{EnvImage, EnvMap};
use crate::error::{PrismError, Result};
use glam::{Vec2, Vec3A};
use std::path::PathBuf;

/// A face's centre direction and the directions of its image-right and image-down axes.
#[derive(Clone, Copy, Debug)]
pub struct FaceFrame {
    /// Unit direction through the face's centre (the face's axis).
    pub center: Vec3A,
    /// Unit direction of increasing image x (columns) on the face.
    pub right: Vec3A,
    /// Unit direction of increasing image y (rows, downwards) on the face.
    pub down: Vec3A,
}

const fn f(c: [f32; 3], r: [f32; 3], d: [f32; 3]) -> FaceFrame {
    FaceFrame {
        center: Vec3A::new(c[0], c[1], c[2]),
        right: Vec3A::new(r[0], r[1], r[2]),
        down: Vec3A::new(d[0], d[1], d[2]),
    }
}

/// Faces in the order +x, -x, +y, -y, +z, -z.
pub const CUBE_FACES: [FaceFrame; 6] = [
    f([1., 0., 0.], [0., 0., 1.], [0., -1., 0.]),
    f([-1., 0., 0.], [0., 0., -1.], [0., -1., 0.]),
    f([0., 1., 0.], [1., 0., 0.], [0., 0., -1.]),
    f([0., -1., 0.], [1., 0., 0.], [0., 0., 1.]),
    f([0., 0., 1.], [-1., 0., 0.], [0., -1., 0.]),
    f([0., 0., -1.], [1., 0., 0.], [0., -1., 0.]),
];

/// Face and (u, v) of a direction (need not be unit).
#[inline]
pub fn cube_coords(d: Vec3A) -> (usize, Vec2) {
    let a = d.abs();
    let face = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 { 0 } else { 1 }
    } else if a.y >= a.z {
        if d.y > 0.0 { 2 } else { 3 }
    } else if d.z > 0.0 {
        4
    } else {
        5
    };
    let fr = &CUBE_FACES[face];
    let m = d.dot(fr.center);
    let s = d.dot(fr.right) / m;
    let t = d.dot(fr.down) / m;
    (face, Vec2::new(((s + 1.0) * 0.5).clamp(0.0, 1.0), ((t + 1.0) * 0.5).clamp(0.0, 1.0)))
}

/// Unit direction of a face point.
#[inline]
pub fn cube_direction(face: usize, uv: Vec2) -> Vec3A {
    let fr = &CUBE_FACES[face];
    (fr.center + fr.right * (2.0 * uv.x - 1.0) + fr.down * (2.0 * uv.y - 1.0)).normalize()
}

/// Solid angle per unit (u, v) area: 4 / (1 + s^2 + t^2)^(3/2) with s = 2u - 1, t = 2v - 1.
#[inline]
pub fn cube_jacobian(uv: Vec2) -> f32 {
    let (s, t) = (2.0 * uv.x - 1.0, 2.0 * uv.y - 1.0);
    4.0 / (1.0 + s * s + t * t).powf(1.5)
}

/// Exact solid angle of texel (x, y) of a face of `size` texels: with A(s, t) = atan2(s t, sqrt(s^2 + t^2 + 1)),
/// the rectangle [s0, s1] x [t0, t1] subtends A(s1,t1) - A(s0,t1) - A(s1,t0) + A(s0,t0).
pub fn cube_texel_solid_angle(size: u32, x: u32, y: u32) -> f32 {
    let n = size as f64;
    let a = |s: f64, t: f64| (s * t).atan2((s * s + t * t + 1.0).sqrt());
    let (s0, s1) = (2.0 * x as f64 / n - 1.0, 2.0 * (x + 1) as f64 / n - 1.0);
    let (t0, t1) = (2.0 * y as f64 / n - 1.0, 2.0 * (y + 1) as f64 / n - 1.0);
    (a(s1, t1) - a(s0, t1) - a(s1, t0) + a(s0, t0)) as f32
}

/// Build Prism's six faces by looking each texel centre up in a source function of (direction).
fn resample(size: u32, fetch: impl Fn(Vec3A) -> glam::Vec3) -> Vec<EnvImage> {
    (0..6)
        .map(|face| {
            let mut texels = Vec::with_capacity((size * size) as usize);
            for y in 0..size {
                for x in 0..size {
                    let uv = Vec2::new((x as f32 + 0.5) / size as f32, (y as f32 + 0.5) / size as f32);
                    texels.push(fetch(cube_direction(face, uv)));
                }
            }
            EnvImage { width: size, height: size, texels }
        })
        .collect()
}

/// Nearest texel of a square face at (u, v).
fn nearest(img: &EnvImage, uv: Vec2) -> glam::Vec3 {
    let x = ((uv.x * img.width as f32) as u32).min(img.width - 1);
    let y = ((uv.y * img.height as f32) as u32).min(img.height - 1);
    img.texel(x, y)
}

/// A vertical cross (3 faces wide, 4 tall): +y, then -x -z +x, then -y, then +z rotated by 180 degrees.
pub fn from_cross(cross: &EnvImage) -> EnvMap {
    let s = cross.width / 3;
    // Cross cell (column, row) of each face, and whether it is stored rotated by 180 degrees.
    let cells: [(u32, u32, bool); 6] =
        [(2, 1, false), (0, 1, false), (1, 0, false), (1, 2, false), (1, 3, true), (1, 1, false)];
    let faces = (0..6)
        .map(|face| {
            let (cx, cy, rot) = cells[face];
            let mut texels = Vec::with_capacity((s * s) as usize);
            for y in 0..s {
                for x in 0..s {
                    let (sx, sy) = if rot { (s - 1 - x, s - 1 - y) } else { (x, y) };
                    texels.push(cross.texel(cx * s + sx, cy * s + sy));
                }
            }
            EnvImage { width: s, height: s, texels }
        })
        .collect();
    EnvMap::cube(faces)
}

/// Six faces `px nx py ny pz nz` in the OpenGL cube-map convention as three.js uses it: a world direction w is
/// looked up as g = (-w.x, w.y, w.z) in the GL face table (major axis, then sc/tc per face).
pub fn from_gl_faces(files: Vec<(EnvImage, PathBuf)>) -> Result<EnvMap> {
    let size = files[0].0.width;
    for (img, path) in &files {
        if img.width != img.height || img.width != size {
            return Err(PrismError::format(
                path,
                format!(
                    "cube faces must be square and equal in size ({size}x{size}), got {}x{}",
                    img.width, img.height
                ),
            ));
        }
    }
    let faces: Vec<EnvImage> = files.into_iter().map(|(i, _)| i).collect();
    let gl_lookup = |w: Vec3A| {
        let g = Vec3A::new(-w.x, w.y, w.z);
        let a = g.abs();
        // (file index, sc, tc, |ma|) per the GL table.
        let (idx, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
            if g.x > 0.0 { (0, -g.z, -g.y, a.x) } else { (1, g.z, -g.y, a.x) }
        } else if a.y >= a.z {
            if g.y > 0.0 { (2, g.x, g.z, a.y) } else { (3, g.x, -g.z, a.y) }
        } else if g.z > 0.0 {
            (4, g.x, -g.y, a.z)
        } else {
            (5, -g.x, -g.y, a.z)
        };
        nearest(&faces[idx], Vec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)))
    };
    Ok(EnvMap::cube(resample(size, gl_lookup)))
}
