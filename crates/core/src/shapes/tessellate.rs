//! The curved surfaces as triangle meshes, with the 6.837 curve editor's resolutions:
//! - [`curve_tessellation`]: `n` segments per cubic piece of a curve (`-curve_tessellation n`);
//! - [`revolution_tessellation`]: the profile tessellated so, revolved in `m` steps (`-revolution_tessellation m`);
//! - [`patch_tessellation`]: an `n x n` grid of quads, two triangles each (`-patch_tessellation n`).
//!
//! Vertices lie exactly on the surface; normals are the exact surface's analytic normals and uvs its parameters
//! (revolution: u around, v along the profile; patch: (u, v)), so a mesh shades like the exact surface up to the
//! interpolation, and its triangles wind counter-clockwise about the same normal (`dpdu x dpdv`). The seam of a
//! revolution is duplicated (u = 0 and u = 1); triangles that collapse (on the axis at poles, at a repeated
//! control point) are left out. Resolutions are checked: 1 to [`MAX_RESOLUTION`], and at most
//! [`MAX_TRIANGLES`] triangles in one mesh.

use super::curve::Curve;
use super::patch::patch_eval;
use crate::mesh::MeshData;
use glam::{DVec3, Vec2, Vec3};
use std::f64::consts::TAU;

/// Largest resolution accepted along one parameter.
pub const MAX_RESOLUTION: usize = 100_000;
/// Largest number of triangles of one tessellated surface.
pub const MAX_TRIANGLES: usize = 1 << 24;

/// Check a resolution given for `what`: an error message for 0 or more than [`MAX_RESOLUTION`].
pub fn check_resolution(what: &str, n: usize) -> Result<(), String> {
    if n == 0 {
        return Err(format!("{what} must be at least 1, got 0"));
    }
    if n > MAX_RESOLUTION {
        return Err(format!("{what} {n} is absurd (at most {MAX_RESOLUTION})"));
    }
    Ok(())
}

/// Points along a curve: `n` segments per cubic piece.
pub fn curve_tessellation(curve: &Curve, n: usize) -> Result<Vec<DVec3>, String> {
    check_resolution("curve tessellation", n)?;
    if curve.num_segments().saturating_mul(n) > MAX_TRIANGLES {
        return Err(format!("curve tessellation {n} gives more than {MAX_TRIANGLES} points"));
    }
    Ok(curve.tessellate(n))
}

/// The outward normal of a revolution at profile parameter `s` and angle `theta` (see `revolution.rs`).
pub fn revolution_normal(profile: &Curve, s: f64, theta: f64) -> DVec3 {
    let (lo, hi) = profile.hull_bounds();
    let size = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let mut tan = profile.derivative(s);
    if tan.length() <= 1e-9 * size {
        let h = 1e-4;
        let n = profile.num_segments() as f64;
        tan = if s + h <= n { profile.eval(s + h) - profile.eval(s) } else { profile.eval(s) - profile.eval(s - h) };
    }
    let (sn, cs) = theta.sin_cos();
    DVec3::new(-tan.y * cs, tan.x, -tan.y * sn).normalize_or(DVec3::Y)
}

/// The surface of revolution of `profile` about y as a mesh: `curve_n` segments per profile piece, `rev_n` steps
/// around.
pub fn revolution_tessellation(profile: &Curve, curve_n: usize, rev_n: usize) -> Result<MeshData, String> {
    check_resolution("curve tessellation", curve_n)?;
    check_resolution("revolution tessellation", rev_n)?;
    let segs = profile.num_segments();
    let rows = segs.saturating_mul(curve_n);
    if rows.saturating_mul(rev_n).saturating_mul(2) > MAX_TRIANGLES {
        return Err(format!(
            "tessellation {curve_n} x {rev_n} of {segs} profile pieces gives more than {MAX_TRIANGLES} triangles"
        ));
    }
    let mut mesh = MeshData { name: "revolution".into(), ..Default::default() };
    let cols = rev_n + 1;
    for k in 0..=rows {
        let s = k as f64 / curve_n as f64;
        let p = profile.eval(s);
        for j in 0..cols {
            let theta = TAU * j as f64 / rev_n as f64;
            let (sn, cs) = theta.sin_cos();
            mesh.positions.push(DVec3::new(p.x * cs, p.y, p.x * sn).as_vec3());
            mesh.normals.push(revolution_normal(profile, s, theta).as_vec3());
            mesh.uvs.push(Vec2::new(j as f32 / rev_n as f32, (s / segs as f64) as f32));
        }
    }
    let idx = |k: usize, j: usize| (k * cols + j) as u32;
    for k in 0..rows {
        for j in 0..rev_n {
            let (a, b, c, d) = (idx(k, j), idx(k, j + 1), idx(k + 1, j + 1), idx(k + 1, j));
            push_if_not_degenerate(&mut mesh, [a, b, c]);
            push_if_not_degenerate(&mut mesh, [a, c, d]);
        }
    }
    Ok(mesh)
}

