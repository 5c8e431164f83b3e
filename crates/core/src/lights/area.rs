//! Area lights: an emissive triangle set (quad, mesh, triangle), sphere (or ellipsoid), or curved surface
//! (revolution, Bézier patch), emitting radiance `L` from its front side (the side of the geometric normal) or
//! from both sides.
//!
//! - Next-event estimation (`sample`/`pdf`): triangle sets by area (a triangle chosen in proportion to its area,
//!   then a uniform point), spheres uniform in the subtended cone, ellipsoids uniform on the object-space sphere
//!   with the exact area Jacobian, curved surfaces by area through `shapes::area_sampling` (a cell of the
//!   parameter square by approximate area, a uniform point in it, pdf `p(u, v) / |dp/du x dp/dv|` exactly).
//! - Emission (`sample_le`/`pdf_le`): a point uniform by area (ellipsoids: object-space uniform, with the area
//!   Jacobian in the pdf), then a cosine-distributed direction about the normal (two-sided lights pick each side
//!   with probability 1/2). Power `pi A L`, twice that for two-sided lights.
//! - Textured emission (glTF's emissive texture): the radiance at a point is `L * texture(uv)`. Points are still
//!   sampled uniformly by area (unbiased for any texture); the power, which only weighs the choice between lights,
//!   integrates the texture over each triangle with 16 stratified points (spheres: 256 points).

use super::{LeSample, LightSample};
use crate::geometry::{gamma, spawn_ray};
use crate::math::Frame;
use crate::primitives::{EntityPrims, Primitives, SurfaceHit, interpolation_error, sphere_point_error, sphere_uv};
use crate::sampling::warp;
use crate::shapes::area_sampling::ParamAreaSampler;
use crate::texture::ImageMap;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

/// The surface of an area light, with what its point sampling needs.
#[derive(Clone, Debug)]
pub enum AreaShape {
    /// Triangles `first..first+count` of the primitives; `cdf[k]` = area of the first k+1 triangles / total;
    /// `normals[k]` the unit geometric normal of triangle k.
    /// `parallelogram`: when the set is two triangles forming one (a `Quad`) and the light is untextured, its
    /// corner, edges and the point error bound: points are drawn as `o + u e1 + v e2`, which keeps the sampler's
    /// 2D stratification intact (no triangle choice, no square-root warp) and costs less.
    Triangles {
        /// Index of the set's first triangle in `Primitives::tris` (and its primitive id).
        first: u32,
        /// Number of triangles.
        count: u32,
        /// Cumulative area fractions, one per triangle, the last exactly 1.
        cdf: Vec<f32>,
        /// Unit geometric normal of each triangle.
        normals: Vec<Vec3A>,
        /// Total world-space area.
        area: f32,
        /// The set as one parallelogram, when it is one (see above).
        parallelogram: Option<Parallelogram>,
    },
    /// Sphere `index` of the primitives.
    Sphere {
        /// Index into `Primitives::spheres` (a sphere, or an ellipsoid through its transform).
        index: u32,
    },
    /// A curved analytic primitive `prim` (revolution, patch): a point of its parameter square drawn by
    /// `sampler`, density by area `p(u, v) / |dp/du x dp/dv|`.
    Curved {
        /// The shape's primitive id (`num_tris()` plus its analytic index).
        prim: u32,
        /// Draws parameter points by approximate area.
        sampler: ParamAreaSampler,
    },
}

/// A parallelogram light: points `o + u e1 + v e2` for `(u, v)` in the unit square; `err` bounds the rounding
/// error of such a point (per coordinate).
#[derive(Clone, Copy, Debug)]
pub struct Parallelogram {
    o: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
    err: Vec3A,
}

impl Parallelogram {
    /// The parallelogram two triangles form, if they do: they share an edge `(s1, s2)` and their other corners
    /// `p`, `r` satisfy `p + r = s1 + s2` (the diagonals bisect each other), with the same orientation.
    fn of(t: &[[Vec3A; 3]]) -> Option<Self> {
        let [a, b] = t else { return None };
        let shared: Vec<Vec3A> = a.iter().copied().filter(|v| b.contains(v)).collect();
        let [s1, s2] = shared[..] else { return None };
        let p = *a.iter().find(|v| !shared.contains(v))?;
        let r = *b.iter().find(|v| !shared.contains(v))?;
        let scale = p.abs().max(r.abs()).max(s1.abs()).max(s2.abs()).max_element().max(f32::MIN_POSITIVE);
        let na = (a[1] - a[0]).cross(a[2] - a[0]);
        let nb = (b[1] - b[0]).cross(b[2] - b[0]);
        if ((p + r) - (s1 + s2)).abs().max_element() > 1e-6 * scale || na.dot(nb) <= 0.0 {
            return None;
        }
        let (e1, e2) = (s1 - p, s2 - p);
        Some(Parallelogram { o: p, e1, e2, err: gamma(7) * (p.abs() + s1.abs() + s2.abs() + r.abs()) })
    }
}

