//! # phong
//!
//! Whitted-style direct lighting with Phong materials, in physically based units. The default integrator of a RON
//! scene, and the one 6.837 course scenes render with. The name is the shading model's (Phong's illumination
//! model, as the 6.837 course uses it); the `Phong` *material* is a different thing, an energy-normalised glossy
//! lobe that every integrator shades.
//!
//! ```text
//! --integrator "phong(max_depth: 5, light_samples: 4, shadows: true, min_weight: 0, shade_back: None)"
//! ```
//!
//! ## What it computes
//!
//! At each hit:
//!
//! - emitted radiance (emitters seen directly or in mirrors);
//! - the ambient term: the material's `ambient` coefficient times the scene's ambient radiance (0 for physically
//!   based scenes);
//! - direct lighting from every light with shadow rays: point lights (`I cos / r^2`), spot lights, directional lights
//!   (`E cos`) and area lights with `light_samples` stratified samples per shading point, each weighted by its pdf, so
//!   irradiance and soft shadows are physically right;
//! - mirrors (`reflective`) and smooth dielectrics (`transparent`: Fresnel-weighted reflection and refraction, total
//!   internal reflection), recursively up to `max_depth` bounces.
//!
//! Rays that leave the scene return the environment light's radiance, or the background. The environment is not
//! sampled for direct lighting (`envlight` does that). With `ambient` 0 and Lambert materials this is exactly the
//! direct-lighting estimator: `scenes/cornell_direct.ron` matches Mitsuba 3's direct-lighting reference
//! (`../shared/refs/direct_only.exr`): image mean within 2% in the tests, and RMSE 0.065 / 0.031 / 0.011 / 0.0048 at
//! 4 / 16 / 64 / 256 spp (`prism render scenes/cornell_direct.ron --spp N -o d.exr && prism compare d.exr
//! ../shared/refs/direct_only.exr`).
//!
//! Materials with the 6.837 course's shading (`Mit6837`, written by `prism convert`) follow the course instead:
//! Blinn-Phong specular without normalisation, and mirror reflection and refraction without Fresnel.
//!
//! ## Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `max_depth` | 5 | mirror and refraction bounces followed (at most 64); the 6.837 option `-bounces` |
//! | `light_samples` | 4 | stratified samples per area light and shading point (1 to 4096) |
//! | `shadows` | `true` | trace shadow rays; `false` lights every point as if unoccluded (the 6.837 default, option `-shadows`) |
//! | `min_weight` | 0 | a mirror or refraction branch is not followed once the product of the reflective or transparent colours along the path (largest channel) is below it (option `-weight`); non-negative |
//! | `shade_back` | `None` | `Some(true)` or `Some(false)` shades back faces or not for every material, overriding `two_sided` (option `-shade_back`) |
//!
//! ## What it is for
//!
//! Previews, direct-lighting references, scenes with few mirrors and glass, and the MIT 6.837 course scenes and
//! command lines (`prism raytracer`). It is not a global-illumination method: diffuse interreflection is absent.
//!
//! ## Failure modes
//!
//! - Mirror and glass branching grows as `2^max_depth` rays per sample. Ctrl-C is checked at every bounce, so such a
//!   render still stops at once; `min_weight` prunes dim branches.
//! - Caustics and indirect light are missing by construction; use `envlight` or `ppm`.
//! - Environment light reaches surfaces only through mirrors and glass, never as direct light.
//! - Bad parameters (`light_samples` outside 1 to 4096, `max_depth` above 64, a negative or non-finite `min_weight`, unknown fields)
//!   are one-line errors naming the parameter.

use glam::Vec3;
use prism_core::bsdf::Bsdf;
use prism_core::error::{PrismError, Result};
use prism_core::geometry::Ray;
use prism_core::integrator::{PerPixel, PixelIntegrator};
use prism_core::primitives::SurfaceHit;
use prism_core::sampling::{Rng, Sampler, stratified_2d};
use prism_core::scene::Scene;
use prism_engine::{App, Plugin};
use serde::Deserialize;

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct PhongParams {
    /// Mirror/refraction bounces followed (0 = direct lighting only).
    pub max_depth: u32,
    /// Samples per area light per shading point (stratified).
    pub light_samples: u32,
    /// Trace shadow rays (false: every light is seen, as 6.837 without `-shadows`).
    pub shadows: bool,
    /// Stop following mirror/refraction branches whose accumulated weight falls below this (6.837 `-weight`).
    pub min_weight: f32,
    /// Shade back faces (`Some(true)`) or paint them black (`Some(false)`) for every material (6.837
    /// `-shade_back`); `None` follows each material's `two_sided`.
    pub shade_back: Option<bool>,
}

