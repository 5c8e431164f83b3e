//! Surface of revolution: a profile curve in the xy-plane (z = 0) revolved about the y axis,
//! `S(s, theta) = (x(s) cos theta, y(s), x(s) sin theta)`, intersected exactly.
//!
//! **Intersection** (object space, f64). The ray walks the profile's ring tree (`profile_tree.rs`) nearest first;
//! in each leaf ring it meets, Newton iteration on `(s, theta, t)` (`newton.rs`) starts from seeds taken from the
//! leaf's chord: the ray meets the cone (cylinder, disc) that the chord sweeps in closed form (a quadratic in
//! `t`), and each such root within the ring's intervals is a seed within the leaf's flatness of the true root;
//! an interval with no chord root (a ray grazing the bulge of the curve beyond its chord) is seeded at its middle.
//! Any converged root with `0 < t < tmax` is a true root and is kept if nearest; since every root lies in the ring
//! interval of its own leaf and leaves are visited nearest first until one starts beyond the best hit, the nearest
//! root is found whenever each leaf's Newton finds its own roots. Roots closer than `4e-10` of the object's size to
//! the ray origin are rejected (a ray starting on the surface does not hit itself).
//!
//! **Surface data.** Parameters `(s, theta)` travel in [`Hit`](crate::primitives::Hit) (`b1`, `b2`); the point is
//! `S(s, theta)` evaluated in f64 and mapped to world space in f64, then rounded to f32, so it lies on the surface
//! up to that rounding: its error bound is `2^-23 |p|` per coordinate plus `1e-9` of the world size (f64 rounding
//! and the iteration's tolerance), the bound secondary rays are offset by. The normal is analytic: the profile's
//! left normal `(-y', x')` revolved, `(-y' cos, x', -y' sin)`, outward for a profile drawn clockwise about the
//! solid (the 6.837 files' convention), defined on the axis too (poles); where the profile's derivative vanishes
//! (a triple control point: a cusp) the one-sided chord over `1e-4` of a segment replaces it. `uv = (theta / 2 pi,
//! s / segments)`: u goes around, v along the profile; `dpdu = 2 pi S_theta`, `dpdv = segments S_s`.

use super::curve::Curve;
use super::newton::{NewtonTol, ParamSurface, solve};
use super::profile_tree::{Leaf, ProfileTree, RingRay};
use super::{AnalyticShape, ShapeHit, ShapePoint};
use crate::geometry::{Bounds, Ray};
use glam::{DAffine3, DVec3, Mat3A, Vec2, Vec3A};
use std::f64::consts::TAU;

/// A surface of revolution with its seeding structure and transform.
#[derive(Clone, Debug)]
pub struct Revolution {
    profile: Curve,
    tree: ProfileTree,
    world_from_object: DAffine3,
    object_from_world: DAffine3,
    /// Linear part of `world_from_object` (for tangents) and its inverse transpose (for normals), f32.
    linear: Mat3A,
    normal_to_world: Mat3A,
    bounds: Bounds,
    /// Size of the profile (largest extent of its control points' box, and the radius).
    size: f64,
    pub material: u32,
    pub light: u32,
}

/// The surface in object space for the Newton iteration.
struct RevSurface<'a> {
    profile: &'a Curve,
    s_max: f64,
}

impl ParamSurface for RevSurface<'_> {
    #[inline]
    fn eval(&self, s: f64, theta: f64) -> (DVec3, DVec3, DVec3) {
        let (i, w) = self.profile.locate(s);
        let seg = &self.profile.bezier_segments()[i];
        let p = super::curve::bezier(seg, w);
        let dp = super::curve::bezier_d1(seg, w);
        let (sn, cs) = theta.sin_cos();
        (
            DVec3::new(p.x * cs, p.y, p.x * sn),
            DVec3::new(dp.x * cs, dp.y, dp.x * sn),
            DVec3::new(-p.x * sn, 0.0, p.x * cs),
        )
    }

    #[inline]
    fn clamp(&self, s: f64, theta: f64) -> (f64, f64) {
        (s.clamp(0.0, self.s_max), theta)
    }
}

impl Revolution {
    /// A revolution of `profile` (z = 0 checked by the loader) under `world_from_object`.
    pub fn new(profile: Curve, world_from_object: DAffine3, material: u32, light: u32) -> Revolution {
        let (lo, hi) = profile.hull_bounds();
        let r = lo.x.abs().max(hi.x.abs());
        let size = (hi - lo).max_element().max(r).max(f64::MIN_POSITIVE);
        let tree = ProfileTree::build(&profile, size);
        let ring = tree.root_ring();
        let obj_lo = DVec3::new(-ring.r_hi, ring.y_lo, -ring.r_hi);
        let obj_hi = DVec3::new(ring.r_hi, ring.y_hi, ring.r_hi);
        let bounds = super::profile_tree::world_box(&world_from_object, obj_lo, obj_hi);
        let inv = world_from_object.inverse();
        let linear = Mat3A::from(world_from_object.matrix3.as_mat3());
        let normal_to_world = Mat3A::from(inv.matrix3.transpose().as_mat3());
        Revolution {
            profile,
            tree,
            world_from_object,
            object_from_world: inv,
            linear,
            normal_to_world,
            bounds,
            size,
            material,
            light,
        }
    }

