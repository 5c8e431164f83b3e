//! Light sources resolved to world space (Prepare stage). Every light owns its emission (pbrt-v4's interface):
//! - `sample_li`/`pdf_li`: next-event estimation — the radiance arriving at a reference point from a sampled point
//!   of the light, with its solid-angle pdf (a delta for point, spot and directional lights);
//! - `sample_le`/`pdf_le`: emitted rays for photon and light tracing, with separate position (area) and direction
//!   (solid angle) pdfs; [`LeSample::flux`] is the power one sample carries;
//! - `power`: total emitted power (RGB, W), what light selection weighs.
//!
//! Light types: area lights (emissive triangle sets, spheres and curved surfaces, `area.rs`), point (`point.rs`), spot (`spot.rs`),
//! directional (`directional.rs`) and the environment (`environment.rs`, sampled through `EnvSampling`: quad-tree,
//! piecewise-constant, uniform or cosine). Distant lights (directional, environment) emit from a disk covering the
//! scene's bounding sphere ([`SceneSphere`]). [`LightSampler`] chooses one light in proportion to its power and
//! samples it, for any integrator.
//!
//! Area lights come first in `LightSet::lights`, in the order of their slot in `SurfaceHit::light`, so a surface
//! hit names its light directly; the environment, if any, is slot `lights.len()`.

mod area;
mod clear_shadows;
mod directional;
mod env_sampling;
mod environment;
mod light;
mod light_sampler;
mod piecewise;
mod point;
mod power_sampler;
mod quadtree;
mod spot;

pub use area::{AreaLight, AreaShape};
pub use clear_shadows::ClearShadows;
pub use directional::DirectionalLight;
pub use env_sampling::{EnvSampling, EnvStrategy};
pub use environment::EnvironmentLight;
pub use light::Light;
pub use light_sampler::LightSampler;
pub use piecewise::Piecewise2D;
pub use point::PointLight;
pub use power_sampler::PowerLightSampler;
pub use quadtree::{DELTA, EPSILON, EnvSample, QuadTree};
pub use spot::{SpotLight, SpotProfile};

use crate::error::{PrismError, Result};
use crate::geometry::{Bounds, Ray};
use crate::primitives::{EntityPrims, Primitives, SurfaceHit};
use glam::{Vec2, Vec3, Vec3A};

/// A light sample as seen from a reference point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Point on the light (for delta lights: the light position, or far away along `wi`).
    pub p: Vec3A,
    /// Floating-point error bound of `p` (zero for delta lights).
    pub p_err: Vec3A,
    /// Surface normal at `p` (zero for point and directional lights).
    pub n: Vec3A,
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3A,
    /// Distance to `p` (infinite for directional lights).
    pub dist: f32,
    /// Incident radiance (area lights) or irradiance-at-normal-incidence (delta lights) along `wi`.
    pub li: Vec3,
    /// Solid-angle pdf; 1 for delta lights.
    pub pdf: f32,
    /// True for point, spot and directional lights: no multiple importance sampling with BSDF sampling.
    pub delta: bool,
}

impl LightSample {
    /// The shadow ray from the surface point `from` to this sample (both ends offset off their surfaces; towards
    /// `wi` without an end for a light at infinity).
    #[inline(always)]
    pub fn shadow_ray(&self, from: &SurfaceHit) -> Ray {
        if self.dist.is_finite() { from.spawn_to(self.p, self.p_err, self.n) } else { from.spawn(self.wi) }
    }

    /// A delta light's sample: light at `p`, direction `wi`, irradiance at normal incidence `li`.
    #[inline]
    pub fn delta(p: Vec3A, wi: Vec3A, dist: f32, li: Vec3) -> Self {
        LightSample { p, p_err: Vec3A::ZERO, n: Vec3A::ZERO, wi, dist, li, pdf: 1.0, delta: true }
    }
}

/// An emitted ray with its pdfs (for photon and light tracing).
#[derive(Clone, Copy, Debug)]
pub struct LeSample {
    /// The ray leaving the light (unit direction; origin offset off the emitting surface).
    pub ray: Ray,
    /// What the ray carries: radiance (area and environment lights), intensity (point and spot lights) or
    /// irradiance (directional lights).
    pub le: Vec3,
    /// Unit normal of the emitting surface or disk at the origin (zero for point and spot lights).
    pub n: Vec3A,
    /// Density of the origin in area measure (1 for point and spot lights).
    pub pdf_pos: f32,
    /// Density of the direction in solid angle (1 for directional lights).
    pub pdf_dir: f32,
}

impl LeSample {
    /// The power this sample carries, `le |cos| / (pdf_pos pdf_dir)`: the mean over samples is the light's power.
    #[inline]
    pub fn flux(&self) -> Vec3 {
        let cos = if self.n == Vec3A::ZERO { 1.0 } else { self.n.dot(self.ray.dir).abs() };
        self.le * (cos / (self.pdf_pos * self.pdf_dir))
    }
}

