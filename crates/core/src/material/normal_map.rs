//! Shading normals from normal maps and bump maps, following Mitsuba 3's `normalmap` BSDF as
//! `../shared/refs/textured.md` specifies it:
//!
//! 1. Tangent frame at the hit: `n` = the (interpolated) shading normal; the tangent `t` is the mesh's
//!    MikkTSpace tangent when the mesh has them (computed for meshes whose material has a normal map), else
//!    `normalize(dp/du - n (n . dp/du))`; the bitangent is `b = sign cross(n, t)`, the sign making `b` point along
//!    increasing v (MikkTSpace's bitangent sign; it handles mirrored uvs).
//! 2. `nr = 2 c - 1` from the texel value `c`, x along t, y along b (negated with `flip_green`: maps whose green
//!    points up the image, OpenGL/glTF style), z along n; x and y are scaled by `strength` (glTF's `scale`).
//! 3. Flip rule: if `wo_local.z (wo_local . nr) <= 0` then `nr = (-nr.x, -nr.y, nr.z)` (mirrored about n so it
//!    faces the viewer).
//! 4. The shading normal is `normalize(nr)` in (t, b, n); a zero-length `nr` (e.g. where interpolation cancels
//!    opposite normals) leaves `n` unchanged.
//!
//! Bump maps displace the surface by a height `h(u, v)` along `n`: `dp/du' = dp/du + (dh/du) n`, the same for v,
//! and the normal is `normalize(dp/du' x dp/dv')` turned to `n`'s side (pbrt's `BumpMap` without the dn/du term);
//! the derivatives are forward differences with a step of `du = dv = 1/2048` in uv.

use glam::{Vec3, Vec3A};

/// Step of the bump map's finite differences, in uv units.
pub const BUMP_DELTA: f32 = 1.0 / 2048.0;

/// The tangent and bitangent at a hit with shading normal `n` (unit), from the mesh's MikkTSpace tangent and
/// sign when given, else from dp/du and dp/dv.
pub fn tangent_frame(n: Vec3A, dpdu: Vec3A, dpdv: Vec3A, mesh_tangent: Option<(Vec3A, f32)>) -> (Vec3A, Vec3A) {
    let (raw, sign) = match mesh_tangent {
        Some((t, s)) => (t, Some(s)),
        None => (dpdu, None),
    };
    let mut t = (raw - n * n.dot(raw)).normalize_or_zero();
    if t == Vec3A::ZERO {
        t = crate::math::Frame::from_normal(n).s;
    }
    let b = n.cross(t);
    let sign = sign.unwrap_or(if b.dot(dpdv) < 0.0 { -1.0 } else { 1.0 });
    (t, b * sign)
}

/// The shading normal of a normal-map texel value `c` (raw, in [0, 1]) in the frame (t, b, n), for the viewer
/// direction `wo` (unit, either side).
pub fn normal_map_normal(n: Vec3A, t: Vec3A, b: Vec3A, c: Vec3, strength: f32, flip_green: bool, wo: Vec3A) -> Vec3A {
    let mut nr = Vec3A::from(2.0 * c - Vec3::ONE);
    if flip_green {
        nr.y = -nr.y;
    }
    nr.x *= strength;
    nr.y *= strength;
    let wl = Vec3A::new(wo.dot(t), wo.dot(b), wo.dot(n));
    if wl.z * wl.dot(nr) <= 0.0 {
        nr.x = -nr.x;
        nr.y = -nr.y;
    }
    let len = nr.length();
    if len.is_nan() || len <= 1e-6 || !len.is_finite() {
        return n;
    }
    ((nr.x * t + nr.y * b + nr.z * n) / len).normalize()
}

/// The bump-mapped normal for height derivatives `dhdu`, `dhdv` (world units per uv unit), on `n`'s side.
pub fn bump_normal(n: Vec3A, dpdu: Vec3A, dpdv: Vec3A, dhdu: f32, dhdv: f32) -> Vec3A {
    let pu = dpdu + dhdu * n;
    let pv = dpdv + dhdv * n;
    let m = pu.cross(pv).normalize_or_zero();
    if m == Vec3A::ZERO || !m.is_finite() {
        return n;
    }
    if m.dot(n) < 0.0 { -m } else { m }
}
