//! Surface of revolution: a profile curve in the xy-plane (z = 0) revolved about the y axis,
//! `S(s, theta) = (x(s) cos theta, y(s), x(s) sin theta)`, intersected exactly.
//!
//! **Intersection** (object space, f64). The ray walks the profile's ring tree (`profile_tree.rs`) nearest first;
//! in each leaf ring it meets, the part inside the leaf's strip (`strip.rs`), split where the ray is closest to
//! the axis, is a *span* that holds every root of the leaf. Newton iteration on `(s, theta, t)` (`newton.rs`)
//! starts from seeds (`revolution_seeds.rs`): the roots of the cone the leaf's chord sweeps within the span, else
//! its middle. A root found well inside the span or at a grazing angle is followed by a seed where the local
//! curvature model puts the other root and one at the span's start; a span where no seed reaches the leaf's own
//! root gets seeds across it and, if the ray runs along the band, a one-dimensional isolation of its crossings; a
//! ray starting on the surface recognises the root at its origin and looks for a crossing beyond it. Any converged
//! root with `0 < t < tmax` is a true root and is kept if nearest; since every root lies in the span of its own
//! leaf and leaves are visited nearest first until one starts beyond the best hit, the nearest root is found
//! whenever each leaf's Newton finds its own roots (`tests/curve_stability.rs` counts when it does not). Roots
//! closer than `4e-10` of the object's size to the ray origin are rejected (a ray starting on the surface does not
//! hit itself).
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
use super::newton::{NewtonTol, ParamSurface, other_root_offset, solve};
use super::profile_tree::{ProfileTree, RingRay};
use super::revolution_seeds::{chord_cone_roots, isolate_crossings, runs_along, seed_at};
use super::strip::Spans;
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
    /// Index into the scene's material table.
    pub material: u32,
    /// Area light slot, or [`crate::primitives::NO_LIGHT`].
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

    #[inline]
    fn max_step(&self) -> (f64, f64) {
        (0.5, 1.0)
    }

    fn second(&self, s: f64, theta: f64) -> (DVec3, DVec3, DVec3) {
        let (i, w) = self.profile.locate(s);
        let seg = &self.profile.bezier_segments()[i];
        let p = super::curve::bezier(seg, w);
        let dp = super::curve::bezier_d1(seg, w);
        let ddp = super::curve::bezier_d2(seg, w);
        let (sn, cs) = theta.sin_cos();
        (
            DVec3::new(ddp.x * cs, ddp.y, ddp.x * sn),
            DVec3::new(-dp.x * sn, 0.0, dp.x * cs),
            DVec3::new(-p.x * cs, 0.0, -p.x * sn),
        )
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

    /// The profile curve, object space (the xy-plane).
    pub fn profile(&self) -> &Curve {
        &self.profile
    }

    /// Leaves and nodes of the seeding structure (for statistics).
    pub fn seeding_stats(&self) -> (usize, usize) {
        (self.tree.leaves.len(), self.tree.num_nodes())
    }

    /// The transform from the profile's object space to world space.
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
        let tol = NewtonTol { stop: 1e-13 * scale, accept: 1e-9 * scale, max_iter: 16 };
        let dl = d.length();
        let tmin = 4e-10 * scale / dl;
        // Roots this close to the origin are the surface a ray starts on.
        let self_eps = 1e-6 * scale / dl;
        let mut best: Option<(f64, f64, f64)> = None;
        let mut best_t = tmax;
        let best_cell = std::cell::Cell::new(tmax);
        self.tree.traverse(
            &ray,
            tmin,
            || best_cell.get(),
            |leaf, iv| {
                let spans = match &leaf.strip {
                    Some(strip) => strip.clip(&ray, &iv.0[..iv.1]),
                    None => {
                        let mut s = Spans::EMPTY;
                        s.iv[..iv.1].copy_from_slice(&iv.0[..iv.1]);
                        s.n = iv.1;
                        s
                    }
                };
                let mut roots = [0.0f64; 2];
                let nroots = chord_cone_roots(leaf.ctrl[0], leaf.ctrl[3], &ray, &mut roots);
                // Split the spans where the ray is closest to the axis: on each side the ray's distance from the axis
                // is monotone, so a flat piece is crossed once except near tangency.
                let (qa, tc, _) = ray.centered();
                let tc = if qa > 0.0 { tc } else { f64::NEG_INFINITY };
                let mut pieces = [(0.0f64, 0.0f64); 8];
                let mut np = 0;
                for &(t0, t1) in spans.as_slice() {
                    if tc > t0 && tc < t1 {
                        pieces[np] = (t0, tc);
                        pieces[np + 1] = (tc, t1);
                        np += 2;
                    } else {
                        pieces[np] = (t0, t1);
                        np += 1;
                    }
                }
                for &(t0, t1) in &pieces[..np] {
                    if t0 > best_t {
                        break;
                    }
                    // The root Newton reaches from `t`: kept if nearest; `Some((root, at_origin))` if it is this
                    // leaf's root within the span, usable or at the origin of a ray starting on the surface.
                    let mut try_seed = |t: f64| -> Option<((f64, f64, f64), bool)> {
                        let r = solve(&surf, o, d, seed_at(leaf, &ray, t), &tol);
                        let (s, th, tr) = r?;
                        if tr > tmin && tr < best_t {
                            best_t = tr;
                            best = Some((s, th, tr));
                        }
                        let slack = 1e-9 * (leaf.s1 - leaf.s0);
                        let w = 1e-6 * (t1 - t0) + tol.accept / dl;
                        // The root at the origin of a ray starting on the surface counts for every leaf near it.
                        let at_origin = tr.abs() <= self_eps;
                        (at_origin
                            || (s >= leaf.s0 - slack
                                && s <= leaf.s1 + slack
                                && tr > tmin
                                && tr >= t0 - w
                                && tr <= t1 + w))
                            .then_some(((s, th, tr), at_origin))
                    };
                    // Seeds: the chord's roots in the span, else its middle.
                    let mut own: Option<((f64, f64, f64), bool)> = None;
                    let mut seeded = false;
                    for &t in &roots[..nroots] {
                        if t >= t0 && t <= t1 {
                            let r = try_seed(t);
                            own = own.or(r);
                            seeded = true;
                        }
                    }
                    if !seeded {
                        own = try_seed(0.5 * (t0 + t1));
                    }
                    let w = t1 - t0;
                    // No seed reached this leaf's root: more seeds across the span; still nothing, and the ray runs
                    // along the leaf (grazing the band: two close roots that seeds far from them miss): isolate its
                    // crossings in one dimension.
                    if own.is_none() {
                        for f in [0.05, 0.5, 0.95] {
                            own = try_seed(t0 + f * w);
                            if own.is_some() {
                                break;
                            }
                        }
                        if own.is_none() && runs_along(leaf, &ray, t0, t1) {
                            let mut seeds = [0.0f64; 4];
                            let k = isolate_crossings(leaf, &ray, t0, t1, 9, &mut seeds);
                            for &t in &seeds[..k] {
                                try_seed(t);
                            }
                        }
                    }
                    match own {
                        // The ray starts on this leaf: it meets it again only where the surface curves back.
                        Some(((s, th, t), true)) => {
                            let (dt, _) = other_root_offset(&surf, s, th, d).unwrap_or((f64::INFINITY, 0.0));
                            let again = dt > 0.0 && t + dt < t1 && try_seed(t + dt).is_some_and(|r| !r.1);
                            // Otherwise look for a crossing beyond the origin in one dimension (thoroughly when the
                            // ray leaves nearly along the band).
                            let from = t0.max(4.0 * self_eps);
                            if !again && from < t1 {
                                let samples = if runs_along(leaf, &ray, from, t1) { 9 } else { 3 };
                                let mut seeds = [0.0f64; 4];
                                let k = isolate_crossings(leaf, &ray, from, t1, samples, &mut seeds);
                                for &t in &seeds[..k] {
                                    try_seed(t);
                                }
                            }
                        }
                        // A root well inside the span may hide a nearer one: a ray cutting through a band twice (try
                        // from the span's start), or grazing it (try where the surface's curvature brings it back).
                        Some(((s, th, t), false)) => {
                            let (dt, cos) = other_root_offset(&surf, s, th, d).unwrap_or((f64::INFINITY, 0.0));
                            if dt < 0.0 && t + dt > t0 {
                                try_seed(t + dt);
                            }
                            if t > t0 + 0.1 * w || cos.abs() < 0.05 {
                                let before = try_seed(t0 + 1e-3 * (t - t0));
                                // Grazing, and still no nearer root: isolate crossings before it in one dimension
                                // (near a cone apex, where the profile crosses the axis, the curvature model fails),
                                // up to just before the root found, so that its own sign change is seen.
                                if cos.abs() < 0.05
                                    && before.is_none_or(|r| r.0.2 >= t)
                                    && runs_along(leaf, &ray, t0, t)
                                {
                                    let mut seeds = [0.0f64; 4];
                                    let k = isolate_crossings(leaf, &ray, t0, t - 1e-3 * (t - t0), 9, &mut seeds);
                                    for &ts in &seeds[..k] {
                                        try_seed(ts);
                                    }
                                }
                            }
                        }
                        None => {}
                    }
                }
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