/// The sphere bounding the scene's bounded primitives: distant lights emit from a disk of its radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneSphere {
    /// Centre, world space.
    pub center: Vec3A,
    /// Radius, world units (positive).
    pub radius: f32,
}

impl Default for SceneSphere {
    fn default() -> Self {
        SceneSphere { center: Vec3A::ZERO, radius: 1.0 }
    }
}

impl SceneSphere {
    /// The bounding sphere of `bounds` (a unit sphere at the origin for an empty scene).
    pub fn from_bounds(bounds: &Bounds) -> Self {
        if bounds.is_empty() || !bounds.diagonal().is_finite() {
            return SceneSphere::default();
        }
        let center = 0.5 * (bounds.min + bounds.max);
        let radius = (0.5 * bounds.diagonal().length()).max(1e-4 * center.abs().max_element()).max(1e-6);
        SceneSphere { center, radius: radius * (1.0 + 1e-4) }
    }

    /// Area pdf of a uniform point on a disk of the sphere's radius.
    #[inline]
    pub fn disk_pdf(&self) -> f32 {
        1.0 / (std::f32::consts::PI * self.radius * self.radius)
    }
}

/// A light other than the environment.
#[derive(Clone, Debug)]
pub enum LightSource {
    /// An emissive surface.
    Area(AreaLight),
    /// A point light.
    Point(PointLight),
    /// A spot light.
    Spot(SpotLight),
    /// A distant light.
    Directional(DirectionalLight),
}

/// The scene's lights: `lights` (area lights first, in slot order), the environment (slot `lights.len()`), and the
/// sphere distant lights emit from.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    /// Every light but the environment, area lights first; the index is the light's slot.
    pub lights: Vec<LightSource>,
    /// The environment light (at most one), slot `lights.len()`.
    pub environment: Option<EnvironmentLight>,
    /// The sphere bounding the scene's bounded primitives.
    pub sphere: SceneSphere,
}

/// A light placed in the world, as [`LightSet::build`] takes it: the scene's description, its composed transform,
/// and for an area light the primitives of its shape.
#[derive(Clone, Copy, Debug)]
pub struct PlacedLight<'a> {
    /// The light as the scene describes it.
    pub light: &'a Light,
    /// The composed transform from the light's frame to world space (area lights are already in world space).
    pub world_from_local: glam::Affine3A,
    /// The primitives an area light emits from (`None` for other lights).
    pub emitter: Option<EntityPrims>,
}

