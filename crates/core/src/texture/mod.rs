//! Textures: values of material parameters that vary over a surface. A parameter is a [`ColorParam`] or a
//! [`ScalarParam`]: a constant, or a texture of the scene's [`TextureSet`] times a constant factor. Textures are
//! image maps (looked up at the hit's uv, `image`) and solid 6.837 textures (evaluated at the world-space hit
//! point, `solid`); evaluation is an enum match, no dynamic dispatch.
//!
//! Colour parameters take the RGB of an image (a grey image gives grey); scalar parameters take one channel of an
//! image (`R`, `G`, `B` or `Mean`; grey images need none) or a solid texture's value.

mod image;
pub mod perlin;
mod solid;

pub use image::{ByteDecoding, ImageMap, MAX_TEXTURE_SIZE, TexImage, Wrap};
pub use solid::{Solid, SolidKind};

use glam::{Vec2, Vec3, Vec3A};

/// Where a texture is looked up: the surface's uv and its world-space position.
#[derive(Clone, Copy, Debug)]
pub struct TexPoint {
    /// Surface texture coordinates (image textures).
    pub uv: Vec2,
    /// World-space position (solid textures).
    pub p: Vec3A,
}

/// One channel of an image, for scalar parameters.
#[derive(serde::Deserialize, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Channel {
    /// The red channel (the default).
    #[default]
    R,
    /// The green channel.
    G,
    /// The blue channel.
    B,
    /// (R + G + B) / 3.
    Mean,
}

impl Channel {
    #[inline]
    fn of(self, c: Vec3) -> f32 {
        match self {
            Channel::R => c.x,
            Channel::G => c.y,
            Channel::B => c.z,
            Channel::Mean => (c.x + c.y + c.z) * (1.0 / 3.0),
        }
    }
}

/// A colour parameter: a constant, or `scale` times texture `tex`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorParam {
    /// The same linear RGB value everywhere.
    Const(Vec3),
    /// A texture's RGB times a factor.
    Map {
        /// Index into the scene's [`TextureSet`].
        tex: u32,
        /// Factor per RGB channel on the texture's value.
        scale: Vec3,
    },
    /// `a + (b - a) t` per RGB channel, `t` a texture's value (a checkerboard between two colours; pbrt's `mix`).
    Mix {
        /// Index into the scene's [`TextureSet`].
        tex: u32,
        /// The colour where the texture is 0.
        a: Vec3,
        /// The colour where the texture is 1.
        b: Vec3,
    },
}

impl ColorParam {
    /// Black: the constant 0.
    pub const ZERO: ColorParam = ColorParam::Const(Vec3::ZERO);
    /// White: the constant 1.
    pub const ONE: ColorParam = ColorParam::Const(Vec3::ONE);

    /// True for the constant 0 (a lobe with this colour can be left out). Each component compared as `== 0.0`
    /// (either zero, not NaN), on the bits: shifted past the sign they are all 0 exactly then, one test instead of
    /// three float comparisons and their NaN branches (materials are classified by this at every path vertex).
    #[inline]
    pub fn is_zero(&self) -> bool {
        matches!(self, ColorParam::Const(c) if (c.x.to_bits() | c.y.to_bits() | c.z.to_bits()) << 1 == 0)
    }

    /// The constant, if it is one.
    #[inline]
    pub fn constant(&self) -> Option<Vec3> {
        match self {
            ColorParam::Const(c) => Some(*c),
            ColorParam::Map { .. } | ColorParam::Mix { .. } => None,
        }
    }
}

/// A scalar parameter: a constant, or `scale` times a channel of texture `tex`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ScalarParam {
    /// The same value everywhere.
    Const(f32),
    /// One channel of a texture times a factor.
    Map {
        /// Index into the scene's [`TextureSet`].
        tex: u32,
        /// Which channel of an image (solid textures have one value and ignore it).
        channel: Channel,
        /// Factor on the texture's value.
        scale: f32,
    },
}

