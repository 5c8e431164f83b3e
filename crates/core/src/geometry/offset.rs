//! Robust spawning of secondary rays with conservative floating-point error bounds (pbrt-v4, "Robust Spawned Ray
//! Origins", Pharr, Jakob & Humphreys, 4th ed. section 6.8.6). Each surface hit carries an absolute error bound
//! `p_err` per coordinate, derived from how the point was computed (barycentric interpolation for triangles,
//! reprojection for spheres and planes); the origin is pushed along the geometric normal just past that error
//! box and rounded one ULP further out. The offset is therefore proportional to the actual rounding error: it
//! is right for a 1 mm object at the origin and for a stadium 10^5 units away, never re-hits the surface
//! (no shadow acne) and never crosses geometry thicker than the error bound (no light leaking).

use super::Ray;
use glam::Vec3A;

/// The bound gamma(n) = n u / (1 - n u) on the relative error of n chained floating-point operations, u = 2^-24.
#[inline]
pub const fn gamma(n: i32) -> f32 {
    let u = f32::EPSILON * 0.5;
    (n as f32 * u) / (1.0 - n as f32 * u)
}

/// The sign bit of an `f32`'s bits.
const SIGN: u32 = 0x8000_0000;
/// The bits of an `f32` but its sign.
const MAGNITUDE: u32 = 0x7FFF_FFFF;
/// The magnitude bits of an infinity (above them: NaN).
const INFINITY: u32 = 0x7F80_0000;

/// All ones where `b` holds, zero otherwise.
#[inline(always)]
fn mask(b: bool) -> u32 {
    (b as u32).wrapping_neg()
}

/// `v` moved by one ULP away from zero in the direction of `o`'s sign, for each of the four lanes (bits of `f32`s),
/// as pbrt-v4's `NextFloatUp` where `o > 0` and `NextFloatDown` where `o < 0`; unchanged where `o` is +-0. Written
/// with masks instead of branches, which LLVM compiles to about thirty SSE2 operations on the four lanes at once;
/// the per-coordinate branches cost more than that and mispredicted on the signs.
///
/// The lane rules, those of the two pbrt functions bit for bit: a zero `v` takes `o`'s sign and becomes the smallest
/// denormal of that sign; where `v`'s sign is `o`'s, the magnitude grows by one ULP (`bits + 1`), otherwise it shrinks
/// (`bits - 1`); an infinity moving outward stays, and a NaN counts as negative (`v >= 0` and `v > 0` are false for
/// it).
#[inline(always)]
fn next_float_towards(v: [u32; 4], o: [u32; 4]) -> [u32; 4] {
    let mut out = [0u32; 4];
    for i in 0..4 {
        let o_nonzero = !mask(o[i] & MAGNITUDE == 0);
        let magnitude = v[i] & MAGNITUDE;
        let zero = mask(magnitude == 0) & o_nonzero;
        let vi = (v[i] & !zero) | (o[i] & SIGN & zero);
        let nan = mask(magnitude as i32 > INFINITY as i32);
        let outward = mask((((vi | (nan & SIGN)) ^ o[i]) as i32) >= 0);
        let stays = outward & mask(magnitude == INFINITY);
        let step = !outward | 1;
        out[i] = vi.wrapping_add(step & o_nonzero & !stays);
    }
    out
}

/// `p` (with absolute error bound `p_err`) moved off its surface along the unit geometric normal `n`, towards the
/// side of `w`, each coordinate then rounded one ULP further away in the offset's direction.
#[inline]
pub fn offset_ray_origin(p: Vec3A, p_err: Vec3A, n: Vec3A, w: Vec3A) -> Vec3A {
    let d = n.abs().dot(p_err);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    from_lanes(next_float_towards(lanes(po), lanes(offset)))
}

/// The bits of a `Vec3A`'s lanes (the fourth lane whatever it holds): a register cast on x86-64.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn lanes(v: Vec3A) -> [u32; 4] {
    bytemuck::cast(std::arch::x86_64::__m128::from(v))
}

/// A `Vec3A` from its lanes' bits (the fourth lane ignored).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn from_lanes(bits: [u32; 4]) -> Vec3A {
    Vec3A::from(bytemuck::cast::<[u32; 4], std::arch::x86_64::__m128>(bits))
}

/// The bits of a `Vec3A`'s lanes (the fourth lane zero).
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn lanes(v: Vec3A) -> [u32; 4] {
    let [x, y, z] = v.to_array();
    [x.to_bits(), y.to_bits(), z.to_bits(), 0]
}

/// A `Vec3A` from its lanes' bits (the fourth lane ignored).
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn from_lanes(bits: [u32; 4]) -> Vec3A {
    Vec3A::new(f32::from_bits(bits[0]), f32::from_bits(bits[1]), f32::from_bits(bits[2]))
}

/// A ray leaving surface point `p` (error `p_err`, geometric normal `ng`) in unit direction `dir`.
#[inline]
pub fn spawn_ray(p: Vec3A, p_err: Vec3A, ng: Vec3A, dir: Vec3A) -> Ray {
    Ray::new(offset_ray_origin(p, p_err, ng, dir), dir)
}

/// A shadow ray from `p` (error `p_err`, normal `ng`) towards `q` (error `q_err`, normal `nq`; zero normal and
/// error for a point light). Both ends are offset off their surfaces. As in pbrt-v4's `SpawnRayTo`, the direction
/// is the whole segment between the offset ends, not a unit vector, and `tmax` is `1 - 1e-4`, so the ray stops
/// just short of the target and the target surface never counts as an occluder. For occlusion queries only (every
/// accelerator and shape test takes any direction length): no square root and division on the way to the query.
#[inline(always)]
pub fn spawn_ray_to(p: Vec3A, p_err: Vec3A, ng: Vec3A, q: Vec3A, q_err: Vec3A, nq: Vec3A) -> Ray {
    let o = offset_ray_origin(p, p_err, ng, q - p);
    let target = if nq == Vec3A::ZERO { q } else { offset_ray_origin(q, q_err, nq, o - q) };
    Ray::with_tmax(o, target - o, 1.0 - 1e-4)
}
