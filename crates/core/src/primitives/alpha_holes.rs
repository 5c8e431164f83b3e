//! Alpha-masked triangles in the primitive store: whether a hit falls on a hole of its triangle's mask (see
//! [`crate::alpha`]).

use super::{Hit, Primitives};
use crate::alpha::{AlphaMode, NO_ALPHA, hash_unit};
use crate::geometry::Ray;

impl Primitives {
    /// True when the scene has alpha-masked triangles (rays then go through [`Primitives::alpha_passes`]).
    #[inline]
    pub fn has_alpha(&self) -> bool {
        !self.tri_alpha.is_empty()
    }

    /// True when `hit` (found along `ray`) is on a hole of its triangle's alpha mask: the ray goes on.
    #[inline]
    pub fn alpha_passes(&self, hit: &Hit, ray: &Ray) -> bool {
        let Some(&m) = self.tri_alpha.get(hit.prim as usize) else {
            return false;
        };
        if m == NO_ALPHA {
            return false;
        }
        let mask = &self.alpha_masks[m as usize];
        let uvs = self.tri_shading[hit.prim as usize].uvs;
        let uv = (1.0 - hit.b1 - hit.b2) * uvs[0] + hit.b1 * uvs[1] + hit.b2 * uvs[2];
        let a = mask.alpha(uv);
        match mask.mode {
            AlphaMode::Mask { cutoff } => a < cutoff || a.is_nan(),
            AlphaMode::Blend => hash_unit(ray, hit.prim) >= a || a.is_nan(),
        }
    }
}