impl ScalarParam {
    /// The constant, if it is one.
    #[inline]
    pub fn constant(&self) -> Option<f32> {
        match self {
            ScalarParam::Const(c) => Some(*c),
            ScalarParam::Map { .. } => None,
        }
    }
}

/// A texture of the scene.
#[derive(Clone, Debug)]
pub enum Texture {
    /// An image looked up at the surface's uv.
    Image(ImageMap),
    /// A 6.837 solid texture evaluated at the world-space point.
    Solid(Solid),
    /// A checkerboard on the surface's uv: 0 on the cells where `floor(u') + floor(v')` is even, 1 on the others,
    /// `uv' = uv * scale + offset` (pbrt's 2D `checkerboard`, point-sampled).
    UvChecker {
        /// Cells per unit of u and v.
        scale: glam::Vec2,
        /// Added to the scaled uv.
        offset: glam::Vec2,
    },
}

impl Texture {
    /// True when the texture has one value per point (a solid texture or a grey image).
    pub fn is_scalar(&self) -> bool {
        match self {
            Texture::Image(m) => m.image.gray,
            Texture::Solid(_) | Texture::UvChecker { .. } => true,
        }
    }

    /// True for textures that only make scalars (solid textures): they cannot be colours.
    pub fn scalar_only(&self) -> bool {
        matches!(self, Texture::Solid(_) | Texture::UvChecker { .. })
    }

    #[inline]
    fn rgb(&self, at: &TexPoint) -> Vec3 {
        match self {
            Texture::Image(m) => m.eval(at.uv),
            Texture::Solid(s) => Vec3::splat(s.eval(at.p)),
            Texture::UvChecker { scale, offset } => Vec3::splat(uv_checker(at.uv, *scale, *offset)),
        }
    }
}

/// The scene's textures, shared by all materials (images are shared between textures through `Arc`).
#[derive(Clone, Debug, Default)]
pub struct TextureSet {
    /// The textures; a texture's index is its id in parameters.
    pub textures: Vec<Texture>,
}

impl TextureSet {
    /// Append `t` and return its index.
    pub fn add(&mut self, t: Texture) -> u32 {
        self.textures.push(t);
        self.textures.len() as u32 - 1
    }

    /// Texture `id` (an index [`TextureSet::add`] returned; panics beyond the set).
    pub fn get(&self, id: u32) -> &Texture {
        &self.textures[id as usize]
    }

    /// The value of a colour parameter at a point.
    #[inline]
    pub fn color(&self, p: &ColorParam, at: &TexPoint) -> Vec3 {
        match p {
            ColorParam::Const(c) => *c,
            ColorParam::Map { tex, scale } => *scale * self.textures[*tex as usize].rgb(at),
            ColorParam::Mix { tex, a, b } => *a + (*b - *a) * self.textures[*tex as usize].rgb(at),
        }
    }

    /// The value of a scalar parameter at a point.
    #[inline]
    pub fn scalar(&self, p: &ScalarParam, at: &TexPoint) -> f32 {
        match p {
            ScalarParam::Const(c) => *c,
            ScalarParam::Map { tex, channel, scale } => match &self.textures[*tex as usize] {
                Texture::Image(m) => *scale * channel.of(m.eval(at.uv)),
                Texture::Solid(s) => *scale * s.eval(at.p),
                Texture::UvChecker { scale: cells, offset } => *scale * uv_checker(at.uv, *cells, *offset),
            },
        }
    }
}

/// [`Texture::UvChecker`]'s value at `uv`: 0 or 1 (0 for non-finite coordinates).
#[inline]
fn uv_checker(uv: glam::Vec2, scale: glam::Vec2, offset: glam::Vec2) -> f32 {
    let q = uv * scale + offset;
    if !q.is_finite() {
        return 0.0;
    }
    let s = (q.x.floor() as f64) + (q.y.floor() as f64);
    if s.rem_euclid(2.0) == 0.0 { 0.0 } else { 1.0 }
}
