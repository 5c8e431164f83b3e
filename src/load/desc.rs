//! The RON scene schema: what a user writes. Every struct denies unknown fields and defaults whatever has a
//! sensible default, so a minimal scene is a few lines. See README "Scene format" for the reference.

use crate::sampling::PixelPattern;
use ron::value::RawValue;
use serde::Deserialize;

pub type V3 = [f32; 3];

fn one3() -> V3 {
    [1.0; 3]
}
fn half3() -> V3 {
    [0.5; 3]
}
fn yes() -> bool {
    true
}
fn ior_glass() -> f32 {
    1.5
}
fn unit() -> f32 {
    1.0
}
fn up() -> V3 {
    [0.0, 1.0, 0.0]
}
fn down() -> V3 {
    [0.0, -1.0, 0.0]
}
fn inverse_square() -> V3 {
    [0.0, 0.0, 1.0]
}
fn default_eye() -> V3 {
    [0.0, 0.0, 5.0]
}
fn default_fov() -> f32 {
    40.0
}
fn default_size() -> (u32, u32) {
    (256, 256)
}

/// A whole scene file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc<'a> {
    #[serde(default)]
    pub camera: Option<CameraDesc>,
    #[serde(default, borrow)]
    pub render: RenderDesc<'a>,
    /// Radiance of rays that leave the scene (for integrators without an environment light).
    #[serde(default)]
    pub background: V3,
    /// Ambient radiance, reflected by materials' `ambient` coefficient (Phong integrator; 0 = physically based).
    #[serde(default)]
    pub ambient: V3,
    #[serde(default)]
    pub materials: std::collections::BTreeMap<String, MaterialDesc>,
    #[serde(default)]
    pub entities: Vec<EntityDesc>,
}

/// How to render: every field can be overridden on the command line.
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc<'a> {
    /// `name` or `name(param: value, ...)`; the plugin owns the parameters.
    #[serde(default, borrow)]
    pub integrator: Option<&'a RawValue>,
    /// `bvh` (default), `kdtree`, `grid` or `brute`.
    #[serde(default)]
    pub accel: Option<AccelDesc>,
    /// Grid cells along x, y, z (implies `accel: grid`); automatic when absent.
    #[serde(default)]
    pub grid: Option<[u32; 3]>,
    /// Samples per pixel in total.
    #[serde(default)]
    pub spp: Option<u32>,
    /// Progressive passes the samples are split into.
    #[serde(default)]
    pub passes: Option<u32>,
    #[serde(default)]
    pub pattern: Option<PixelPattern>,
    #[serde(default)]
    pub seed: Option<u64>,
    /// Time budget in seconds: stop after the pass that crosses it.
    #[serde(default)]
    pub time: Option<f64>,
    /// PNG exposure in stops.
    #[serde(default)]
    pub exposure: Option<f32>,
}

