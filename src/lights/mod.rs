//! Light sources resolved to world space (Prepare stage), with sampling for next-event estimation.
//!
//! Area lights come first, in the order of their slot in `SurfaceHit::light`, so a surface hit names its light
//! directly. Every `sample` returns the radiance arriving at the reference point and a pdf in solid angle (or a
//! delta for point and directional lights); `pdf` gives the same density for a direction that hit the light, as
//! multiple importance sampling needs. Sampling schemes:
//! - triangle sets: a triangle chosen in proportion to its area, then a uniform point on it;
//! - spheres (world-space): uniform in the cone the sphere subtends (pbrt's scheme), uniform by area from inside;
//! - ellipsoids (spheres under non-uniform scale): uniform on the object-space sphere, with the exact area Jacobian;
//! - curved surfaces (revolutions, Bézier patches): a cell of their parameter square by approximate area, a uniform
//!   point in it, pdf `p(u, v) / |dp/du x dp/dv|` exactly (`shapes/area_sampling.rs`).

mod area;
mod environment;

pub use area::{AreaLight, AreaShape};
pub use environment::EnvironmentLight;

use crate::components::{Light, WorldFromLocal};
use crate::error::{PrismError, Result};
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
    pub delta: bool,
}

#[derive(Clone, Debug)]
pub enum LightSource {
    Area(AreaLight),
    /// Irradiance `intensity cos / (a0 + a1 d + a2 d^2)`, `attenuation = (a0, a1, a2)`.
    Point {
        position: Vec3A,
        intensity: Vec3,
        attenuation: Vec3,
    },
    /// `to_light` is the unit direction towards the light (opposite to the direction it travels).
    Directional {
        to_light: Vec3A,
        irradiance: Vec3,
    },
}

/// The scene's lights: `lights` are sampled by `sample` (area lights first, in slot order); the environment, if
/// any, is kept apart because the integrators that importance-sample it own that sampler.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    pub lights: Vec<LightSource>,
    pub environment: Option<EnvironmentLight>,
}

impl LightSet {
    /// Collect the lights of the world. `emitters` are the entities with area lights, in slot order.
    pub fn build(world: &hecs::World, prims: &Primitives, emitters: &[(hecs::Entity, EntityPrims)]) -> Result<Self> {
        let mut lights = Vec::new();
        for (entity, ep) in emitters {
            let Ok(light) = world.get::<&Light>(*entity) else {
                continue;
            };
            if let Light::Area { radiance, two_sided } = *light {
                lights.push(LightSource::Area(AreaLight::new(prims, ep, radiance, two_sided)));
            }
        }
        let mut environment = None;
        let mut q = world.query::<(hecs::Entity, &Light, Option<&WorldFromLocal>)>();
        let mut others: Vec<_> = q.iter().filter(|(_, l, _)| !matches!(l, Light::Area { .. })).collect();
        others.sort_by_key(|(e, ..)| e.id());
        for (entity, light, wfl) in others {
            let m = wfl.map(|w| w.0).unwrap_or_default();
            match light {
                Light::Point { intensity, position, attenuation } => lights.push(LightSource::Point {
                    position: m.transform_point3a((*position).into()),
                    intensity: *intensity,
                    attenuation: *attenuation,
                }),
                Light::Environment { radiance, map } => {
                    if environment.is_some() {
                        return Err(PrismError::scene(
                            crate::load::entity_label(world, entity),
                            "a scene can have only one environment light",
                        ));
                    }
                    environment = Some(EnvironmentLight::new(*radiance, map.clone(), &m));
                }
                Light::Directional { irradiance, direction } => {
                    let irradiance = *irradiance;
                    let d = m.transform_vector3a((*direction).into());
                    let to_light = (-d).try_normalize().ok_or_else(|| {
                        PrismError::scene(
                            crate::load::entity_label(world, entity),
                            "directional light has a zero direction",
                        )
                    })?;
                    lights.push(LightSource::Directional { to_light, irradiance })
                }
                Light::Area { .. } => {}
            }
        }
        Ok(LightSet { lights, environment })
    }

    pub fn len(&self) -> usize {
        self.lights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// True for point and directional lights (sampled once, no stratification needed).
    pub fn is_delta(&self, i: usize) -> bool {
        !matches!(self.lights[i], LightSource::Area(_))
    }

    /// Sample light `i` from reference point `p`. `None` when the sample carries no light (back of a one-sided
    /// emitter, or `p` on the light's plane).
    #[inline]
    pub fn sample(&self, i: usize, prims: &Primitives, p: Vec3A, u: Vec2) -> Option<LightSample> {
        match &self.lights[i] {
            LightSource::Area(a) => a.sample(prims, p, u),
            LightSource::Point { position, intensity, attenuation } => {
                let d = *position - p;
                let dist2 = d.length_squared();
                if dist2 == 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let falloff = if *attenuation == Vec3::Z {
                    dist2
                } else {
                    attenuation.x + attenuation.y * dist + attenuation.z * dist2
                };
                Some(LightSample {
                    p: *position,
                    p_err: Vec3A::ZERO,
                    n: Vec3A::ZERO,
                    wi: d / dist,
                    dist,
                    li: *intensity / falloff,
                    pdf: 1.0,
                    delta: true,
                })
            }
            LightSource::Directional { to_light, irradiance } => Some(LightSample {
                p: p + *to_light * 1e30,
                p_err: Vec3A::ZERO,
                n: Vec3A::ZERO,
                wi: *to_light,
                dist: f32::INFINITY,
                li: *irradiance,
                pdf: 1.0,
                delta: true,
            }),
        }
    }

    /// Solid-angle pdf with which `sample` would have produced the direction from `p` to the light point `s`
    /// (a surface hit on area light `i`).
    #[inline]
    pub fn pdf(&self, i: usize, prims: &Primitives, p: Vec3A, s: &SurfaceHit) -> f32 {
        match &self.lights[i] {
            LightSource::Area(a) => a.pdf(prims, p, s),
            _ => 0.0,
        }
    }

    /// Radiance leaving area light `slot` at a point with geometric normal `ng` towards `wo`.
    #[inline]
    pub fn area_radiance(&self, slot: u32, ng: Vec3A, wo: Vec3A) -> Vec3 {
        match &self.lights[slot as usize] {
            LightSource::Area(a) if a.two_sided || ng.dot(wo) > 0.0 => a.radiance,
            _ => Vec3::ZERO,
        }
    }
}
