//! Alpha cut-outs: surfaces that exist for rays only where their alpha says so (glTF `alphaMode` MASK and BLEND,
//! pbrt's `alpha` shape parameter). An entity with an [`AlphaMask`] component gets a mask index on each of its
//! triangles (`Primitives::tri_alpha`); [`crate::scene::Scene::intersect`] and `occluded` skip a triangle hit the
//! mask lets through and continue the ray behind it, so camera rays, scattered rays, photons and shadow rays all
//! see the same holes. Scenes without masks pay one `is_empty` test per ray.
//!
//! - `Mask { cutoff }`: the surface is there where `alpha >= cutoff` (glTF MASK; pbrt-v3's alpha textures cut
//!   where alpha is 0, which is a tiny cutoff).
//! - `Blend`: stochastic transparency (Enderton et al. 2010): a ray stops at the surface with probability alpha,
//!   decided by a hash of the ray (origin, direction) and the triangle, as pbrt-v4 does for its alpha textures:
//!   deterministic for a given ray whatever the thread, unbiased over the rays of a pixel, and a shadow ray is
//!   blocked with probability alpha, so shadows are `1 - alpha` light (glTF BLEND, pbrt-v4's alpha).
//!
//! `alpha(uv) = factor * texture(uv).r` (a grey texture: the loader extracts an image's alpha channel).

use crate::geometry::Ray;
use crate::texture::ImageMap;

/// Marks a triangle without a mask in `Primitives::tri_alpha`.
pub const NO_ALPHA: u32 = u32::MAX;

/// How alpha decides whether a ray meets the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Opaque where `alpha >= cutoff`, a hole elsewhere.
    Mask {
        /// The alpha from which the surface is there (glTF's `alphaCutoff`; a tiny one for pbrt's alpha textures).
        cutoff: f32,
    },
    /// Met with probability `alpha` (stochastic transparency).
    Blend,
}

/// The alpha of an entity's surface (ECS component, and the per-scene table entry).
#[derive(Clone, Debug)]
pub struct AlphaMask {
    /// A grey image of alpha values (its red channel is used); `None`: the constant `factor`.
    pub texture: Option<ImageMap>,
    /// Constant alpha, or the factor on the texture's (glTF `baseColorFactor`'s alpha), normally in `[0, 1]`.
    pub factor: f32,
    /// Cut-out or stochastic transparency.
    pub mode: AlphaMode,
}

impl AlphaMask {
    /// Alpha at surface parameter `uv`.
    #[inline]
    pub fn alpha(&self, uv: glam::Vec2) -> f32 {
        match &self.texture {
            None => self.factor,
            Some(t) => self.factor * t.eval(uv).x,
        }
    }
}

/// A uniform number in [0, 1) from a ray and a primitive (a 64-bit mix of their bits).
#[inline]
pub fn hash_unit(ray: &Ray, prim: u32) -> f32 {
    let mut h = 0x9e37_79b9_7f4a_7c15u64 ^ prim as u64;
    for v in [ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z] {
        h = (h ^ v.to_bits() as u64).wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 32;
    }
    h = (h ^ (h >> 29)).wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^= h >> 32;
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}
