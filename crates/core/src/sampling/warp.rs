//! Warps from the unit square `[0,1)^2` to the domains integrators sample, each paired with its pdf in the
//! measure named in its doc (solid angle unless stated). Local frames have the normal along +z.

use glam::{Vec2, Vec3A};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4, PI};

const INV_4PI: f32 = 0.25 * FRAC_1_PI;
const INV_2PI: f32 = 0.5 * FRAC_1_PI;

/// Uniform direction on the unit sphere.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3A {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// Pdf of [`uniform_sphere`]: `1 / (4 pi)` for every direction.
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// Uniform direction on the hemisphere z >= 0.
#[inline]
pub fn uniform_hemisphere(u: Vec2) -> Vec3A {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// Pdf of [`uniform_hemisphere`] at the local direction `local`: `1 / (2 pi)` where `z >= 0`, 0 below.
#[inline]
pub fn uniform_hemisphere_pdf(local: Vec3A) -> f32 {
    if local.z >= 0.0 { INV_2PI } else { 0.0 }
}

/// Shirley–Chiu concentric map from the square to the unit disk (area preserving, low distortion).
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // The angle is pi/4 * a with |a| <= 1 in the first wedge, pi/2 - pi/4 * a in the second (where cos and sin
    // swap), so one polynomial pair on [-pi/4, pi/4] replaces a libm call.
    // The wedge is a coin flip per sample, so it is chosen by bit masks, not a branch (which mispredicted half the
    // time, and which LLVM makes of a plain select of the two results); the arithmetic is each wedge's own.
    let first = o.x.abs() > o.y.abs();
    let (big, small) = if first { (o.x, o.y) } else { (o.y, o.x) };
    let (s, c) = sin_cos_quarter(FRAC_PI_4 * (small / big));
    let (along, across) = ((big * c).to_bits(), (big * s).to_bits());
    let m = (first as u32).wrapping_neg();
    Vec2::new(f32::from_bits((along & m) | (across & !m)), f32::from_bits((across & m) | (along & !m)))
}

/// `(sin x, cos x)` for `|x| <= pi/4` by their Taylor polynomials to degree 9 and 10 (truncation error below
/// 2e-9 there, so the result is within a few ulps of the exact value; `tests/sampling.rs` checks it against f64).
#[inline]
pub fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let s = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 - x2 / 3_628_800.0))));
    (s, c)
}

/// Cosine-weighted direction on the hemisphere z >= 0 (Malley's method).
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3A {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3A::new(d.x, d.y, z)
}

/// [`cosine_hemisphere`] of sixteen points at once: lane `l` of `u` (x in `u[0]`, y in `u[1]`) to lane `l` of
/// `out` (x, y, z) — the same bits as the one-point function, which is plain `f32` arithmetic (its disk wedge chosen
/// by masks), so the lane loop compiles to one vector computation. Compiled for AVX-512 and AVX2 and chosen at run
/// time.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx512bw", "x86_64+avx2"))]
pub fn cosine_hemisphere_lanes(u: &[[f32; 16]; 2], out: &mut [[f32; 16]; 3]) {
    for l in 0..16 {
        let d = concentric_disk(Vec2::new(u[0][l], u[1][l]));
        out[0][l] = d.x;
        out[1][l] = d.y;
        out[2][l] = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    }
}

/// Pdf of [`cosine_hemisphere`] at the unit local direction `local`: `cos / pi`, 0 below the surface.
#[inline]
pub fn cosine_hemisphere_pdf(local: Vec3A) -> f32 {
    local.z.max(0.0) * FRAC_1_PI
}

/// Direction around +z with density proportional to `cos^exponent` of the angle to +z (the Phong lobe).
#[inline]
pub fn phong_lobe(u: Vec2, exponent: f32) -> Vec3A {
    let z = u.x.powf(1.0 / (exponent + 1.0));
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// Pdf of [`phong_lobe`]: (n + 1) / (2 pi) cos^n.
#[inline]
pub fn phong_lobe_pdf(local: Vec3A, exponent: f32) -> f32 {
    if local.z <= 0.0 { 0.0 } else { (exponent + 1.0) * INV_2PI * local.z.powf(exponent) }
}

/// Uniform direction inside the cone of half-angle acos(cos_max) around +z.
#[inline]
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3A {
    let z = 1.0 - u.x * (1.0 - cos_max);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// Pdf of [`uniform_cone`] for directions inside the cone, `1 / (2 pi (1 - cos_max))` (the caller tests
/// whether a direction is inside; infinite for `cos_max = 1`).
#[inline]
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Uniform point on a triangle as barycentric weights `(b0, b1, b2)`; pdf 1/area in area measure.
/// Uses Heitz's low-distortion square-to-triangle map (2019), which keeps strata compact.
#[inline]
pub fn uniform_triangle(u: Vec2) -> (f32, f32, f32) {
    let (b0, b1) = if u.x < u.y {
        let b0 = u.x / 2.0;
        (b0, u.y - b0)
    } else {
        let b1 = u.y / 2.0;
        (u.x - b1, b1)
    };
    (b0, b1, 1.0 - b0 - b1)
}