impl Default for PhongParams {
    fn default() -> Self {
        PhongParams { max_depth: 5, light_samples: 4, shadows: true, min_weight: 0.0, shade_back: None }
    }
}

/// Most samples per area light and shading point (`light_samples`): 64 x 64 strata.
pub const MAX_LIGHT_SAMPLES: u32 = 4096;

/// Registers `phong`.
pub struct PhongPlugin;

impl Plugin for PhongPlugin {
    fn name(&self) -> &str {
        "phong"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "phong",
            Box::new(|cfg| {
                let p: PhongParams = cfg.parse_params()?;
                Ok(Box::new(PerPixel::new(Phong::new(p)?)))
            }),
        );
    }
}

pub struct Phong {
    params: PhongParams,
}

impl Phong {
    pub fn new(params: PhongParams) -> Result<Self> {
        if params.light_samples == 0 || params.light_samples > MAX_LIGHT_SAMPLES {
            return Err(PrismError::invalid(format!(
                "phong: light_samples must be between 1 and {MAX_LIGHT_SAMPLES}, got {}",
                params.light_samples
            )));
        }
        if params.max_depth > 64 {
            return Err(PrismError::invalid("phong: max_depth must be at most 64"));
        }
        if !(params.min_weight.is_finite() && params.min_weight >= 0.0) {
            return Err(PrismError::invalid("phong: min_weight must be a non-negative number"));
        }
        Ok(Phong { params })
    }

    fn trace(&self, scene: &Scene, ray: &Ray, rng: &mut Rng, depth: u32, weight: f32) -> Vec3 {
        // Mirror and glass branches multiply (2^max_depth rays per sample): a cancelled render stops at once
        // (the sample is discarded).
        if scene.cancelled() {
            return Vec3::ZERO;
        }
        let Some(s) = scene.trace(ray) else {
            return scene.escaped(ray.dir);
        };
        let wo = -ray.dir;
        let mut l = scene.emitted(&s, wo);
        // The material resolved at the hit; `shade_back` overrides every material's sidedness.
        let Some(bsdf) = scene.bsdf_sided(&s, wo, self.params.shade_back) else {
            return l;
        };
        // Branch weights below `min_weight` are not followed (6.837 `-weight`).
        let follow = |filter: Vec3| weight * filter.max_element() >= self.params.min_weight;
        l += bsdf.ambient() * scene.globals.ambient;
        if bsdf.has_smooth() {
            l += self.direct(scene, &s, &bsdf, rng);
        }
        if depth < self.params.max_depth && bsdf.has_delta() {
            // Mirror, Fresnel reflection and refraction (1/eta^2 included), the course's refraction: each branch
            // followed deterministically.
            bsdf.delta_branches(|b| {
                if follow(b.filter) {
                    let w = weight * b.filter.max_element();
                    l += b.weight * self.trace(scene, &s.spawn(b.wi), rng, depth + 1, w);
                }
            });
        }
        l
    }

    /// Direct lighting from every light, `light_samples` stratified samples for each area light.
    fn direct(&self, scene: &Scene, s: &SurfaceHit, bsdf: &Bsdf, rng: &mut Rng) -> Vec3 {
        let mut sum = Vec3::ZERO;
        let ns = bsdf.normal();
        for i in 0..scene.lights.len() {
            // Many lights, or many samples of each, make one shading point long: a cancelled render stops here too.
            if scene.cancelled() {
                return sum;
            }
            let n = if scene.lights.is_delta(i) { 1 } else { self.params.light_samples };
            let key = rng.next_u32();
            let mut acc = Vec3::ZERO;
            for k in 0..n {
                if k % 256 == 255 && scene.cancelled() {
                    return sum;
                }
                let u = stratified_2d(k, n, key, rng);
                let Some(ls) = scene.lights.sample_li(i, &scene.prims, s.p, u) else {
                    continue;
                };
                // The BSDF decides which side it scatters to (reflection above the surface, transmission below).
                let f = bsdf.eval(ls.wi);
                if f == Vec3::ZERO {
                    continue;
                }
                if self.params.shadows && scene.occluded(&ls.shadow_ray(s)) {
                    continue;
                }
                acc += f * ls.li * (ls.wi.dot(ns).abs() / ls.pdf);
            }
            sum += acc / n as f32;
        }
        sum
    }
}

impl PixelIntegrator for Phong {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        self.trace(scene, &ray, sampler.rng(), 0, 1.0)
    }
}
