//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2013).
//!
//! The ray is turned once into a shear-and-permute map that sends its direction to +z; each triangle's vertices
//! are mapped by it (`x = d[kx] - sx d[kz]`, `y = d[ky] - sy d[kz]`, `z = sz d[kz]` for a vertex less the origin
//! `d`: the matrix product without its zero and unit coefficients, the same numbers for two operations where the
//! full rows take five) and the 2D edge functions decide the hit. An edge shared by two triangles yields exactly
//! negated edge functions in both, so a ray through a shared edge or vertex hits at least one of them: no cracks.
//! Edge functions that come out exactly zero are recomputed in f64, as the paper prescribes. Hits closer than the
//! rounding error of t are rejected (pbrt-v4's conservative t bound), so rays leaving a surface never re-hit it.
//!
//! Triangles are tested in structure-of-arrays form ([`TriSoa`]: the three vertices' x, y and z in the lanes of
//! three vectors, 48 bytes like three `Vec3A`s): one SIMD pass maps all three vertices, the edge functions are one
//! lane rotation away, and the z row is only computed for hits. Every accelerator calls this one kernel, so all of
//! them compute bit-identical hits.

use super::{Ray, gamma};
use core::arch::x86_64::__m128;
use glam::{Vec3A, Vec3Swizzles, Vec4};

/// A triangle with its vertices' coordinates gathered per axis: lane i of `xs` is vertex i's x.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriSoa {
    /// The three vertices' x coordinates.
    pub xs: Vec3A,
    /// The three vertices' y coordinates.
    pub ys: Vec3A,
    /// The three vertices' z coordinates.
    pub zs: Vec3A,
}

impl TriSoa {
    /// The triangle of vertices `v[0]`, `v[1]`, `v[2]` (in that order, which sets its winding).
    #[inline]
    pub fn new(v: &[Vec3A; 3]) -> Self {
        TriSoa {
            xs: Vec3A::new(v[0].x, v[1].x, v[2].x),
            ys: Vec3A::new(v[0].y, v[1].y, v[2].y),
            zs: Vec3A::new(v[0].z, v[1].z, v[2].z),
        }
    }

    /// The vertices back in array form.
    #[inline]
    pub fn vertices(&self) -> [Vec3A; 3] {
        [
            Vec3A::new(self.xs.x, self.ys.x, self.zs.x),
            Vec3A::new(self.xs.y, self.ys.y, self.zs.y),
            Vec3A::new(self.xs.z, self.ys.z, self.zs.z),
        ]
    }
}

/// Per-ray precomputation: the permutation that makes the direction's largest component the last axis, the
/// origin's coordinates on the permuted axes and the shear that sends the direction to +z, each number splatted
/// across lanes. A vertex less the origin, `d`, maps to `x = d[kx] - sx d[kz]`, `y = d[ky] - sy d[kz]`, `z = sz
/// d[kz]`: the product of the shear/permutation matrix's rows `e_kx - sx e_kz`, `e_ky - sy e_kz`, `sz e_kz` with `d`
/// without its zero and unit coefficients, which give the same numbers (a product by 0 or 1 and a sum with zero
/// are exact) for two operations where the full rows take five.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    /// `(kx, ky, kz)`, kz the axis of the direction's largest component.
    axes: [Axis; 3],
    /// `(o[kx], o[ky], o[kz])`, splatted.
    origin_k: [Vec3A; 3],
    /// `(sx, sy, sz)`, splatted.
    shear: [Vec3A; 3],
}

/// A coordinate axis, as an index the compiler knows to be below 3 (no bounds checks where it picks a coordinate).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(usize)]
pub(super) enum Axis {
    X = 0,
    Y = 1,
    Z = 2,
}

impl Axis {
    const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];
}

/// Hit distance and barycentric weights of the three vertices.
#[derive(Clone, Copy, Debug)]
pub struct TriangleHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of vertex 0.
    pub b0: f32,
    /// Barycentric weight of vertex 1.
    pub b1: f32,
    /// Barycentric weight of vertex 2 (the three sum to 1 up to rounding).
    pub b2: f32,
}

