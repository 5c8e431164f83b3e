//! The RON schema of materials and textures (`docs/guide/materials.md` and `docs/guide/textures.md`). A colour or scalar parameter is
//! a constant or a texture reference:
//!
//! ```ron
//! albedo: (0.8, 0.6, 0.5)            // a colour
//! albedo: 0.5                        // a grey
//! albedo: Texture("wood")            // a texture of `textures`
//! albedo: Map(texture: "wood", scale: (1, 0.9, 0.8))   // a texture times a factor
//! alpha: Map(texture: "orm", channel: G, scale: 0.5)  // one channel of an image, for a scalar
//! ```

use super::schema::{TransformOp, V3};
use prism_core::texture::{Channel, Wrap};
use serde::Deserialize;

fn one3() -> ColorDesc {
    ColorDesc::Rgb([1.0; 3])
}
fn half3() -> ColorDesc {
    ColorDesc::Rgb([0.5; 3])
}
fn quarter3() -> ColorDesc {
    ColorDesc::Rgb([0.25; 3])
}
fn zero3() -> ColorDesc {
    ColorDesc::Rgb([0.0; 3])
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
fn scalar_one() -> ScalarDesc {
    ScalarDesc::Value(1.0)
}
fn default_alpha() -> ScalarDesc {
    ScalarDesc::Value(0.1)
}
fn scalar_zero() -> ScalarDesc {
    ScalarDesc::Value(0.0)
}
fn thickness() -> f32 {
    0.01
}
fn max_depth() -> u32 {
    10
}
fn one() -> u32 {
    1
}
fn uv_one() -> [f32; 2] {
    [1.0, 1.0]
}

/// A colour: `(r, g, b)`, a grey `g`, `Texture("name")` or `Map(texture: "name", scale: ...)`.
#[derive(Deserialize, Debug, Clone, PartialEq)]
#[serde(untagged)]
pub enum ColorDesc {
    Rgb(V3),
    Gray(f32),
    Texture(TextureRef),
}

/// A scalar: a number, `Texture("name")` or `Map(texture: "name", channel: G, scale: ...)`.
#[derive(Deserialize, Debug, Clone, PartialEq)]
#[serde(untagged)]
pub enum ScalarDesc {
    Value(f32),
    Texture(TextureRef),
}

/// A texture used by a parameter.
#[derive(Deserialize, Debug, Clone, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum TextureRef {
    /// The texture as it is.
    Texture(String),
    /// The texture times `scale`; `channel` picks one channel of an image for a scalar parameter.
    Map {
        texture: String,
        #[serde(default)]
        scale: Option<ScaleDesc>,
        #[serde(default)]
        channel: Option<Channel>,
    },
    /// A colour `a + (b - a) t`, `t` the texture's value (a checkerboard of two colours).
    Mix { texture: String, a: V3, b: V3 },
}

/// A factor: one number or one per channel.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq)]
#[serde(untagged)]
pub enum ScaleDesc {
    Rgb(V3),
    Uniform(f32),
}

