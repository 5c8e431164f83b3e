//! Small math helpers shared by geometry, materials and integrators: orthonormal frames, optics (reflection,
//! refraction, Fresnel), colour luminance.

mod affine;
mod frame;
mod optics;

pub use affine::check_affine;
pub use frame::Frame;
pub use optics::{fresnel_dielectric, reflect, refract};

use glam::Vec3;

/// `v / |v|` computed in double precision, so vectors as short as 1e-38 or as long as 1e38 (whose squared length
/// underflows or overflows in `f32`) normalise exactly; `None` for zero or non-finite vectors.
pub fn unit_vector(v: Vec3) -> Option<Vec3> {
    let d = v.as_dvec3();
    let len = d.length();
    (len > 0.0 && len.is_finite()).then(|| (d / len).as_vec3())
}

/// Bit `l` set where `f(l)` holds, for the sixteen lanes `l` of a ray packet. The answers as bytes of 0 or 1,
/// eight to a `u64`, gathered into eight bits by one multiplication each: byte `i` times `2^(7j + 7)` lands its bit
/// at `56 + i` for `j = 7 - i`, and no two of the products share a bit, so nothing carries. LLVM compiled the plain
/// shift-and-or fold over the lanes to about thirty shuffles and extractions per mask (`tests/geometry.rs` checks
/// all 65,536 patterns against it).
#[inline(always)]
pub fn lane_mask16(f: impl Fn(usize) -> bool) -> u32 {
    const GATHER: u64 = 0x0102_0408_1020_4080;
    let bytes: [u8; 16] = std::array::from_fn(|l| f(l) as u8);
    let (lo, hi) = bytes.split_at(8);
    let eight = |b: &[u8]| (u64::from_le_bytes(b.try_into().unwrap_or([0; 8])).wrapping_mul(GATHER) >> 56) as u32;
    eight(lo) | eight(hi) << 8
}

/// `x.floor()`, bit for bit for every `f32` (signed zeros, NaN and infinities included), without a call: on the
/// baseline x86-64 target (SSE2, no rounding instruction) `f32::floor` is a call to libm's `floorf`, which showed
/// up beside the texture lookups in profiles. Every `f32` of magnitude 2^23 or more is an integer already; below
/// that the truncation toward zero is exact, and one is taken off where it rounded up.
#[inline(always)]
pub fn floor_f32(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let t = x as i32 as f32;
        if t > x { t - 1.0 } else { t.copysign(x) }
    } else {
        x
    }
}

/// Rec. 709 luminance of a linear RGB colour.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// True when every component is finite.
#[inline]
pub fn is_finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}
