//! A light as a scene describes it, in its entity's local frame; [`super::LightSet::build`] resolves it to world
//! space.

use crate::envmap::EnvMap;
use crate::texture::ImageMap;
use glam::Vec3;
use std::sync::Arc;

/// A light. Physical units: `intensity` in W/sr (radiant intensity), `irradiance` in W/m^2 on a surface facing the
/// light, `radiance` in W/(m^2 sr).
#[derive(Clone, Debug)]
pub enum Light {
    /// An isotropic point light at `position` (local frame); irradiance `intensity cos / (a0 + a1 d + a2 d^2)`
    /// with `attenuation = (a0, a1, a2)`, `(0, 0, 1)` for a physical light.
    Point { intensity: Vec3, position: Vec3, attenuation: Vec3 },
    /// A spot light at `position` pointing along `direction` (local frame): intensity `intensity` (W/sr) inside
    /// the cone of half-angle `cone_angle - falloff` degrees, smoothly falling to 0 at `cone_angle` degrees (the
    /// shape of the fall-off is `profile`'s).
    Spot {
        intensity: Vec3,
        position: Vec3,
        direction: Vec3,
        cone_angle: f32,
        falloff: f32,
        profile: super::SpotProfile,
    },
    /// A distant light; `direction` is the direction the light travels (local frame).
    Directional { irradiance: Vec3, direction: Vec3 },
    /// The entity's shape emits `radiance` from its front side (the side of its normal), or both sides; with a
    /// `texture`, `radiance * texture(uv)`.
    Area { radiance: Vec3, two_sided: bool, texture: Option<ImageMap> },
    /// Radiance arriving from infinitely far away: `radiance` times the map's value in the direction (rotated by
    /// the entity's transform), or `radiance` alone without a map.
    Environment { radiance: Vec3, map: Option<Arc<EnvMap>> },
}