/// A bicubic Bézier patch (16 points, rows of 4 along u) as an `n x n` grid.
pub fn patch_tessellation(ctrl: &[DVec3; 16], n: usize) -> Result<MeshData, String> {
    check_resolution("patch tessellation", n)?;
    if n.saturating_mul(n).saturating_mul(2) > MAX_TRIANGLES {
        return Err(format!("patch tessellation {n} gives more than {MAX_TRIANGLES} triangles"));
    }
    let mut mesh = MeshData { name: "patch".into(), ..Default::default() };
    for i in 0..=n {
        let v = i as f64 / n as f64;
        for j in 0..=n {
            let u = j as f64 / n as f64;
            let (p, su, sv) = patch_eval(ctrl, u, v);
            let mut nrm = su.cross(sv);
            if nrm.length_squared() == 0.0 || !nrm.is_finite() {
                let (_, su2, sv2) = patch_eval(ctrl, u + (0.5 - u) * 1e-3, v + (0.5 - v) * 1e-3);
                nrm = su2.cross(sv2);
            }
            mesh.positions.push(p.as_vec3());
            mesh.normals.push(nrm.normalize_or(DVec3::Y).as_vec3());
            mesh.uvs.push(Vec2::new(u as f32, v as f32));
        }
    }
    let idx = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j));
            push_if_not_degenerate(&mut mesh, [a, b, c]);
            push_if_not_degenerate(&mut mesh, [a, c, d]);
        }
    }
    Ok(mesh)
}

fn push_if_not_degenerate(mesh: &mut MeshData, t: [u32; 3]) {
    let p = t.map(|i| mesh.positions[i as usize]);
    if (p[1] - p[0]).cross(p[2] - p[0]) != Vec3::ZERO {
        mesh.indices.push(t);
    }
}

/// Several meshes as one (indices offset), named `name`.
pub fn merge_meshes(name: &str, parts: &[MeshData]) -> MeshData {
    let mut out = MeshData { name: name.into(), ..Default::default() };
    for m in parts {
        let base = out.positions.len() as u32;
        out.positions.extend_from_slice(&m.positions);
        out.normals.extend_from_slice(&m.normals);
        out.uvs.extend_from_slice(&m.uvs);
        out.indices.extend(m.indices.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

/// The mesh as Wavefront OBJ text (`v`, `vt`, `vn`, `f v/vt/vn`, 1-based indices).
pub fn to_obj(mesh: &MeshData, header: &str) -> String {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(64 * mesh.positions.len());
    for line in header.lines() {
        let _ = writeln!(s, "# {line}");
    }
    let _ = writeln!(s, "o {}", mesh.name);
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    let with_uv = mesh.uvs.len() == mesh.positions.len();
    let with_n = mesh.normals.len() == mesh.positions.len();
    if with_uv {
        for t in &mesh.uvs {
            let _ = writeln!(s, "vt {} {}", t.x, t.y);
        }
    }
    if with_n {
        for n in &mesh.normals {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    for t in &mesh.indices {
        let f = |i: u32| match (with_uv, with_n) {
            (true, true) => format!("{0}/{0}/{0}", i + 1),
            (true, false) => format!("{0}/{0}", i + 1),
            (false, true) => format!("{0}//{0}", i + 1),
            (false, false) => format!("{}", i + 1),
        };
        let _ = writeln!(s, "f {} {} {}", f(t[0]), f(t[1]), f(t[2]));
    }
    s
}
