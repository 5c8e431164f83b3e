//! The BSDF of a [`Material`] at a surface point, for path tracing: evaluation and pdf of the smooth lobes
//! (Lambert + normalised Phong, the same `Material::eval_smooth`), and sampling of every lobe — cosine-weighted
//! diffuse, the Phong lobe around the mirror direction, the ideal mirror and the smooth Fresnel dielectric.
//!
//! A lobe is chosen with probability proportional to its albedo (luminance of kd, ks, reflective, transparent).
//! The smooth lobes form one mixture whose pdf (`pdf`) is what multiple importance sampling compares with light
//! sampling; delta lobes (mirror, dielectric) have no pdf and are flagged `delta`. Refraction scales radiance by
//! 1/eta^2 (it cancels for closed objects). Two-sided materials flip the shading frame towards `wo`; one-sided
//! materials are black from behind.

use crate::material::Material;
use crate::math::{Frame, fresnel_dielectric, luminance, reflect, refract};
use crate::primitives::SurfaceHit;
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};

/// A sampled direction and its throughput weight `f |cos| / pdf`.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    pub wi: Vec3A,
    pub weight: Vec3,
    /// Mixture pdf of the smooth lobes in solid angle (0 for delta samples).
    pub pdf: f32,
    pub delta: bool,
}

#[derive(Clone, Copy, Debug)]
pub struct Bsdf<'a> {
    m: &'a Material,
    /// Shading frame, normal facing `wo`.
    frame: Frame,
    /// Geometric normal facing `wo`.
    ng: Vec3A,
    wo: Vec3A,
    /// Relative index eta_t / eta_i for a ray leaving through the surface (entering when `wo` is on the side of
    /// the primitive's normal).
    eta: f32,
    /// Cumulative lobe probabilities: diffuse, + specular, + mirror, + dielectric (= 1).
    cdf: [f32; 4],
}

impl<'a> Bsdf<'a> {
    /// The BSDF seen from direction `wo` (unit, pointing away from the surface). `None` when it reflects nothing
    /// towards `wo` (black material, or the back of a one-sided one).
    pub fn new(m: &'a Material, s: &SurfaceHit, wo: Vec3A) -> Option<Self> {
        let front = wo.dot(s.ng) >= 0.0;
        let (ng, mut ns) = if front { (s.ng, s.ns) } else { (-s.ng, -s.ns) };
        if ns.dot(wo) <= 0.0 {
            ns = ng;
        }
        let eta = if front { m.ior } else { 1.0 / m.ior };
        let shades = front || m.two_sided;
        let w = [
            if shades { luminance(m.diffuse) } else { 0.0 },
            if shades { luminance(m.specular) } else { 0.0 },
            if shades { luminance(m.reflective) } else { 0.0 },
            luminance(m.transparent),
        ];
        let total: f32 = w.iter().sum();
        if total <= 0.0 {
            return None;
        }
        let cdf = [w[0] / total, (w[0] + w[1]) / total, (w[0] + w[1] + w[2]) / total, 1.0];
        Some(Bsdf { m, frame: Frame::from_normal(ns), ng, wo, eta, cdf })
    }

    /// Shading normal facing `wo`.
    #[inline]
    pub fn normal(&self) -> Vec3A {
        self.frame.n
    }

    /// Geometric normal facing `wo`.
    #[inline]
    pub fn geometric_normal(&self) -> Vec3A {
        self.ng
    }

    /// True when the material has a smooth (non-delta) lobe that light sampling can illuminate.
    #[inline]
    pub fn has_smooth(&self) -> bool {
        self.cdf[1] > 0.0
    }

    /// Probability that `sample` picks a smooth (non-delta) lobe; 1 for purely smooth materials, 0 for purely
    /// specular ones (mirror, glass).
    #[inline]
    pub fn smooth_probability(&self) -> f32 {
        self.cdf[1]
    }

    /// `sample` for light (importance) transport, as photons and light paths scatter (Veach 1997, ch. 5): the
    /// radiance scaling 1/eta^2 of refraction does not apply, and the shading-normal correction
    /// `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)` makes the adjoint BSDF of a shaded surface. `wo` is the direction the
    /// particle came from.
    pub fn sample_importance(&self, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let mut bs = self.sample(u_lobe, u)?;
        if bs.delta && bs.wi.dot(self.ng) < 0.0 {
            bs.weight *= self.eta * self.eta;
        }
        let (ns, ng) = (self.frame.n, self.ng);
        let denom = self.wo.dot(ng).abs() * bs.wi.dot(ns).abs();
        if denom > 0.0 {
            bs.weight *= (self.wo.dot(ns).abs() * bs.wi.dot(ng).abs()) / denom;
        }
        Some(bs)
    }

    /// The smooth part of the BSDF, `f(wo, wi)`; zero for `wi` below the surface (shading or geometric).
    #[inline]
    pub fn eval(&self, wi: Vec3A) -> Vec3 {
        if wi.dot(self.ng) <= 0.0 {
            return Vec3::ZERO;
        }
        self.m.eval_smooth(self.wo, wi, self.frame.n)
    }

    /// Mixture pdf (solid angle) with which `sample` produces `wi` through a smooth lobe.
    #[inline]
    pub fn pdf(&self, wi: Vec3A) -> f32 {
        if wi.dot(self.ng) <= 0.0 {
            return 0.0;
        }
        let (pd, ps) = (self.cdf[0], self.cdf[1] - self.cdf[0]);
        let mut pdf = 0.0;
        if pd > 0.0 {
            pdf += pd * warp::cosine_hemisphere_pdf(self.frame.to_local(wi));
        }
        if ps > 0.0 {
            let r = Frame::from_normal(reflect(self.wo, self.frame.n));
            pdf += ps * warp::phong_lobe_pdf(r.to_local(wi), self.m.exponent);
        }
        pdf
    }

    /// Sample a direction: `u_lobe` picks the lobe, `u` the direction within it.
    pub fn sample(&self, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if u_lobe < self.cdf[1] {
            let wi = if u_lobe < self.cdf[0] {
                self.frame.to_world(warp::cosine_hemisphere(u))
            } else {
                Frame::from_normal(reflect(self.wo, self.frame.n)).to_world(warp::phong_lobe(u, self.m.exponent))
            };
            let pdf = self.pdf(wi);
            let cos = wi.dot(self.frame.n);
            if pdf <= 0.0 || cos <= 0.0 {
                return None;
            }
            let f = self.eval(wi);
            return Some(BsdfSample { wi, weight: f * (cos / pdf), pdf, delta: false });
        }
        let n = self.frame.n;
        if u_lobe < self.cdf[2] {
            let p = self.cdf[2] - self.cdf[1];
            let wi = reflect(self.wo, n);
            return (wi.dot(self.ng) > 0.0).then(|| BsdfSample {
                wi,
                weight: self.m.reflective / p,
                pdf: 0.0,
                delta: true,
            });
        }
        // Dielectric: reflect with probability F, refract otherwise (u.x reused to choose).
        let p = 1.0 - self.cdf[2];
        let f = fresnel_dielectric(self.wo.dot(n), self.eta);
        if u.x < f {
            let wi = reflect(self.wo, n);
            (wi.dot(self.ng) > 0.0).then(|| BsdfSample { wi, weight: self.m.transparent / p, pdf: 0.0, delta: true })
        } else {
            let wi = refract(self.wo, n, self.eta)?.normalize();
            (wi.dot(self.ng) < 0.0).then(|| BsdfSample {
                wi,
                weight: self.m.transparent / (p * self.eta * self.eta),
                pdf: 0.0,
                delta: true,
            })
        }
    }
}