impl LightSet {
    /// Resolve the scene's lights to world space: first the area lights, in the order of their slots (`lights`
    /// entries with an `emitter`), then the others in the order given. `label(i)` names the owner of `lights[i]`
    /// in errors.
    pub fn build(lights_in: &[PlacedLight<'_>], prims: &Primitives, label: impl Fn(usize) -> String) -> Result<Self> {
        let mut lights = Vec::new();
        // The index of each light's owner (and of the environment's), for errors.
        let mut owners = Vec::new();
        let mut env_owner = None;
        for (index, placed) in lights_in.iter().enumerate() {
            if let (Some(ep), Light::Area { radiance, two_sided, texture }) = (&placed.emitter, placed.light) {
                lights.push(LightSource::Area(AreaLight::new(prims, ep, *radiance, *two_sided, texture.clone())));
                owners.push(index);
            }
        }
        let mut environment = None;
        for (index, placed) in lights_in.iter().enumerate() {
            let (light, m) = (placed.light, placed.world_from_local);
            if matches!(light, Light::Area { .. }) {
                continue;
            }
            let name = || label(index);
            if !matches!(light, Light::Environment { .. }) {
                owners.push(index);
            }
            match light {
                Light::Point { intensity, position, attenuation } => lights.push(LightSource::Point(PointLight {
                    position: m.transform_point3a((*position).into()),
                    intensity: *intensity,
                    attenuation: *attenuation,
                })),
                Light::Spot { intensity, position, direction, cone_angle, falloff, profile } => {
                    let axis = m
                        .transform_vector3a((*direction).into())
                        .try_normalize()
                        .ok_or_else(|| PrismError::scene(name(), "spot light has a zero direction"))?;
                    lights.push(LightSource::Spot(SpotLight::new(
                        m.transform_point3a((*position).into()),
                        axis,
                        *intensity,
                        *cone_angle,
                        *falloff,
                        *profile,
                    )))
                }
                Light::Environment { radiance, map } => {
                    if environment.is_some() {
                        return Err(PrismError::scene(name(), "a scene can have only one environment light"));
                    }
                    environment = Some(EnvironmentLight::new(*radiance, map.clone(), &m));
                    env_owner = Some(index);
                }
                Light::Directional { irradiance, direction } => {
                    let d = m.transform_vector3a((*direction).into());
                    let to_light = (-d)
                        .try_normalize()
                        .ok_or_else(|| PrismError::scene(name(), "directional light has a zero direction"))?;
                    lights.push(LightSource::Directional(DirectionalLight { to_light, irradiance: *irradiance }))
                }
                Light::Area { .. } => {}
            }
        }
        let set = LightSet { lights, environment, sphere: SceneSphere::from_bounds(&prims.bounds) };
        // Light choice by power and photon flux need finite powers: radiance 3e38 on a unit quad, or an environment
        // scale of 3e38, overflows single precision.
        for (i, owner) in owners.iter().copied().chain(env_owner).enumerate() {
            let i = if i < set.lights.len() { i } else { set.lights.len() };
            let p = set.power(i, prims);
            if !p.is_finite() {
                return Err(PrismError::scene(
                    label(owner),
                    format!("the light's power overflows ({p}): its radiance, intensity or scale is too large"),
                ));
            }
        }
        Ok(set)
    }

    /// Number of lights other than the environment.
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    /// True when there is no light other than the environment.
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// True for point, spot and directional lights (sampled once, no stratification needed).
    pub fn is_delta(&self, i: usize) -> bool {
        !matches!(self.lights[i], LightSource::Area(_))
    }

    /// Sample light `i` from reference point `p`. `None` when the sample carries no light (back of a one-sided
    /// emitter, `p` on the light's plane, outside a spot's cone).
    #[inline(always)]
    pub fn sample_li(&self, i: usize, prims: &Primitives, p: Vec3A, u: Vec2) -> Option<LightSample> {
        match &self.lights[i] {
            LightSource::Area(a) => a.sample(prims, p, u),
            LightSource::Point(l) => l.sample_li(p),
            LightSource::Spot(l) => l.sample_li(p),
            LightSource::Directional(l) => Some(l.sample_li(p)),
        }
    }

    /// Solid-angle pdf with which `sample_li` would have produced the direction from `p` to the light point `s`
    /// (a surface hit on area light `i`); 0 for delta lights.
    #[inline]
    pub fn pdf_li(&self, i: usize, prims: &Primitives, p: Vec3A, s: &SurfaceHit) -> f32 {
        match &self.lights[i] {
            LightSource::Area(a) => a.pdf(prims, p, s),
            _ => 0.0,
        }
    }

    /// Total emitted power of light `i` (slot `len()` is the environment).
    pub fn power(&self, i: usize, prims: &Primitives) -> Vec3 {
        match self.lights.get(i) {
            Some(LightSource::Area(a)) => a.power(prims),
            Some(LightSource::Point(l)) => l.power(),
            Some(LightSource::Spot(l)) => l.power(),
            Some(LightSource::Directional(l)) => l.power(&self.sphere),
            None => self.environment.as_ref().map_or(Vec3::ZERO, |e| e.power(&self.sphere)),
        }
    }

    /// An emitted ray of light `i` (not the environment: see [`LightSampler::sample_le`]).
    #[inline]
    pub fn sample_le(&self, i: usize, prims: &Primitives, u_pos: Vec2, u_dir: Vec2) -> Option<LeSample> {
        match &self.lights[i] {
            LightSource::Area(a) => a.sample_le(prims, u_pos, u_dir),
            LightSource::Point(l) => Some(l.sample_le(u_dir)),
            LightSource::Spot(l) => l.sample_le(u_dir),
            LightSource::Directional(l) => Some(l.sample_le(&self.sphere, u_pos)),
        }
    }

    /// Position and direction pdfs of an emitted ray of light `i` starting at `p` (unit normal `n` there, for
    /// area lights) in unit direction `dir`.
    pub fn pdf_le(&self, i: usize, prims: &Primitives, p: Vec3A, n: Vec3A, dir: Vec3A) -> (f32, f32) {
        match &self.lights[i] {
            LightSource::Area(a) => a.pdf_le(prims, p, n, dir),
            LightSource::Point(l) => l.pdf_le(),
            LightSource::Spot(l) => l.pdf_le(dir),
            LightSource::Directional(l) => l.pdf_le(&self.sphere),
        }
    }

    /// Radiance leaving area light `slot` at the surface point `s` towards `wo`.
    #[inline]
    pub fn area_radiance(&self, slot: u32, s: &SurfaceHit, wo: Vec3A) -> Vec3 {
        match &self.lights[slot as usize] {
            LightSource::Area(a) if a.two_sided || s.ng.dot(wo) > 0.0 => a.radiance_at(s.uv),
            _ => Vec3::ZERO,
        }
    }
}