impl WatertightRay {
    /// The shear-and-permute map of `ray` (its direction must not be zero).
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let d = ray.dir.to_array();
        let a = ray.dir.abs();
        // kz: the axis of the largest |d|, ties broken as by `x > y ? (x > z ? x : z) : (y > z ? y : z)`, but
        // computed without branches: the axis varies from ray to ray, and on bounce rays the branches were
        // mispredicted about once per ray (shadow and bounce rays of the Cornell box 10-12% faster).
        // The wide BVH's packets compute the same lane by lane (`Packet::new` in `accel/wide_bvh/packet.rs`): a change
        // here must be made there too (`packets_of_rays_get_the_closest_hit_each_ray_gets_alone` checks them).
        let (x_y, x_z, y_z) = ((a.x > a.y) as usize, (a.x > a.z) as usize, (a.y > a.z) as usize);
        let kz = x_y * (2 - 2 * x_z) + (1 - x_y) * (2 - y_z);
        let (kx, ky) = ([1, 2, 0][kz], [2, 0, 1][kz]);
        let (kx, ky) = if d[kz] < 0.0 { (ky, kx) } else { (kx, ky) };
        let sz = 1.0 / d[kz];
        let sx = d[kx] * sz;
        let sy = d[ky] * sz;
        let o = ray.origin.to_array();
        WatertightRay {
            axes: [Axis::ALL[kx], Axis::ALL[ky], Axis::ALL[kz]],
            origin_k: [Vec3A::splat(o[kx]), Vec3A::splat(o[ky]), Vec3A::splat(o[kz])],
            shear: [Vec3A::splat(sx), Vec3A::splat(sy), Vec3A::splat(sz)],
        }
    }

    /// The permutation `(kx, ky, kz)`, the origin on the permuted axes and the shear `(sx, sy, sz)`, the last two
    /// splatted across the four lanes of a `Vec4` (see the fields).
    #[inline(always)]
    pub(super) fn permuted4(&self) -> ([Axis; 3], [Vec4; 3], [Vec4; 3]) {
        let v = |a: Vec3A| Vec4::from(__m128::from(a));
        let [o0, o1, o2] = self.origin_k;
        let [s0, s1, s2] = self.shear;
        (self.axes, [v(o0), v(o1), v(o2)], [v(s0), v(s1), v(s2)])
    }

    /// The ray's origin and the shear/permutation rows (coefficient c of row r at `[r][c]`) as plain numbers, for
    /// kernels that test many rays at once lane by lane (the wide BVH's ray packets).
    #[inline(always)]
    pub fn coefficients(&self) -> ([f32; 3], [[f32; 3]; 3]) {
        let [kx, ky, kz] = self.axes.map(|a| a as usize);
        let [sx, sy, sz] = self.shear.map(|s| s.x);
        let mut origin = [0.0f32; 3];
        (origin[kx], origin[ky], origin[kz]) = (self.origin_k[0].x, self.origin_k[1].x, self.origin_k[2].x);
        // The rows entry by entry as the arithmetic e_kx - sx e_kz, ... gives them (1 - sx 0 = 1, 0 - sx 0 = +0,
        // 0 - sx = -sx, sz 0 = a zero of sz's sign).
        let mut rows = [[0.0f32; 3], [0.0f32; 3], [sz * 0.0; 3]];
        rows[0][kx] = 1.0;
        rows[0][kz] = 0.0 - sx;
        rows[1][ky] = 1.0;
        rows[1][kz] = 0.0 - sy;
        rows[2][kz] = sz;
        (origin, rows)
    }

    /// Intersect the triangle `(p0, p1, p2)`; hits with `t` in `(0, tmax)` only.
    #[inline(always)]
    pub fn intersect(&self, p0: Vec3A, p1: Vec3A, p2: Vec3A, tmax: f32) -> Option<TriangleHit> {
        self.intersect_soa(&TriSoa::new(&[p0, p1, p2]), tmax)
    }

    /// Intersect a triangle in SoA form; hits with `t` in `(0, tmax)` only.
    #[inline(always)]
    pub fn intersect_soa(&self, tri: &TriSoa, tmax: f32) -> Option<TriangleHit> {
        // Indexed, not matched: the axes vary from ray to ray, and a match compiled to branches that bounce rays
        // mispredicted.
        let coords = [tri.xs, tri.ys, tri.zs];
        let pick = |a: Axis| coords[a as usize];
        let ([kx, ky, kz], [okx, oky, okz], [sx, sy, sz]) = (self.axes, self.origin_k, self.shear);
        // Lane i holds vertex i's sheared coordinate.
        let dz = pick(kz) - okz;
        let x = pick(kx) - okx - sx * dz;
        let y = pick(ky) - oky - sy * dz;
        // Edge functions (U, V, W) = (x2 y1 - y2 x1, x0 y2 - y0 x2, x1 y0 - y1 x0): the barycentric weights of the
        // vertices opposite each edge. A shared edge gives exactly negated values in its two triangles.
        let mut uvw = x.zxy() * y.yzx() - y.zxy() * x.yzx();
        if uvw.cmpeq(Vec3A::ZERO).any() {
            let (x, y) = (x.to_array().map(f64::from), y.to_array().map(f64::from));
            uvw = Vec3A::new(
                (x[2] * y[1] - y[2] * x[1]) as f32,
                (x[0] * y[2] - y[0] * x[2]) as f32,
                (x[1] * y[0] - y[1] * x[0]) as f32,
            );
        }
        if uvw.cmplt(Vec3A::ZERO).any() && uvw.cmpgt(Vec3A::ZERO).any() {
            return None;
        }
        let (u, v, w) = (uvw.x, uvw.y, uvw.z);
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let z = sz * dz;
        let t_scaled = u * z.x + v * z.y + w * z.z;
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
        let max_zt = z.abs().max_element();
        let max_xt = x.abs().max_element();
        let max_yt = y.abs().max_element();
        let delta_z = gamma(3) * max_zt;
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = uvw.abs().max_element();
        let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
        if t <= delta_t {
            return None;
        }
        Some(TriangleHit { t, b0: u * inv, b1: v * inv, b2: w * inv })
    }
}
