//! pbrt-v4's equal-area octahedral environment maps (Clarberg's mapping; pbrt-v4 `EqualAreaSquareToSphere`,
//! `EqualAreaSphereToSquare`, `WrapMode::OctahedralSphere`): one square image whose texels all subtend the same
//! solid angle, `4 pi / (width height)`, so the Jacobian from the unit square to the sphere is the constant `4 pi`.
//!
//! The square's centre is pbrt's map-frame +z, its corners -z. Prism's env frame has +y up and looks along -z; a
//! direction `(x, y, z)` of Prism's env frame is pbrt's `(z, -x, y)`, the same fixed rotation as for pbrt-v3's
//! equirect maps (`+z` up), so one pbrt light transform places either kind of map.

use glam::{Vec2, Vec3A};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Solid angle per unit area of the square: the constant `4 pi`.
pub const EQUAL_AREA_JACOBIAN: f32 = 4.0 * PI;

/// pbrt's square-to-sphere mapping, in pbrt's map frame.
fn square_to_sphere_pbrt(p: Vec2) -> Vec3A {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    let signed_distance = 1.0 - (up + vp);
    let r = 1.0 - signed_distance.abs();
    let phi = (if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 }) * FRAC_PI_4;
    let z = (1.0 - r * r).copysign(signed_distance);
    let s = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3A::new(phi.cos().copysign(u) * s, phi.sin().copysign(v) * s, z)
}

/// pbrt's sphere-to-square mapping, in pbrt's map frame (exact `atan`, where pbrt uses a minimax polynomial of
/// it accurate to about 1e-6).
fn sphere_to_square_pbrt(d: Vec3A) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let b = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b.atan() / FRAC_PI_2;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    let (u, v) = (u.copysign(d.x), v.copysign(d.y));
    Vec2::new((0.5 * (u + 1.0)).clamp(0.0, 1.0), (0.5 * (v + 1.0)).clamp(0.0, 1.0))
}

/// Square coordinates (u right, v down, in `[0, 1]^2`) of a unit direction of Prism's env frame.
#[inline]
pub fn equal_area_coords(d: Vec3A) -> Vec2 {
    sphere_to_square_pbrt(Vec3A::new(d.z, -d.x, d.y))
}

/// Unit direction of Prism's env frame at square coordinates `uv`.
#[inline]
pub fn equal_area_direction(uv: Vec2) -> Vec3A {
    let p = square_to_sphere_pbrt(uv.clamp(Vec2::ZERO, Vec2::ONE));
    Vec3A::new(-p.y, p.z, p.x)
}

/// The texel a lookup reads for integer coordinates one texel outside the `w x h` square: the square folds over
/// its edges onto the sphere (pbrt-v4's octahedral wrap), so a texel past an edge is the mirrored one across it.
#[inline]
pub fn octahedral_texel(x: i64, y: i64, w: i64, h: i64) -> (i64, i64) {
    let (mut x, mut y) = (x, y);
    if x < 0 {
        x = -x - 1;
        y = h - 1 - y;
    } else if x >= w {
        x = 2 * w - 1 - x;
        y = h - 1 - y;
    }
    if y < 0 {
        x = w - 1 - x;
        y = -y - 1;
    } else if y >= h {
        x = w - 1 - x;
        y = 2 * h - 1 - y;
    }
    (x.clamp(0, w - 1), y.clamp(0, h - 1))
}
