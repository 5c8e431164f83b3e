//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2013).
//!
//! The ray is turned once into a shear-and-permute map that sends its direction to +z; each triangle's vertices
//! are mapped by it and the 2D edge functions decide the hit. An edge shared by two triangles yields exactly
//! negated edge functions in both, so a ray through a shared edge or vertex hits at least one of them: no cracks.
//! Edge functions that come out exactly zero are recomputed in f64, as the paper prescribes. Hits closer than the
//! rounding error of t are rejected (pbrt-v4's conservative t bound), so rays leaving a surface never re-hit it.

use super::{Ray, gamma};
use glam::{Mat3A, Vec3A};

/// Per-ray precomputation: origin and the shear/permutation matrix.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    /// Rows: e_kx - sx e_kz, e_ky - sy e_kz, sz e_kz (applied as a matrix so it stays SIMD-friendly).
    shear: Mat3A,
}

/// Hit distance and barycentric weights of the three vertices.
#[derive(Clone, Copy, Debug)]
pub struct TriangleHit {
    pub t: f32,
    pub b0: f32,
    pub b1: f32,
    pub b2: f32,
}

impl WatertightRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / d[kz];
        let sx = d[kx] * sz;
        let sy = d[ky] * sz;
        let e = |k: usize| match k {
            0 => Vec3A::X,
            1 => Vec3A::Y,
            _ => Vec3A::Z,
        };
        let row0 = e(kx) - sx * e(kz);
        let row1 = e(ky) - sy * e(kz);
        let row2 = sz * e(kz);
        WatertightRay { origin: ray.origin, shear: Mat3A::from_cols(row0, row1, row2).transpose() }
    }

    /// Intersect the triangle `(p0, p1, p2)`; hits with `t` in `(0, tmax)` only.
    #[inline(always)]
    pub fn intersect(&self, p0: Vec3A, p1: Vec3A, p2: Vec3A, tmax: f32) -> Option<TriangleHit> {
        let a = self.shear * (p0 - self.origin);
        let b = self.shear * (p1 - self.origin);
        let c = self.shear * (p2 - self.origin);
        let mut u = c.x * b.y - c.y * b.x;
        let mut v = a.x * c.y - a.y * c.x;
        let mut w = b.x * a.y - b.y * a.x;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let (ax, ay, bx, by, cx, cy) = (a.x as f64, a.y as f64, b.x as f64, b.y as f64, c.x as f64, c.y as f64);
            u = (cx * by - cy * bx) as f32;
            v = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = u * a.z + v * b.z + w * c.z;
        if det > 0.0 {
            if t_scaled <= 0.0 || t_scaled >= tmax * det {
                return None;
            }
        } else if t_scaled >= 0.0 || t_scaled <= tmax * det {
            return None;
        }
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        // Reject t within its rounding error of 0 (pbrt-v4 section 6.8.4): a ray that starts exactly on the
        // triangle's plane (an exactly representable surface point, whose spawn offset is 0) must not re-hit it.
        let max_zt = a.z.abs().max(b.z.abs()).max(c.z.abs());
        let max_xt = a.x.abs().max(b.x.abs()).max(c.x.abs());
        let max_yt = a.y.abs().max(b.y.abs()).max(c.y.abs());
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = u.abs().max(v.abs()).max(w.abs());
        let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
        if t <= delta_t {
            return None;
        }
        Some(TriangleHit { t, b0: u * inv, b1: v * inv, b2: w * inv })
    }
}