/// An emissive surface: radiance `radiance` (times the emission texture) leaving its front side, or both sides.
#[derive(Clone, Debug)]
pub struct AreaLight {
    /// Emitted radiance per RGB channel, linear (the texture's factor where there is one).
    pub radiance: Vec3,
    /// Emit from both sides; otherwise only towards the side the geometric normal points to.
    pub two_sided: bool,
    /// The emitting surface.
    pub shape: AreaShape,
    /// Emission texture: the radiance at uv is `radiance * texture(uv)`.
    pub texture: Option<ImageMap>,
    /// Mean of the texture over the surface (by area), per channel; 1 without a texture.
    texture_mean: Vec3,
}

fn tri_area(t: &[Vec3A; 3]) -> f32 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

impl AreaLight {
    /// The light over the primitives `ep` one entity produced: its sphere, its curved shape, or its triangles (two
    /// that form a parallelogram, untextured, are sampled as one). A texture's area-weighted mean is integrated
    /// here, once: it scales [`AreaLight::power`].
    pub fn new(
        prims: &Primitives,
        ep: &EntityPrims,
        radiance: Vec3,
        two_sided: bool,
        texture: Option<ImageMap>,
    ) -> Self {
        let shape = match (ep.sphere, ep.curved) {
            (Some(index), _) => AreaShape::Sphere { index },
            (None, Some(k)) => {
                let prim = prims.num_tris() + k;
                let sampler = ParamAreaSampler::new(|u, v| {
                    prims.analytic_point_at(prim, Vec2::new(u, v)).map_or(0.0, |q| q.dpdu.cross(q.dpdv).length())
                });
                AreaShape::Curved { prim, sampler }
            }
            (None, None) => {
                let tris = &prims.tris[ep.first_tri as usize..(ep.first_tri + ep.tri_count) as usize];
                let mut acc = 0.0f64;
                let mut cdf: Vec<f32> = tris
                    .iter()
                    .map(|t| {
                        acc += tri_area(t) as f64;
                        acc as f32
                    })
                    .collect();
                let area = acc as f32;
                cdf.iter_mut().for_each(|c| *c /= area);
                if let Some(last) = cdf.last_mut() {
                    *last = 1.0;
                }
                let normals = tris.iter().map(crate::primitives::triangle_normal).collect();
                let parallelogram = if texture.is_none() { Parallelogram::of(tris) } else { None };
                AreaShape::Triangles { first: ep.first_tri, count: ep.tri_count, cdf, normals, area, parallelogram }
            }
        };
        let mut light = AreaLight { radiance, two_sided, shape, texture, texture_mean: Vec3::ONE };
        if light.texture.is_some() {
            light.texture_mean = light.mean_texture(prims);
        }
        light
    }

    /// Radiance emitted at surface parameter `uv` (towards the emitting side).
    #[inline]
    pub fn radiance_at(&self, uv: Vec2) -> Vec3 {
        match &self.texture {
            None => self.radiance,
            Some(t) => self.radiance * t.eval(uv),
        }
    }

