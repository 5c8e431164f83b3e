//! `phong`: Whitted-style direct lighting with Phong materials, in physically based units.
//!
//! At each hit: emitted radiance (emitters seen directly or in mirrors), ambient term (`ambient` material
//! coefficient times the scene's ambient radiance; 0 for physically based scenes), and direct lighting from every
//! light with shadow rays: point lights (I cos / r^2), directional lights (E cos) and area lights with
//! `light_samples` stratified samples per shading point, each weighted by its pdf, so irradiance and soft shadows
//! are physically right. Mirrors (`reflective`) and smooth dielectrics (`transparent`, Fresnel-weighted reflection
//! and refraction, total internal reflection) recurse up to `max_depth` bounces. Rays that leave the scene return
//! the environment light's radiance (or the background); the environment is not sampled for direct lighting (the
//! `envlight` integrator does that). With `ambient` 0 and Lambert
//! materials this is exactly the direct-lighting estimator (tested against Mitsuba 3 in `tests/scenes.rs`).
//!
//! Materials with `Shading::Mit6837` (6.837 scenes) follow the course instead: refraction without Fresnel.
//!
//! Parameters: `phong(max_depth: 5, light_samples: 4, shadows: true, min_weight: 0, shade_back: None)`; the last
//! three map the 6.837 options `-shadows` (no shadow rays when false), `-weight` (a mirror or refraction branch
//! is not followed once the product of the reflective/transparent colours along the path, largest channel, is
//! below it) and `-shade_back` (`Some(b)` shades back faces or not for every material, overriding `two_sided`).

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
        if params.light_samples == 0 {
            return Err(PrismError::invalid("phong: light_samples must be at least 1"));
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
            let n = if scene.lights.is_delta(i) { 1 } else { self.params.light_samples };
            let key = rng.next_u32();
            let mut acc = Vec3::ZERO;
            for k in 0..n {
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
