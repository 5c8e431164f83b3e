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
    Point {
        /// Radiant intensity per RGB channel, W/sr.
        intensity: Vec3,
        /// Position, local frame.
        position: Vec3,
        /// `(a0, a1, a2)` of the distance fall-off `a0 + a1 d + a2 d^2`.
        attenuation: Vec3,
    },
    /// A spot light at `position` pointing along `direction` (local frame): intensity `intensity` (W/sr) inside
    /// the cone of half-angle `cone_angle - falloff` degrees, smoothly falling to 0 at `cone_angle` degrees (the
    /// shape of the fall-off is `profile`'s).
    Spot {
        /// Radiant intensity inside the inner cone per RGB channel, W/sr.
        intensity: Vec3,
        /// Position, local frame.
        position: Vec3,
        /// The cone's axis, the direction the light points to (local frame; need not be unit).
        direction: Vec3,
        /// Half-angle of the outer cone, degrees (no light outside it).
        cone_angle: f32,
        /// Width of the fall-off band inside the outer cone, degrees (a larger one makes the band the whole cone).
        falloff: f32,
        /// How the intensity falls from the inner cone to the outer.
        profile: super::SpotProfile,
    },
    /// A distant light; `direction` is the direction the light travels (local frame).
    Directional {
        /// Irradiance per RGB channel on a surface facing the light, W/m^2.
        irradiance: Vec3,
        /// The direction the light travels, local frame (need not be unit).
        direction: Vec3,
    },
    /// The entity's shape emits `radiance` from its front side (the side of its normal), or both sides; with a
    /// `texture`, `radiance * texture(uv)`.
    Area {
        /// Emitted radiance per RGB channel, W/(m^2 sr).
        radiance: Vec3,
        /// Emit from both sides of the surface.
        two_sided: bool,
        /// Emission texture (glTF's emissive texture), looked up at the surface's uv.
        texture: Option<ImageMap>,
    },
    /// Radiance arriving from infinitely far away: `radiance` times the map's value in the direction (rotated by
    /// the entity's transform), or `radiance` alone without a map.
    Environment {
        /// Radiance per RGB channel, W/(m^2 sr), or the factor on the map's values.
        radiance: Vec3,
        /// The environment map, in the entity's frame.
        map: Option<Arc<EnvMap>>,
    },
}