    /// Area-weighted mean of the emission texture: 16 stratified points per triangle (256 on a sphere).
    fn mean_texture(&self, prims: &Primitives) -> Vec3 {
        let n = 4;
        let strata = |f: &mut dyn FnMut(Vec2)| {
            for i in 0..n {
                for j in 0..n {
                    f(Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                }
            }
        };
        let mut sum = glam::DVec3::ZERO;
        let mut weight = 0.0f64;
        match &self.shape {
            AreaShape::Triangles { first, count, .. } => {
                for k in *first..*first + *count {
                    let a = tri_area(&prims.tris[k as usize]) as f64;
                    let uvs = prims.tri_shading[k as usize].uvs;
                    strata(&mut |u| {
                        let (b0, b1, b2) = warp::uniform_triangle(u);
                        let uv = b0 * uvs[0] + b1 * uvs[1] + b2 * uvs[2];
                        sum += self.radiance_at(uv).as_dvec3() * (a / (n * n) as f64);
                    });
                    weight += a;
                }
            }
            AreaShape::Sphere { index } => {
                let r = prims.spheres[*index as usize].radius;
                for _ in 0..4 {
                    strata(&mut |u| {
                        let (uv, ..) = sphere_uv(warp::uniform_sphere(u), r);
                        sum += self.radiance_at(uv).as_dvec3();
                        weight += 1.0;
                    });
                }
            }
            AreaShape::Curved { prim, .. } => {
                // Midpoint rule over the parameter square, weighted by the area element.
                for _ in 0..16 {
                    strata(&mut |u| {
                        if let Some(q) = prims.analytic_point_at(*prim, u) {
                            let jac = q.dpdu.cross(q.dpdv).length() as f64;
                            if jac.is_finite() {
                                sum += self.radiance_at(u).as_dvec3() * jac;
                                weight += jac;
                            }
                        }
                    });
                }
            }
        }
        let mean = if weight > 0.0 { (sum / weight).as_vec3() } else { Vec3::ZERO };
        // The mean relative to the constant factor (the factor itself enters `power` separately).
        Vec3::select(
            self.radiance.cmpgt(Vec3::ZERO),
            mean / self.radiance.max(Vec3::splat(f32::MIN_POSITIVE)),
            Vec3::ZERO,
        )
    }

    /// Total surface area (exact for triangle sets and spheres; for ellipsoids the area integral by a 256 x 512
    /// midpoint quadrature of the Jacobian over the object-space sphere, relative error below 1e-5).
    pub fn area(&self, prims: &Primitives) -> f32 {
        match &self.shape {
            AreaShape::Triangles { area, .. } => *area,
            AreaShape::Curved { sampler, .. } => sampler.area(),
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                let r2 = s.radius as f64 * s.radius as f64;
                match &s.transform {
                    None => (4.0 * std::f64::consts::PI * r2) as f32,
                    Some(x) => {
                        // dA_world = |det M| |M^-T n| dA_object over the unit sphere, uniform in (z, phi).
                        let det = x.world_from_object.matrix3.determinant().abs() as f64;
                        let (nz, nphi) = (256, 512);
                        let mut sum = 0.0f64;
                        for i in 0..nz {
                            let z = -1.0 + (2.0 * i as f64 + 1.0) / nz as f64;
                            let r = (1.0 - z * z).max(0.0).sqrt();
                            for j in 0..nphi {
                                let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * std::f64::consts::PI;
                                let n = Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                                sum += (x.normal_to_world * n).length() as f64;
                            }
                        }
                        (det * r2 * 4.0 * std::f64::consts::PI * sum / (nz * nphi) as f64) as f32
                    }
                }
            }
        }
    }

    /// Total emitted power: `pi A L`, doubled for a two-sided light.
    pub fn power(&self, prims: &Primitives) -> Vec3 {
        self.radiance * self.texture_mean * (PI * self.area(prims) * if self.two_sided { 2.0 } else { 1.0 })
    }

