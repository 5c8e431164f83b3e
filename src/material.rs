//! Materials and their BSDFs, in physically based units: a diffuse coefficient is an albedo (BRDF = kd / pi), the
//! Phong specular lobe is energy-normalised (BRDF = ks (n + 2) / (2 pi) cos^n alpha, Lafortune & Willems 1994),
//! `reflective` is an ideal mirror's reflectance, `transparent` the transmittance filter of a smooth dielectric
//! with index `ior` whose reflection and refraction are split by the exact Fresnel term. Lambert, mirror and glass
//! are special cases of this one struct, so integrators need a single code path.

use crate::math::reflect;
use glam::{Vec3, Vec3A};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Reflectance for the scene's ambient radiance (0 for physically based scenes).
    pub ambient: Vec3,
    /// Lambertian albedo.
    pub diffuse: Vec3,
    /// Phong specular reflectance.
    pub specular: Vec3,
    /// Phong exponent.
    pub exponent: f32,
    /// Ideal mirror reflectance (no Fresnel).
    pub reflective: Vec3,
    /// Smooth dielectric transmittance filter (reflection/refraction weighted by Fresnel).
    pub transparent: Vec3,
    /// Index of refraction of the inside (the side opposite the geometric normal).
    pub ior: f32,
    /// Shade both faces (the shading normal is flipped towards the viewer). One-sided materials are black from behind.
    pub two_sided: bool,
    /// Physically based (default) or the 6.837 course's shading.
    pub shading: Shading,
}

/// How a material's terms are evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// As above: energy-normalised Phong lobe, Fresnel-weighted dielectric.
    #[default]
    Physical,
    /// The 6.837 course's conventions, for its scenes: radiance `kd c cos + ks (n.h)^e c` per light of colour `c`
    /// (Blinn-Phong half vector, no normalisation, no cosine on the specular term), mirror and refraction without
    /// Fresnel (refracted radiance is `transparent` times the radiance behind, nothing under total internal
    /// reflection).
    Mit6837,
}

impl Default for Material {
    /// The material of entities that name none: grey Lambert, albedo 0.5.
    fn default() -> Self {
        Material::lambert("default", Vec3::splat(0.5))
    }
}

impl Material {
    pub fn black(name: &str) -> Self {
        Material {
            name: name.to_string(),
            ambient: Vec3::ZERO,
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
            exponent: 1.0,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            ior: 1.5,
            two_sided: true,
            shading: Shading::Physical,
        }
    }

    pub fn lambert(name: &str, albedo: Vec3) -> Self {
        Material { diffuse: albedo, ..Material::black(name) }
    }

    /// True when the material has a non-delta lobe (something light sampling can illuminate).
    #[inline]
    pub fn has_smooth_lobe(&self) -> bool {
        self.diffuse != Vec3::ZERO || self.specular != Vec3::ZERO
    }

    /// True when the material has a mirror or dielectric lobe.
    #[inline]
    pub fn has_delta_lobe(&self) -> bool {
        self.reflective != Vec3::ZERO || self.transparent != Vec3::ZERO
    }

    /// The non-delta part of the BRDF, `f(wo, wi)`, for unit directions pointing away from the surface and the
    /// shading normal `n` already facing `wo`'s side. Zero when `wi` is below the surface.
    #[inline]
    pub fn eval_smooth(&self, wo: Vec3A, wi: Vec3A, n: Vec3A) -> Vec3 {
        let cos_i = wi.dot(n);
        if cos_i <= 0.0 || wo.dot(n) <= 0.0 {
            return Vec3::ZERO;
        }
        let mut f = self.diffuse * FRAC_1_PI;
        if self.shading == Shading::Mit6837 {
            // The course adds ks (n.h)^e times the light colour; the integrator multiplies f by the irradiance
            // (pi times that colour) and the cosine, so divide both out.
            if self.specular != Vec3::ZERO {
                let cos_h = (wo + wi).normalize_or_zero().dot(n);
                if cos_h > 0.0 {
                    f += self.specular * (cos_h.powf(self.exponent) * FRAC_1_PI / cos_i);
                }
            }
            return f;
        }
        if self.specular != Vec3::ZERO {
            let cos_alpha = reflect(wo, n).dot(wi);
            if cos_alpha > 0.0 {
                let norm = (self.exponent + 2.0) * 0.5 * FRAC_1_PI;
                f += self.specular * (norm * cos_alpha.powf(self.exponent));
            }
        }
        f
    }
}
