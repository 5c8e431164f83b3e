//! Area lights: an emissive triangle set (quad, mesh, triangle), sphere, or curved surface (revolution, Bézier
//! patch; sampled by area through `shapes::area_sampling` with the exact pdf).

use super::LightSample;
use crate::math::Frame;
use crate::primitives::{EntityPrims, Primitives, SurfaceHit, interpolation_error, sphere_point_error};
use crate::sampling::warp;
use crate::shapes::area_sampling::ParamAreaSampler;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub enum AreaShape {
    /// Triangles `first..first+count` of the primitives; `cdf[k]` = area of the first k+1 triangles / total;
    /// `normals[k]` the unit geometric normal of triangle k.
    Triangles { first: u32, count: u32, cdf: Vec<f32>, normals: Vec<Vec3A>, area: f32 },
    /// Sphere `index` of the primitives.
    Sphere { index: u32 },
    /// A curved analytic primitive `prim` (revolution, patch): a point of its parameter square drawn by
    /// `sampler`, density by area `p(u, v) / |dp/du x dp/dv|`.
    Curved { prim: u32, sampler: ParamAreaSampler },
}

#[derive(Clone, Debug)]
pub struct AreaLight {
    pub radiance: Vec3,
    pub two_sided: bool,
    pub shape: AreaShape,
}

fn tri_area(t: &[Vec3A; 3]) -> f32 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

impl AreaLight {
    pub fn new(prims: &Primitives, ep: &EntityPrims, radiance: Vec3, two_sided: bool) -> Self {
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
                let normals = tris.iter().map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize()).collect();
                AreaShape::Triangles { first: ep.first_tri, count: ep.tri_count, cdf, normals, area }
            }
        };
        AreaLight { radiance, two_sided, shape }
    }

    /// Total surface area (exact for triangle sets and spheres; for ellipsoids the Knud Thomsen approximation,
    /// only used to weigh lights, never in a pdf).
    pub fn area(&self, prims: &Primitives) -> f32 {
        match &self.shape {
            AreaShape::Triangles { area, .. } => *area,
            AreaShape::Curved { sampler, .. } => sampler.area(),
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                match &s.transform {
                    None => 4.0 * PI * s.radius * s.radius,
                    Some(x) => {
                        let m = x.world_from_object.matrix3;
                        let (a, b, c) =
                            (m.x_axis.length() * s.radius, m.y_axis.length() * s.radius, m.z_axis.length() * s.radius);
                        let p = 1.6075f32;
                        4.0 * PI * (((a * b).powf(p) + (b * c).powf(p) + (c * a).powf(p)) / 3.0).powf(1.0 / p)
                    }
                }
            }
        }
    }

    /// Convert an area-measure sample at `q` (normal `n`) seen from `p` into a light sample.
    #[inline]
    fn sample_at_point(&self, p: Vec3A, q: Vec3A, q_err: Vec3A, n: Vec3A, pdf_area: f32) -> Option<LightSample> {
        let d = q - p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let cos_l = -wi.dot(n);
        if cos_l == 0.0 || (!self.two_sided && cos_l < 0.0) {
            return None;
        }
        Some(LightSample {
            p: q,
            p_err: q_err,
            n,
            wi,
            dist,
            li: self.radiance,
            pdf: pdf_area * dist2 / cos_l.abs(),
            delta: false,
        })
    }

    pub fn sample(&self, prims: &Primitives, p: Vec3A, u: Vec2) -> Option<LightSample> {
        match &self.shape {
            AreaShape::Curved { prim, sampler } => {
                let (uv, pdf_uv) = sampler.sample(u);
                let q = prims.analytic_point_at(*prim, uv)?;
                let jac = q.dpdu.cross(q.dpdv).length();
                if jac.is_nan() || jac <= 0.0 {
                    return None;
                }
                self.sample_at_point(p, q.p, q.p_err, q.n, pdf_uv / jac)
            }
            AreaShape::Triangles { first, count, cdf, normals, area } => {
                // Pick a triangle by area, then reuse the remainder of u.x for the point inside it.
                let k = cdf.partition_point(|&c| c <= u.x).min(*count as usize - 1);
                let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
                let ux = ((u.x - lo) / (cdf[k] - lo)).clamp(0.0, 1.0 - f32::EPSILON);
                let t = &prims.tris[*first as usize + k];
                let (b0, b1, b2) = warp::uniform_triangle(Vec2::new(ux, u.y));
                let q = b0 * t[0] + b1 * t[1] + b2 * t[2];
                self.sample_at_point(p, q, interpolation_error([b0, b1, b2], t), normals[k], 1.0 / area)
            }
            AreaShape::Sphere { index } => {
                let s = &prims.spheres[*index as usize];
                match &s.transform {
                    None => {
                        let to_c = s.center - p;
                        let dc2 = to_c.length_squared();
                        let r2 = s.radius * s.radius;
                        if dc2 <= r2 * 1.0001 {
                            // Inside (or on) the sphere: uniform by area.
                            let n = warp::uniform_sphere(u);
                            let err = sphere_point_error(s.center, n * s.radius, None);
                            return self.sample_at_point(p, s.center + n * s.radius, err, n, 1.0 / (4.0 * PI * r2));
                        }
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
                        let d = q - p;
                        let dist = d.length();
                        let wi = d / dist;
                        if !self.two_sided && -wi.dot(n) <= 0.0 {
                            return None;
                        }
                        Some(LightSample {
                            p: q,
                            p_err: sphere_point_error(s.center, n * s.radius, None),
                            n,
                            wi,
                            dist,
                            li: self.radiance,
                            pdf: 1.0 / (2.0 * PI * one_minus_cos_max),
                            delta: false,
                        })
                    }
                    Some(x) => {
                        let no = warp::uniform_sphere(u);
                        let q = x.world_from_object.transform_point3a(s.center + no * s.radius);
                        let nw = x.normal_to_world * no;
                        // dA_world = |det M| |M^-T n| dA_object
                        let jac = x.world_from_object.matrix3.determinant().abs() * nw.length();
                        let err = sphere_point_error(s.center, no * s.radius, Some(x));
                        self.sample_at_point(p, q, err, nw.normalize(), 1.0 / (4.0 * PI * s.radius * s.radius * jac))
                    }
                }
            }
        }
    }

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
