//! The gather at a visible point and the per-pixel progressive statistics.
//!
//! A photon within the radius counts when it arrived on the side the visible point is seen from (its surface's
//! geometric normal on the photon's side agrees with the visible point's on the viewer's side, so photons on the
//! far side of a wall thinner than the radius are not gathered) and contributes `power x f(wo, wi)`. The
//! contributions are summed in fixed point, so the sum does not depend on the order the lookup visits photons in:
//! the hash grid and the kd-tree give the same bits, and so do row shards whose grids differ.
//!
//! Statistics (f64, so 10^5 iterations neither underflow the radius nor lose the flux): `n` (accumulated photon
//! count N), `r2` (radius squared), `tau` (flux), `direct` (sum of emission and direct light from the eye passes).
//! Update after a gather of `M` photons and flux `Phi` (Hachisuka & Jensen 2009):
//! `N' = N + alpha M`, `R'^2 = R^2 (N + alpha M) / (N + M)`, `tau' = (tau + beta Phi) R'^2 / R^2`.

use super::photons::Photon;
use super::visible::{EyeResult, VisiblePoint};
use glam::{DVec3, Vec3, Vec3A};
use prism_core::film::FixedRgb;
use prism_core::scene::Scene;

/// One pixel's progressive photon mapping state.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelStats {
    /// Accumulated photon count N.
    pub n: f64,
    /// Squared gather radius (0 until the pixel's first visible point).
    pub r2: f64,
    /// Accumulated flux tau (already multiplied by the visible points' path weights).
    pub tau: DVec3,
    /// Sum over iterations of the emission and direct light the eye passes found.
    pub direct: DVec3,
}

/// The smallest squared radius kept (relative to the initial one), so the radius never underflows.
const MIN_R2_FRACTION: f64 = 1e-12;

impl PixelStats {
    /// Set the initial radius the first time the pixel has a visible point.
    #[inline]
    pub fn init_radius(&mut self, r: f32) {
        if self.r2 == 0.0 && r > 0.0 && r.is_finite() {
            self.r2 = r as f64 * r as f64;
        }
    }

    #[inline]
    pub fn has_radius(&self) -> bool {
        self.r2 > 0.0
    }

    #[inline]
    pub fn radius(&self) -> f64 {
        self.r2.sqrt()
    }

    /// Fold in one iteration: the eye result (direct light, visible point weight) and the gathered flux.
    #[inline]
    pub fn update(&mut self, eye: &EyeResult, phi: DVec3, m: u32, alpha: f64, add_direct: bool) {
        if add_direct {
            self.direct += eye.direct.as_dvec3();
        }
        let Some(vp) = &eye.vp else { return };
        if m == 0 {
            return;
        }
        let m = m as f64;
        let n_new = self.n + alpha * m;
        let shrink = n_new / (self.n + m);
        let flux = self.tau + vp.beta.as_dvec3() * phi;
        let r2_new = (self.r2 * shrink).max(self.r2 * MIN_R2_FRACTION);
        self.tau = flux * (r2_new / self.r2);
        self.r2 = r2_new;
        self.n = n_new;
    }

    /// Radiance estimate: `direct / direct_count + tau / (photons pi R^2)`.
    #[inline]
    pub fn estimate(&self, direct_count: f64, photons: f64) -> Vec3 {
        let mut l = self.direct / direct_count;
        if self.r2 > 0.0 && photons > 0.0 {
            l += self.tau / (photons * std::f64::consts::PI * self.r2);
        }
        l.as_vec3()
    }
}

/// Sum of photon power x BSDF over the photons within `r` of the visible point whose full path has at most
/// `max_segments` segments, and their count; `query` walks the lookup structure. With `wide_only` the BSDF's
/// near-specular parts are left out (the eye pass counts them: `visible.rs`).
#[inline]
pub fn gather(
    scene: &Scene,
    vp: &VisiblePoint,
    r: f32,
    max_segments: u32,
    wide_only: bool,
    query: impl FnOnce(Vec3A, f32, &mut dyn FnMut(&Photon)),
) -> (DVec3, u32) {
    let Some(bsdf) = scene.bsdf(&vp.hit, vp.wo) else {
        return (DVec3::ZERO, 0);
    };
    let ng = bsdf.geometric_normal();
    // Photons that arrived on the other side of the surface light it only through a diffuse transmitter (else
    // they would leak through thin walls).
    let both_sides = bsdf.transmits_diffusely();
    let mut phi = FixedRgb::default();
    let mut m = 0u32;
    query(vp.hit.p, r, &mut |ph: &Photon| {
        if (ph.ng.dot(ng) <= 0.0 && !both_sides) || vp.eye_depth + ph.depth + 2 > max_segments {
            return;
        }
        m += 1;
        let c: Vec3 = ph.beta * if wide_only { bsdf.eval_wide(ph.wi) } else { bsdf.eval(ph.wi) };
        if c != Vec3::ZERO {
            phi.add(FixedRgb::from_rgb(c.x as f64, c.y as f64, c.z as f64));
        }
    });
    (phi.to_dvec3(), m)
}

/// Bytes per pixel of [`PixelStats::to_bytes`].
pub const STATS_BYTES: usize = 64;

impl PixelStats {
    /// The statistics as 8 little-endian f64 (n, r2, tau, direct).
    pub fn to_bytes(&self, out: &mut Vec<u8>) {
        for v in [self.n, self.r2, self.tau.x, self.tau.y, self.tau.z, self.direct.x, self.direct.y, self.direct.z] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }

    /// Read what `to_bytes` wrote (`b.len() == STATS_BYTES`); `None` for non-finite or negative values.
    pub fn from_bytes(b: &[u8]) -> Option<Self> {
        let f = |i: usize| f64::from_le_bytes(b[8 * i..8 * i + 8].try_into().unwrap_or_default());
        let s =
            PixelStats { n: f(0), r2: f(1), tau: DVec3::new(f(2), f(3), f(4)), direct: DVec3::new(f(5), f(6), f(7)) };
        let ok = s.n.is_finite()
            && s.n >= 0.0
            && s.r2.is_finite()
            && s.r2 >= 0.0
            && s.tau.is_finite()
            && s.direct.is_finite();
        ok.then_some(s)
    }
}
