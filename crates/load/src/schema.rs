//! The RON scene schema: what a user writes. Every struct denies unknown fields and defaults whatever has a
//! sensible default, so a minimal scene is a few lines. The reference is the book's `docs/guide/scene-format.md`.

pub use super::material_schema::{ColorDesc, MaterialDesc, ScalarDesc, ScaleDesc, TextureDesc, TextureRef};
use prism_core::sampling::{PixelFilter, PixelPattern, SamplerKind};
use ron::value::RawValue;
use serde::Deserialize;

pub type V3 = [f32; 3];

fn one3() -> V3 {
    [1.0; 3]
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
fn default_cone() -> f32 {
    30.0
}
fn default_falloff() -> f32 {
    5.0
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
    /// Named textures the materials refer to.
    #[serde(default)]
    pub textures: std::collections::BTreeMap<String, TextureDesc>,
    #[serde(default)]
    pub materials: std::collections::BTreeMap<String, MaterialDesc>,
    /// Named inline triangle meshes (`TriangleMesh("name")` shapes refer to them; each is stored once).
    #[serde(default)]
    pub meshes: std::collections::BTreeMap<String, MeshDesc>,
    #[serde(default)]
    pub entities: Vec<EntityDesc>,
}

/// An inline triangle mesh: positions, triangles (indices into positions, counter-clockwise seen from the
/// front), and optionally one normal and one uv per position.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    pub positions: Vec<V3>,
    pub indices: Vec<[u32; 3]>,
    #[serde(default)]
    pub normals: Vec<V3>,
    #[serde(default)]
    pub uvs: Vec<[f32; 2]>,
}

/// Where an entity's surface exists for rays: `alpha = factor * texture(uv).r` (a grey image, or the red channel).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct AlphaDesc {
    #[serde(default)]
    pub texture: Option<String>,
    #[serde(default = "unit")]
    pub factor: f32,
    /// `Mask(cutoff: c)`: a hole where alpha < c; `Blend`: met with probability alpha (stochastic transparency).
    #[serde(default)]
    pub mode: AlphaModeDesc,
}

#[derive(Deserialize, Debug, Clone, Copy, Default)]
#[serde(deny_unknown_fields)]
pub enum AlphaModeDesc {
    Mask {
        cutoff: f32,
    },
    #[default]
    Blend,
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
    /// Progressive passes the samples are split into evenly (default: `settings::default_pass_layout`).
    #[serde(default)]
    pub passes: Option<u32>,
    /// `independent`, `stratified` or `sobol` (the default).
    #[serde(default)]
    pub sampler: Option<SamplerKind>,
    /// Pixel positions from an explicit pattern: `random`, `stratified`, `uniform`, `rgss`.
    #[serde(default)]
    pub pattern: Option<PixelPattern>,
    /// `Box(radius: 0.5)` (default), `Tent(radius: 1)`, `Gaussian(sigma: 0.5)`.
    #[serde(default)]
    pub filter: Option<PixelFilter>,
    /// Samples after the first pass go where the image is noisy (`false` by default).
    #[serde(default)]
    pub adaptive: Option<bool>,
    #[serde(default)]
    pub seed: Option<u64>,
    /// Time budget in seconds: stop when it is spent (the pass then running is cut short and does not count).
    #[serde(default)]
    pub time: Option<f64>,
    /// Noise target: stop after the pass at which the estimated relMSE is at most this.
    #[serde(default)]
    pub noise: Option<f32>,
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
    /// Thin lens: radius of the aperture in world units (0: pinhole).
    #[serde(default)]
    pub aperture_radius: f32,
    /// Thin lens: distance of the plane in focus along the view direction (default: eye to target).
    #[serde(default)]
    pub focus_distance: Option<f32>,
    /// Image width and height in pixels.
    #[serde(default = "default_size")]
    pub size: (u32, u32),
    /// Mirror the image left-right (image-right = up x forward: pbrt's left-handed screen space).
    #[serde(default)]
    pub mirror: bool,
    /// Render only the window `(x_min, y_min, x_max, y_max)` of the full frame (fractions; pbrt's `cropwindow`);
    /// `size` is then the window's size in pixels.
    #[serde(default)]
    pub crop: Option<[f32; 4]>,
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
    /// An alpha cut-out of the entity's triangles (see [`AlphaDesc`]).
    #[serde(default)]
    pub alpha: Option<AlphaDesc>,
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
    /// A mesh file (OBJ or PLY), path relative to the scene file.
    Mesh {
        path: String,
        /// Ignore the file's vertex normals and shade flat.
        #[serde(default)]
        flat: bool,
        /// Reverse the triangles' winding: the front face (the side an area light emits from) becomes the back.
        #[serde(default)]
        reverse: bool,
    },
    /// A mesh of the scene's `meshes` table, by name.
    TriangleMesh(String),
    /// A glTF file's scene (`.gltf` or `.glb`), its node tree nested under this entity: its meshes, materials,
    /// punctual lights and emissive surfaces; its camera only when the RON scene has none. `materials` replaces
    /// glTF materials by name with materials of this scene (`Mesh(path: "x.glb")` is the same with no options).
    Gltf {
        path: String,
        /// The glTF scene by index (default: the file's default scene).
        #[serde(default)]
        scene: Option<usize>,
        /// glTF material name -> the name of a material of this RON scene.
        #[serde(default)]
        materials: std::collections::BTreeMap<String, String>,
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
    /// Spot light at `position` pointing along `direction` (or at `target`): `intensity` (W/sr) on its axis and
    /// inside the cone of half-angle `cone_angle - falloff` (degrees), falling smoothly to 0 at `cone_angle`.
    Spot {
        intensity: V3,
        #[serde(default)]
        position: V3,
        #[serde(default)]
        direction: Option<V3>,
        #[serde(default)]
        target: Option<V3>,
        #[serde(default = "default_cone")]
        cone_angle: f32,
        #[serde(default = "default_falloff")]
        falloff: f32,
        /// Shape of the fall-off: `smoothstep` (pbrt-v4, default), `quartic` (pbrt-v3) or `gltf`.
        #[serde(default)]
        profile: prism_core::lights::SpotProfile,
    },
    /// Distant light travelling along `direction`; `irradiance` in W/m^2 on a surface facing it.
    Directional {
        irradiance: V3,
        #[serde(default = "down")]
        direction: V3,
    },
    /// The entity's shape emits `radiance` (W/m^2/sr) from its front face, or both faces; with a `texture` (an
    /// image of `textures`), `radiance * texture(uv)`.
    Area {
        radiance: V3,
        #[serde(default)]
        two_sided: bool,
        #[serde(default)]
        texture: Option<String>,
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
        layout: Option<prism_core::envmap::SourceLayout>,
        #[serde(default = "one3")]
        radiance: V3,
        #[serde(default = "unit")]
        scale: f32,
    },
}
