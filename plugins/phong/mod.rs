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

use crate::app::{App, Plugin};
use crate::error::{PrismError, Result};
use crate::geometry::Ray;
use crate::integrator::{PerPixel, PixelIntegrator};
use crate::material::{Material, Shading};
use crate::math::{fresnel_dielectric, reflect, refract};
use crate::primitives::SurfaceHit;
use crate::sampling::{Rng, Sampler, stratified_2d};
use crate::scene::Scene;
use glam::{Vec3, Vec3A};
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
                Ok(Box::new(PerPixel(Phong::new(p)?)))
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
        let Some(s) = scene.trace(ray) else {
            return scene.escaped(ray.dir);
        };
        let wo = -ray.dir;
        let m = scene.material(s.material);
        let mut l = scene.emitted(&s, wo);
        let front = wo.dot(s.ng) >= 0.0;
        // Normals facing the viewer.
        let (ng, ns) = if front { (s.ng, s.ns) } else { (-s.ng, -s.ns) };
        let ns = if ns.dot(wo) > 0.0 { ns } else { ng };
        let shaded = front || self.params.shade_back.unwrap_or(m.two_sided);
        // Branch weights below `min_weight` are not followed (6.837 `-weight`).
        let follow = |filter: Vec3| weight * filter.max_element() >= self.params.min_weight;
        if shaded {
            l += m.ambient * scene.globals.ambient;
            if m.has_smooth_lobe() {
                l += self.direct(scene, &s, m, wo, ng, ns, rng);
            }
        }
        if depth < self.params.max_depth && m.has_delta_lobe() {
            if shaded && m.reflective != Vec3::ZERO && follow(m.reflective) {
                let r = reflect(wo, ns);
                if r.dot(ng) > 0.0 {
                    let w = weight * m.reflective.max_element();
                    l += m.reflective * self.trace(scene, &s.spawn(r), rng, depth + 1, w);
                }
            }
            if m.transparent != Vec3::ZERO && m.shading == Shading::Mit6837 {
                // The course: the refracted radiance times the transparent colour, no Fresnel, nothing under
                // total internal reflection.
                let eta = if front { m.ior } else { 1.0 / m.ior };
                if follow(m.transparent)
                    && let Some(t) = refract(wo, ns, eta)
                {
                    let w = weight * m.transparent.max_element();
                    l += m.transparent * self.trace(scene, &s.spawn(t.normalize()), rng, depth + 1, w);
                }
            } else if m.transparent != Vec3::ZERO && follow(m.transparent) {
                let w = weight * m.transparent.max_element();
                // Entering when the ray comes from the side the geometric normal points to.
                let eta = if front { m.ior } else { 1.0 / m.ior };
                let cos_i = wo.dot(ns).max(0.0);
                let f = fresnel_dielectric(cos_i, eta);
                if f > 0.0 {
                    let r = reflect(wo, ns);
                    l += m.transparent * f * self.trace(scene, &s.spawn(r), rng, depth + 1, w);
                }
                if f < 1.0
                    && let Some(t) = refract(wo, ns, eta)
                {
                    // Radiance is scaled by 1/eta^2 across the interface (it cancels for closed objects).
                    let scale = (1.0 - f) / (eta * eta);
                    l += m.transparent * scale * self.trace(scene, &s.spawn(t.normalize()), rng, depth + 1, w);
                }
            }
        }
        l
    }

    /// Direct lighting from every light, `light_samples` stratified samples for each area light.
    #[allow(clippy::too_many_arguments)]
    fn direct(
        &self,
        scene: &Scene,
        s: &SurfaceHit,
        m: &Material,
        wo: Vec3A,
        ng: Vec3A,
        ns: Vec3A,
        rng: &mut Rng,
    ) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for i in 0..scene.lights.len() {
            let n = if scene.lights.is_delta(i) { 1 } else { self.params.light_samples };
            let key = rng.next_u32();
            let mut acc = Vec3::ZERO;
            for k in 0..n {
                let u = stratified_2d(k, n, key, rng);
                let Some(ls) = scene.lights.sample_li(i, &scene.prims, s.p, u) else {
                    continue;
                };
                let cos = ls.wi.dot(ns);
                if cos <= 0.0 || ls.wi.dot(ng) <= 0.0 {
                    continue;
                }
                let f = m.eval_smooth(wo, ls.wi, ns);
                if f == Vec3::ZERO {
                    continue;
                }
                if self.params.shadows && scene.occluded(&s.spawn_to(&ls)) {
                    continue;
                }
                acc += f * ls.li * (cos / ls.pdf);
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