    pub fn profile(&self) -> &Curve {
        &self.profile
    }

    /// Leaves and nodes of the seeding structure (for statistics).
    pub fn seeding_stats(&self) -> (usize, usize) {
        (self.tree.leaves.len(), self.tree.num_nodes())
    }

    pub fn world_from_object(&self) -> &DAffine3 {
        &self.world_from_object
    }

    fn surface_fn(&self) -> RevSurface<'_> {
        RevSurface { profile: &self.profile, s_max: self.profile.num_segments() as f64 }
    }

    /// Nearest root in `(tmin, tmax)` of the object-space ray, `(s, theta, t)`; with `any`, the first one found.
    fn query(&self, o: DVec3, d: DVec3, tmax: f64, any: bool) -> Option<(f64, f64, f64)> {
        let ray = RingRay::new(o, d);
        let surf = self.surface_fn();
        let scale = self.size.max(o.length() * 1e-3);
        let tol = NewtonTol { stop: 1e-13 * scale, accept: 1e-9 * scale, max_iter: 24 };
        let dl = d.length();
        let tmin = 4e-10 * scale / dl;
        let mut best: Option<(f64, f64, f64)> = None;
        let mut best_t = tmax;
        let best_cell = std::cell::Cell::new(tmax);
        self.tree.traverse(
            &ray,
            tmin,
            || best_cell.get(),
            |leaf, iv| {
                for_each_seed(leaf, &ray, iv, |seed| {
                    if let Some((s, th, t)) = solve(&surf, o, d, seed, &tol)
                        && t > tmin
                        && t < best_t
                    {
                        best_t = t;
                        best = Some((s, th, t));
                    }
                });
                best_cell.set(best_t);
                !(any && best.is_some())
            },
        );
        best
    }

    fn object_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        let o = self.object_from_world.transform_point3(ray.origin.as_dvec3());
        let d = self.object_from_world.transform_vector3(ray.dir.as_dvec3());
        (o, d)
    }

    /// The profile tangent at `s`; at a zero derivative (a cusp), the one-sided chord.
    fn profile_tangent(&self, s: f64) -> DVec3 {
        let dp = self.profile.derivative(s);
        if dp.length() > 1e-9 * self.size {
            return dp;
        }
        let n = self.profile.num_segments() as f64;
        let h = 1e-4;
        if s + h <= n {
            self.profile.eval(s + h) - self.profile.eval(s)
        } else {
            self.profile.eval(s) - self.profile.eval(s - h)
        }
    }
}

/// Seeds `(s, theta, t)` for one leaf: roots of the chord's cone within the intervals, else interval middles.
#[inline]
fn for_each_seed(leaf: &Leaf, ray: &RingRay, iv: &super::profile_tree::Intervals, mut f: impl FnMut((f64, f64, f64))) {
    let (a, b) = (leaf.ctrl[0], leaf.ctrl[3]);
    let e = b - a;
    let len2 = e.x * e.x + e.y * e.y;
    let lambda_of = |t: f64| -> f64 {
        if len2 == 0.0 {
            return 0.5;
        }
        let rho = ray.rho2(t).max(0.0).sqrt();
        // Points with negative profile x sit at radius -x.
        let x = if a.x + b.x < 0.0 { -rho } else { rho };
        let y = ray.o.y + t * ray.d.y;
        (((x - a.x) * e.x + (y - a.y) * e.y) / len2).clamp(0.0, 1.0)
    };
    let seed_at = |t: f64| {
        let p = ray.o + ray.d * t;
        let lambda = lambda_of(t);
        let theta = if a.x + b.x < 0.0 { (-p.z).atan2(-p.x) } else { p.z.atan2(p.x) };
        (leaf.s0 + lambda * (leaf.s1 - leaf.s0), theta, t)
    };
    let mut roots = [0.0f64; 2];
    let n = chord_cone_roots(a, b, ray, &mut roots);
    for k in 0..iv.1 {
        let (t0, t1) = iv.0[k];
        let mut seeded = false;
        for &t in &roots[..n] {
            if t >= t0 && t <= t1 {
                f(seed_at(t));
                seeded = true;
            }
        }
        if !seeded {
            f(seed_at(0.5 * (t0 + t1)));
        }
    }
}