#[derive(Deserialize, Debug, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum AccelDesc {
    Bvh,
    Kdtree,
    Grid,
    Brute,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    #[serde(default = "default_eye")]
    pub eye: V3,
    #[serde(default)]
    pub target: V3,
    #[serde(default = "up")]
    pub up: V3,
    /// Full vertical field of view in degrees (pinhole).
    #[serde(default = "default_fov")]
    pub fov: f32,
    /// View height in world units: makes the camera orthographic.
    #[serde(default)]
    pub orthographic: Option<f32>,
    /// Image width and height in pixels.
    #[serde(default = "default_size")]
    pub size: (u32, u32),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum MaterialDesc {
    /// Ideal diffuse reflector; `albedo` in [0,1].
    Lambert {
        #[serde(default = "half3")]
        albedo: V3,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// Phong material, physically based units (see `material.rs`).
    Phong {
        #[serde(default)]
        ambient: V3,
        #[serde(default)]
        diffuse: V3,
        #[serde(default)]
        specular: V3,
        #[serde(default = "unit")]
        exponent: f32,
        #[serde(default)]
        reflective: V3,
        #[serde(default)]
        transparent: V3,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// Ideal mirror.
    Mirror {
        #[serde(default = "one3")]
        reflectance: V3,
    },
    /// Smooth glass: Fresnel-weighted reflection and refraction.
    Glass {
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "one3")]
        transmittance: V3,
    },
    /// A 6.837 course material (`Material`/`PhongMaterial`) with the course's non-physical shading: ambient
    /// reflectance = `diffuse`, Blinn-Phong specular `specular (n.h)^exponent` without energy normalisation,
    /// mirror (`reflective`) and refraction (`transparent`, index `ior`) without Fresnel.
    Mit6837 {
        #[serde(default = "one3")]
        diffuse: V3,
        #[serde(default)]
        specular: V3,
        #[serde(default = "unit")]
        exponent: f32,
        #[serde(default)]
        reflective: V3,
        #[serde(default)]
        transparent: V3,
        #[serde(default = "unit")]
        ior: f32,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// A black surface that emits `radiance`: the entity becomes an area light.
    Emissive {
        radiance: V3,
        #[serde(default)]
        two_sided: bool,
    },
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct EntityDesc {
    #[serde(default)]
    pub name: Option<String>,
    /// Applied like a matrix product, left to right: `[A, B]` maps `p` to `A(B(p))`.
    #[serde(default)]
    pub transform: Vec<TransformOp>,
    #[serde(default)]
    pub shape: Option<ShapeDesc>,
    /// Name of an entry of `materials`.
    #[serde(default)]
    pub material: Option<String>,
    #[serde(default)]
    pub light: Option<LightDesc>,
    /// Nested entities: they inherit this entity's transform (and its material if they name none).
    #[serde(default)]
    pub children: Vec<EntityDesc>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum TransformOp {
    Translate(V3),
    /// Non-uniform scale.
    Scale(V3),
    UniformScale(f32),
    /// Rotation by `degrees` about `axis` (right-handed).
    Rotate {
        axis: V3,
        degrees: f32,
    },
    /// Rotation by Euler angles in degrees: about x first, then y, then z (R = Rz Ry Rx).
    Euler(V3),
    /// A 4x4 matrix, rows listed top to bottom (the last row must be 0 0 0 1).
    Matrix([[f32; 4]; 4]),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum ShapeDesc {
    Sphere {
        #[serde(default)]
        center: V3,
        #[serde(default = "unit")]
        radius: f32,
    },
    /// The plane `{x : normal . x = offset}`.
    Plane {
        #[serde(default = "up")]
        normal: V3,
        #[serde(default)]
        offset: f32,
    },
    Triangle {
        vertices: [V3; 3],
        #[serde(default)]
        normals: Option<[V3; 3]>,
        #[serde(default)]
        uvs: Option<[[f32; 2]; 3]>,
    },
    /// Four corners counter-clockwise seen from the front; default the square [-1,1]^2 at z = 0 facing +z.
    Quad {
        #[serde(default)]
        corners: Option<[V3; 4]>,
    },
    /// The cube [-1,1]^3 (outward normals); scale and place it with `transform`.
    Cube,
    /// A mesh file (OBJ), path relative to the scene file.
    Mesh {
        path: String,
        /// Ignore the file's vertex normals and shade flat.
        #[serde(default)]
        flat: bool,
    },
    /// The surface of revolution of `profile` (a curve in the xy-plane, z = 0) about the y axis, intersected
    /// exactly, or as a mesh with `tessellation: Some((curve: n, revolution: m))`.
    Revolution {
        profile: CurveDesc,
        #[serde(default)]
        tessellation: Option<TessellationDesc>,
    },
    /// A bicubic Bézier patch: 16 control points, four rows of four (u along a row), intersected exactly, or as
    /// a mesh with `tessellation: Some((patch: n))`.
    BezierPatch {
        points: Vec<V3>,
        #[serde(default)]
        tessellation: Option<TessellationDesc>,
    },
    /// Every surface of a 6.837 spline file (`spline8_*.txt`: surfaces of revolution and Bézier patches; curves
    /// alone are left out), exact or tessellated.
    Splines {
        path: String,
        #[serde(default)]
        tessellation: Option<TessellationDesc>,
    },
}

/// A piecewise cubic curve: `Bezier([...])` (3k + 1 control points) or `BSpline([...])` (uniform cubic, at least
/// 4; a point repeated three times is passed through).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum CurveDesc {
    Bezier(Vec<V3>),
    BSpline(Vec<V3>),
}

fn ten() -> usize {
    10
}

/// Tessellation resolutions (the 6.837 curve editor's): segments per cubic piece of a profile, steps around a
/// revolution, quads along each side of a patch.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct TessellationDesc {
    #[serde(default = "ten")]
    pub curve: usize,
    #[serde(default = "ten")]
    pub revolution: usize,
    #[serde(default = "ten")]
    pub patch: usize,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum LightDesc {
    /// Isotropic point light; `intensity` in W/sr. Irradiance `I cos / (a0 + a1 d + a2 d^2)` with
    /// `attenuation: (a0, a1, a2)`, physically `(0, 0, 1)` (the default); other values reproduce 6.837 scenes.
    Point {
        intensity: V3,
        #[serde(default)]
        position: V3,
        #[serde(default = "inverse_square")]
        attenuation: V3,
    },
    /// Distant light travelling along `direction`; `irradiance` in W/m^2 on a surface facing it.
    Directional {
        irradiance: V3,
        #[serde(default = "down")]
        direction: V3,
    },
    /// The entity's shape emits `radiance` (W/m^2/sr) from its front face, or both faces.
    Area {
        radiance: V3,
        #[serde(default)]
        two_sided: bool,
    },
    /// Light from infinitely far away: `radiance * scale * map(direction)`, or the constant `radiance * scale`.
    /// `map` is one file (equirect or vertical cross), `faces` six files (px nx py ny pz nz); the entity's
    /// transform rotates the map.
    Environment {
        #[serde(default)]
        map: Option<String>,
        #[serde(default)]
        faces: Option<[String; 6]>,
        #[serde(default)]
        layout: Option<crate::envmap::SourceLayout>,
        #[serde(default = "one3")]
        radiance: V3,
        #[serde(default = "unit")]
        scale: f32,
    },
}