/// A named texture (`textures: { "name": ..., }`).
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum TextureDesc {
    /// An image file (PNG, JPEG, Radiance HDR, OpenEXR), path relative to the scene file. `raw: true` for data
    /// (normal, roughness, height maps): 8-bit values are used as stored instead of decoded from sRGB.
    Image {
        path: String,
        #[serde(default)]
        raw: bool,
        #[serde(default)]
        wrap: Wrap,
        #[serde(default = "uv_one")]
        uv_scale: [f32; 2],
        #[serde(default)]
        uv_offset: [f32; 2],
        /// Degrees, applied after `uv_scale` and before `uv_offset` (glTF's `KHR_texture_transform` rotation).
        #[serde(default)]
        uv_rotation: f32,
        /// Decode 8- and 16-bit values as `c^gamma` instead of from sRGB (pbrt's `"encoding" "gamma g"`).
        #[serde(default)]
        gamma: Option<f32>,
    },
    /// 2D checkerboard on the surface's uv: 0 and 1 on alternating cells of `uv * uv_scale + uv_offset`.
    Checker2d {
        #[serde(default = "uv_one")]
        uv_scale: [f32; 2],
        #[serde(default)]
        uv_offset: [f32; 2],
    },
    /// 3D checkerboard: 0 and 1 on alternating unit cells of `transform(p)`.
    Checker3d {
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// Perlin noise (6.837): `(N + 1) / 2` with `N = sum_{i<octaves} noise(2^i q) / 2^i`.
    Noise {
        #[serde(default)]
        transform: Vec<TransformOp>,
        #[serde(default = "one_octave")]
        octaves: u32,
    },
    /// Marble (6.837): `(sin(frequency q.x + amplitude N(q)) + 1) / 2`.
    Marble {
        #[serde(default)]
        transform: Vec<TransformOp>,
        #[serde(default = "one_octave")]
        octaves: u32,
        #[serde(default = "unit")]
        frequency: f32,
        #[serde(default = "unit")]
        amplitude: f32,
    },
    /// Wood: rings around the texture-space y axis, `(sin(frequency |q.xz| + amplitude N(q)) + 1) / 2`.
    Wood {
        #[serde(default)]
        transform: Vec<TransformOp>,
        #[serde(default = "one_octave")]
        octaves: u32,
        #[serde(default = "unit")]
        frequency: f32,
        #[serde(default = "unit")]
        amplitude: f32,
    },
}

fn one_octave() -> u32 {
    1
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub enum MaterialDesc {
    /// Ideal diffuse reflector; `albedo` in `[0, 1]`.
    Lambert {
        #[serde(default = "half3")]
        albedo: ColorDesc,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// Phong material, physically based units (see `material/mod.rs`).
    Phong {
        #[serde(default = "zero3")]
        ambient: ColorDesc,
        #[serde(default = "zero3")]
        diffuse: ColorDesc,
        #[serde(default = "zero3")]
        specular: ColorDesc,
        #[serde(default = "scalar_one")]
        exponent: ScalarDesc,
        #[serde(default = "zero3")]
        reflective: ColorDesc,
        #[serde(default = "zero3")]
        transparent: ColorDesc,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// Ideal mirror.
    Mirror {
        #[serde(default = "one3")]
        reflectance: ColorDesc,
    },
    /// Smooth glass: Fresnel-weighted reflection and refraction.
    Glass {
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "one3")]
        transmittance: ColorDesc,
    },
    /// A 6.837 course material (`Material`/`PhongMaterial`) with the course's non-physical shading: ambient
    /// reflectance = `diffuse`, Blinn-Phong specular `specular (n.h)^exponent` without energy normalisation,
    /// mirror (`reflective`) and refraction (`transparent`, index `ior`) without Fresnel.
    Mit6837 {
        #[serde(default = "one3")]
        diffuse: ColorDesc,
        #[serde(default = "zero3")]
        specular: ColorDesc,
        #[serde(default = "scalar_one")]
        exponent: ScalarDesc,
        #[serde(default = "zero3")]
        reflective: ColorDesc,
        #[serde(default = "zero3")]
        transparent: ColorDesc,
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
    /// GGX rough metal: a named metal (`material: "Au"`), a complex index (`eta`, `k`), or a reflectance colour at
    /// normal incidence (`reflectance`, Schlick). `alpha` 0 is a smooth metal.
    RoughConductor {
        #[serde(default = "default_alpha")]
        alpha: ScalarDesc,
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        eta: Option<V3>,
        #[serde(default)]
        k: Option<V3>,
        #[serde(default)]
        reflectance: Option<ColorDesc>,
        /// Multiplies the reflectance (Mitsuba's `specular_reflectance`).
        #[serde(default = "one3")]
        scale: ColorDesc,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// GGX rough glass (reflection and transmission); `alpha` 0 is smooth glass.
    RoughDielectric {
        #[serde(default = "default_alpha")]
        alpha: ScalarDesc,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "one3")]
        reflectance: ColorDesc,
        #[serde(default = "one3")]
        transmittance: ColorDesc,
    },
    /// A diffuse base under a GGX dielectric coat.
    RoughPlastic {
        #[serde(default = "default_alpha")]
        alpha: ScalarDesc,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "half3")]
        diffuse: ColorDesc,
        #[serde(default = "one3")]
        specular: ColorDesc,
        #[serde(default = "yes")]
        two_sided: bool,
    },
    /// pbrt-v4's `coateddiffuse`: a Lambertian base of `reflectance` under a dielectric coat of GGX width `alpha`
    /// and index `ior`, with a medium of `thickness` (mean free paths), single-scattering `albedo` and
    /// Henyey–Greenstein `g` between them, evaluated by random walks of at most `max_depth` events (`samples`
    /// walks per value).
    CoatedDiffuse {
        #[serde(default = "half3")]
        reflectance: ColorDesc,
        #[serde(default = "scalar_zero")]
        alpha: ScalarDesc,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "thickness")]
        thickness: f32,
        #[serde(default = "zero3")]
        albedo: ColorDesc,
        #[serde(default)]
        g: f32,
        #[serde(default = "max_depth")]
        max_depth: u32,
        #[serde(default = "one")]
        samples: u32,
    },
    /// pbrt-v4's `coatedconductor`: a GGX conductor of width `conductor_alpha` (a named metal, `eta` with `k`, or a
    /// `reflectance`; copper by default, as in pbrt) under the coat of `CoatedDiffuse`.
    CoatedConductor {
        #[serde(default = "scalar_zero")]
        alpha: ScalarDesc,
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "scalar_zero")]
        conductor_alpha: ScalarDesc,
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        eta: Option<V3>,
        #[serde(default)]
        k: Option<V3>,
        #[serde(default)]
        reflectance: Option<ColorDesc>,
        #[serde(default = "thickness")]
        thickness: f32,
        #[serde(default = "zero3")]
        albedo: ColorDesc,
        #[serde(default)]
        g: f32,
        #[serde(default = "max_depth")]
        max_depth: u32,
        #[serde(default = "one")]
        samples: u32,
    },
    /// Lambertian reflection and Lambertian transmission to the other side (pbrt-v4's `diffusetransmission`).
    DiffuseTransmission {
        #[serde(default = "quarter3")]
        reflectance: ColorDesc,
        #[serde(default = "quarter3")]
        transmittance: ColorDesc,
    },
    /// A thin slab of glass: Fresnel reflection with the slab's inter-reflections, straight transmission (pbrt-v4's
    /// `thindielectric`).
    ThinDielectric {
        #[serde(default = "ior_glass")]
        ior: f32,
        #[serde(default = "one3")]
        reflectance: ColorDesc,
        #[serde(default = "one3")]
        transmittance: ColorDesc,
    },
    /// `(1 - weight) a + weight b`.
    Blend { a: String, b: String, weight: ScalarDesc },
    /// `material` with a tangent-space normal map (an image texture, usually `raw: true`).
    NormalMap {
        material: String,
        texture: String,
        #[serde(default = "unit")]
        strength: f32,
        #[serde(default)]
        flip_green: bool,
    },
    /// `material` with a bump map: the surface displaced along its normal by `height` (world units).
    Bump { material: String, height: ScalarDesc },
}