/// Roots `t` of the ray with the surface swept by the segment `a b` of the half-plane (a cone, cylinder or disc).
/// Returns how many were written (0 to 2).
fn chord_cone_roots(a: DVec3, b: DVec3, ray: &RingRay, out: &mut [f64; 2]) -> usize {
    let e = b - a;
    // Line m . (rho, y) = k with m normal to e.
    let (mx, my) = (-e.y, e.x);
    if mx == 0.0 && my == 0.0 {
        return 0;
    }
    let k = mx * a.x + my * a.y;
    let (o, d) = (ray.o, ray.d);
    // mx^2 rho^2(t) = (K - L t)^2 with K = k - my oy, L = my dy.
    let kk = k - my * o.y;
    let ll = my * d.y;
    let qa = mx * mx * (d.x * d.x + d.z * d.z) - ll * ll;
    let qb = mx * mx * (o.x * d.x + o.z * d.z) + kk * ll;
    let qc = mx * mx * (o.x * o.x + o.z * o.z) - kk * kk;
    let mut n = 0;
    let mut push = |t: f64| {
        // Keep roots on the chord's side of the axis and within the chord (with a margin).
        let y = o.y + t * d.y;
        let rho = ray.rho2(t).max(0.0).sqrt();
        let x = if a.x + b.x < 0.0 { -rho } else { rho };
        let len2 = e.x * e.x + e.y * e.y;
        let lambda = ((x - a.x) * e.x + (y - a.y) * e.y) / len2;
        // The other nappe of a double cone solves the squared equation too: keep points on the chord's line.
        let off_line = ((x - a.x) * mx + (y - a.y) * my).abs() > 0.1 * len2;
        if t.is_finite() && (-0.25..=1.25).contains(&lambda) && !off_line && n < 2 {
            out[n] = t;
            n += 1;
        }
    };
    if qa.abs() <= 1e-12 * (qb.abs() + qc.abs()).max(f64::MIN_POSITIVE) {
        if qb != 0.0 {
            push(-qc / (2.0 * qb));
        }
        return n;
    }
    let disc = qb * qb - qa * qc;
    if disc < 0.0 {
        return 0;
    }
    let q = -(qb + disc.sqrt().copysign(qb));
    if q == 0.0 {
        push(0.0);
        return n;
    }
    let (t0, t1) = (q / qa, qc / q);
    push(t0.min(t1));
    push(t0.max(t1));
    n
}

impl AnalyticShape for Revolution {
    fn bounds(&self) -> Bounds {
        self.bounds
    }

    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.object_ray(ray);
        let (s, th, t) = self.query(o, d, ray.tmax as f64, false)?;
        let t32 = t as f32;
        (t32 < ray.tmax && t32 > 0.0).then(|| ShapeHit { t: t32, u: s as f32, v: th.rem_euclid(TAU) as f32 })
    }

    #[inline]
    fn occludes(&self, ray: &Ray) -> bool {
        let (o, d) = self.object_ray(ray);
        self.query(o, d, ray.tmax as f64, true).is_some_and(|(_, _, t)| (t as f32) < ray.tmax)
    }

    fn overlaps_box(&self, b: &Bounds) -> bool {
        self.tree.overlaps(&self.world_from_object, b)
    }

    fn clip_bounds(&self, voxel: &Bounds) -> Option<Bounds> {
        self.tree.clipped(&self.world_from_object, voxel)
    }

    fn surface(&self, _ray: &Ray, hit: &ShapeHit) -> ShapePoint {
        let (s, theta) = (hit.u as f64, hit.v as f64);
        let (p_obj, s_s, s_theta) = self.surface_fn().eval(s, theta);
        let pw = self.world_from_object.transform_point3(p_obj);
        let p = Vec3A::from(pw.as_vec3());
        let world_size = self.bounds.diagonal().length();
        let p_err = p.abs() * f32::EPSILON + Vec3A::splat(1e-9 * world_size);
        let tan = self.profile_tangent(s);
        let (sn, cs) = theta.sin_cos();
        let n_obj = DVec3::new(-tan.y * cs, tan.x, -tan.y * sn);
        let n = (self.normal_to_world * Vec3A::from(n_obj.as_vec3())).normalize_or(Vec3A::Y);
        let segs = self.profile.num_segments() as f64;
        let dpdu = self.linear * Vec3A::from((s_theta * TAU).as_vec3());
        let dpdv = self.linear * Vec3A::from((s_s * segs).as_vec3());
        ShapePoint { p, p_err, n, uv: Vec2::new((theta / TAU) as f32, (s / segs) as f32), dpdu, dpdv }
    }

    fn point_at_uv(&self, uv: Vec2) -> Option<ShapePoint> {
        let segs = self.profile.num_segments() as f64;
        let hit = ShapeHit { t: 0.0, u: (uv.y as f64 * segs) as f32, v: (uv.x as f64 * TAU) as f32 };
        Some(self.surface(&Ray::new(Vec3A::ZERO, Vec3A::X), &hit))
    }

    fn material(&self) -> u32 {
        self.material
    }

    fn light(&self) -> u32 {
        self.light
    }
}
