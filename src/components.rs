//! ECS components carried by scene entities. An entity carries only what it uses: a group node has a `Name` and a
//! `Transform`; a sphere adds `Shape` and `MaterialId`; an area light adds `Light::Area` to a shape; the camera
//! is an entity with a `Camera`. `WorldFromLocal` is derived by the Propagate stage from `Transform` and `Parent`.

use glam::{Affine3A, Vec2, Vec3};

/// Human-readable entity name, used in error messages and statistics.
#[derive(Clone, Debug)]
pub struct Name(pub String);

/// The entity's local transform: `parent_from_local`. Absent means identity.
#[derive(Clone, Copy, Debug)]
pub struct Transform(pub Affine3A);

/// The entity this one is nested in; it inherits that entity's transform.
#[derive(Clone, Copy, Debug)]
pub struct Parent(pub hecs::Entity);

/// Composed transform from the entity's local frame to world space (written by the Propagate stage).
#[derive(Clone, Copy, Debug)]
pub struct WorldFromLocal(pub Affine3A);

/// Index of a mesh in [`crate::mesh::MeshStore`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MeshHandle(pub u32);

/// Geometry of an entity, in its local frame.
#[derive(Clone, Debug)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// The plane `{x : normal . x = offset}`; unbounded, so accelerators keep it aside.
    Plane {
        normal: Vec3,
        offset: f32,
    },
    Triangle {
        p: [Vec3; 3],
        n: Option<[Vec3; 3]>,
        uv: Option<[Vec2; 3]>,
    },
    Mesh(MeshHandle),
    /// The surface of revolution of a profile curve in the xy-plane (z = 0) about the y axis.
    Revolution {
        profile: crate::shapes::Curve,
    },
    /// A bicubic Bézier patch: 16 control points, four rows of four (u along a row).
    BezierPatch {
        points: [glam::Vec3; 16],
    },
}

/// Index of a material in the scene's material table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialId(pub u32);

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
        profile: crate::lights::SpotProfile,
    },
    /// A distant light; `direction` is the direction the light travels (local frame).
    Directional { irradiance: Vec3, direction: Vec3 },
    /// The entity's shape emits `radiance` from its front side (the side of its normal), or both sides; with a
    /// `texture`, `radiance * texture(uv)`.
    Area { radiance: Vec3, two_sided: bool, texture: Option<crate::texture::ImageMap> },
    /// Radiance arriving from infinitely far away: `radiance` times the map's value in the direction (rotated by
    /// the entity's transform), or `radiance` alone without a map.
    Environment { radiance: Vec3, map: Option<std::sync::Arc<crate::envmap::EnvMap>> },
}

/// Camera projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole; `fov_y` is the full vertical field of view in degrees.
    Perspective { fov_y: f32 },
    /// Parallel projection; `height` is the world-space height of the view.
    Orthographic { height: f32 },
}

/// A camera looking from `eye` to `target` (local frame of its entity), with an image size in pixels. An
/// `aperture_radius` above 0 makes it a thin lens focused at `focus_distance` along the view direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub projection: Projection,
    pub width: u32,
    pub height: u32,
    pub aperture_radius: f32,
    pub focus_distance: f32,
    /// Mirror the image left-right: image-right is `up x forward` instead of `forward x up` (pbrt's left-handed
    /// screen space; a pbrt `LookAt` camera sees the world mirrored relative to Prism's convention).
    pub mirror: bool,
    /// Render only this window of the full frame, `[x_min, y_min, x_max, y_max]` as fractions of the frame
    /// (0 = left/top edge, 1 = right/bottom; pbrt's `cropwindow`). `width` x `height` are the window's pixels,
    /// so the full frame's aspect ratio is `(width / (x_max - x_min)) / (height / (y_max - y_min))`.
    pub crop: Option<[f32; 4]>,
}

impl Default for Camera {
    /// A pinhole at (0, 0, 5) looking at the origin, +y up, 40 degrees, 256 x 256.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y: 40.0 },
            width: 256,
            height: 256,
            aperture_radius: 0.0,
            focus_distance: 5.0,
            mirror: false,
            crop: None,
        }
    }
}