    /// A uniform point by area: (point, error bound, unit normal, area pdf, emitted radiance there).
    #[inline(always)]
    fn sample_point(&self, prims: &Primitives, u: Vec2) -> (Vec3A, Vec3A, Vec3A, f32, Vec3) {
        match &self.shape {
            AreaShape::Triangles { parallelogram: Some(g), normals, area, .. } => {
                let q = g.o + u.x * g.e1 + u.y * g.e2;
                (q, g.err, normals[0], 1.0 / area, self.radiance)
            }
            AreaShape::Triangles { first, count, cdf, normals, area, .. } => {
                let k = cdf.partition_point(|&c| c <= u.x).min(*count as usize - 1);
                let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
                let ux = ((u.x - lo) / (cdf[k] - lo)).clamp(0.0, 1.0 - f32::EPSILON);
                let t = &prims.tris[*first as usize + k];
                let (b0, b1, b2) = warp::uniform_triangle(Vec2::new(ux, u.y));
                let q = b0 * t[0] + b1 * t[1] + b2 * t[2];
                let le = match &self.texture {
                    None => self.radiance,
                    Some(_) => {
                        let uvs = prims.tri_shading[*first as usize + k].uvs;
                        self.radiance_at(b0 * uvs[0] + b1 * uvs[1] + b2 * uvs[2])
                    }
                };
                (q, interpolation_error([b0, b1, b2], t), normals[k], 1.0 / area, le)
            }
            AreaShape::Curved { prim, sampler } => {
                let (uv, pdf_uv) = sampler.sample(u);
                match prims.analytic_point_at(*prim, uv) {
                    Some(q) => {
                        let jac = q.dpdu.cross(q.dpdv).length();
                        // A degenerate point (zero area element) has no density: its sample is dropped.
                        let pdf = if jac > 0.0 { pdf_uv / jac } else { f32::INFINITY };
                        (q.p, q.p_err, q.n, pdf, self.radiance_at(uv))
                    }
                    None => (Vec3A::ZERO, Vec3A::ZERO, Vec3A::Z, f32::INFINITY, Vec3::ZERO),
                }
            }
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                let no = warp::uniform_sphere(u);
                let le = match &self.texture {
                    None => self.radiance,
                    Some(_) => self.radiance_at(sphere_uv(no, s.radius).0),
                };
                match &s.transform {
                    None => (
                        s.center + no * s.radius,
                        sphere_point_error(s.center, no * s.radius, None),
                        no,
                        1.0 / (4.0 * PI * s.radius * s.radius),
                        le,
                    ),
                    Some(x) => {
                        let q = x.world_from_object.transform_point3a(s.center + no * s.radius);
                        let nw = x.normal_to_world * no;
                        let jac = x.world_from_object.matrix3.determinant().abs() * nw.length();
                        let err = sphere_point_error(s.center, no * s.radius, Some(x));
                        (q, err, nw.normalize(), 1.0 / (4.0 * PI * s.radius * s.radius * jac), le)
                    }
                }
            }
        }
    }

    /// An emitted ray: a point uniform by area (`u_pos`), a cosine-distributed direction (`u_dir`; a two-sided
    /// light first picks its side with `u_dir.x`). The origin is offset off the surface.
    #[inline]
    pub fn sample_le(&self, prims: &Primitives, u_pos: Vec2, u_dir: Vec2) -> Option<LeSample> {
        let (p, p_err, n, pdf_pos, le) = self.sample_point(prims, u_pos);
        let (side, u_dir, side_prob) = if self.two_sided {
            if u_dir.x < 0.5 {
                (n, Vec2::new(2.0 * u_dir.x, u_dir.y), 0.5)
            } else {
                (-n, Vec2::new((2.0 * u_dir.x - 1.0).min(1.0 - f32::EPSILON), u_dir.y), 0.5)
            }
        } else {
            (n, u_dir, 1.0)
        };
        let local = warp::cosine_hemisphere(u_dir);
        let pdf_dir = warp::cosine_hemisphere_pdf(local) * side_prob;
        if pdf_dir <= 0.0 || !pdf_pos.is_finite() {
            return None;
        }
        let dir = Frame::from_normal(side).to_world(local);
        Some(LeSample { ray: spawn_ray(p, p_err, n, dir), le, n: side, pdf_pos, pdf_dir })
    }

    /// Position (area) and direction (solid angle) pdfs of an emitted ray leaving the point `p` (on the light, with
    /// unit geometric normal `n`) in the unit direction `dir`.
    pub fn pdf_le(&self, prims: &Primitives, p: Vec3A, n: Vec3A, dir: Vec3A) -> (f32, f32) {
        let cos = dir.dot(n);
        let pdf_dir = if self.two_sided { 0.5 * cos.abs() / PI } else { cos.max(0.0) / PI };
        let pdf_pos = match &self.shape {
            AreaShape::Triangles { area, .. } => 1.0 / area,
            // The position density of a curved surface depends on the surface parameters, which a world point
            // does not give: the mean density 1/area is returned (no integrator uses it; `sample_le` returns the
            // exact one).
            AreaShape::Curved { sampler, .. } => 1.0 / sampler.area(),
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                match &s.transform {
                    None => 1.0 / (4.0 * PI * s.radius * s.radius),
                    Some(x) => {
                        let no = (x.object_from_world.transform_point3a(p) - s.center).normalize();
                        let jac = x.world_from_object.matrix3.determinant().abs() * (x.normal_to_world * no).length();
                        1.0 / (4.0 * PI * s.radius * s.radius * jac)
                    }
                }
            }
        };
        (pdf_pos, pdf_dir)
    }

    /// Convert an area-measure sample at `q` (normal `n`) seen from `p` into a light sample.
    #[inline]
    fn sample_at_point(
        &self,
        p: Vec3A,
        (q, q_err, n, pdf_area, li): (Vec3A, Vec3A, Vec3A, f32, Vec3),
    ) -> Option<LightSample> {
        let d = q - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 || !pdf_area.is_finite() {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let cos_l = -wi.dot(n);
        if cos_l == 0.0 || (!self.two_sided && cos_l < 0.0) {
            return None;
        }
        Some(LightSample { p: q, p_err: q_err, n, wi, dist, li, pdf: pdf_area * dist2 / cos_l.abs(), delta: false })
    }

    /// A light sample seen from `p` for next-event estimation (solid-angle pdf).
    #[inline(always)]
    pub fn sample(&self, prims: &Primitives, p: Vec3A, u: Vec2) -> Option<LightSample> {
        if let AreaShape::Sphere { index } = &self.shape {
            let s = &prims.spheres[*index as usize];
            let to_c = s.center - p;
            let dc2 = to_c.length_squared();
            let r2 = s.radius * s.radius;
            if s.transform.is_none() && dc2 > r2 * 1.0001 {
                // Uniform in the subtended cone; find the point on the sphere the direction hits.
                let dc = dc2.sqrt();
                let wc = to_c / dc;
                let sin2_max = r2 / dc2;
                let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
                let one_minus_cos_max = sin2_max / (1.0 + cos_max);
                let cos_t = 1.0 - u.x * one_minus_cos_max;
                let sin2_t = (1.0 - cos_t * cos_t).max(0.0);
                let ds = dc * cos_t - (r2 - dc2 * sin2_t).max(0.0).sqrt();
                let cos_a = ((dc2 + r2 - ds * ds) / (2.0 * dc * s.radius)).clamp(-1.0, 1.0);
                let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
                let phi = 2.0 * PI * u.y;
                let f = Frame::from_normal(-wc);
                let n = f.to_world(Vec3A::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a));
                let q = s.center + n * s.radius;
                let li = match &self.texture {
                    None => self.radiance,
                    Some(_) => self.radiance_at(sphere_uv(n, s.radius).0),
                };
                let d = q - p;
                let dist = d.length();
                let wi = d / dist;
                if !self.two_sided && -wi.dot(n) <= 0.0 {
                    return None;
                }
                return Some(LightSample {
                    p: q,
                    p_err: sphere_point_error(s.center, n * s.radius, None),
                    n,
                    wi,
                    dist,
                    li,
                    pdf: 1.0 / (2.0 * PI * one_minus_cos_max),
                    delta: false,
                });
            }
        }
        // Triangle sets, ellipsoids, and points inside (or on) a sphere: uniform by area.
        self.sample_at_point(p, self.sample_point(prims, u))
    }

    /// Solid-angle density, seen from `p`, with which [`AreaLight::sample`] draws the point `hit` of this light
    /// (0 when the light's surface is seen edge-on there).
    pub fn pdf(&self, prims: &Primitives, p: Vec3A, hit: &SurfaceHit) -> f32 {
        let d = hit.p - p;
        let dist2 = d.length_squared();
        let cos_l = (d.dot(hit.ng) / dist2.sqrt()).abs();
        if cos_l == 0.0 {
            return 0.0;
        }
        match &self.shape {
            AreaShape::Triangles { area, .. } => dist2 / (cos_l * area),
            AreaShape::Curved { sampler, .. } => {
                let jac = hit.dpdu.cross(hit.dpdv).length();
                if jac > 0.0 { dist2 / cos_l * sampler.pdf(hit.uv) / jac } else { 0.0 }
            }
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                match &s.transform {
                    None => {
                        let dc2 = (s.center - p).length_squared();
                        let r2 = s.radius * s.radius;
                        if dc2 <= r2 * 1.0001 {
                            dist2 / (cos_l * 4.0 * PI * r2)
                        } else {
                            let sin2_max = r2 / dc2;
                            let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
                            1.0 / (2.0 * PI * sin2_max / (1.0 + cos_max))
                        }
                    }
                    Some(x) => {
                        let po = x.object_from_world.transform_point3a(hit.p);
                        let no = (po - s.center).normalize();
                        let jac = x.world_from_object.matrix3.determinant().abs() * (x.normal_to_world * no).length();
                        dist2 / (cos_l * 4.0 * PI * s.radius * s.radius * jac)
                    }
                }
            }
        }
    }
}
