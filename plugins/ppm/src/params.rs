//! The `ppm` plugin's parameters, their defaults and their checks (each error names the parameter).

use prism_core::error::{PrismError, Result};
use serde::Deserialize;

/// Which estimator.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum PpmMode {
    /// Stochastic progressive photon mapping (Hachisuka & Jensen 2009): a fresh eye pass every iteration.
    #[default]
    Stochastic,
    /// The original progressive photon mapping (Hachisuka, Ogaki & Jensen 2008): one eye pass through the pixel
    /// centres, fixed visible points, all light (direct included) from photons afterwards.
    Fixed,
}

/// How photons are found around a visible point.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum PhotonLookup {
    /// A uniform spatial hash over the photons, cell size tied to the current largest radius.
    #[default]
    HashGrid,
    /// A balanced kd-tree over the photons (the seed's photon map).
    Kdtree,
}

/// What the eye pass does at a glossy surface (smooth lobes, none diffuse: rough metal and glass).
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum GlossyEye {
    /// Trace on through it as a path tracer would (next-event estimation and BSDF sampling weighted by multiple
    /// importance sampling), and put the visible point on the next diffuse surface: a reflection in rough metal or
    /// glass stays as sharp as the BSDF makes it, and photons are not stored on glossy surfaces.
    #[default]
    Trace,
    /// Put the visible point on the glossy surface itself (the seed's behaviour): photons gathered over the radius
    /// blur what the surface reflects until the radius has shrunk.
    Gather,
}

/// Most photons per iteration accepted (each stored photon takes 64 bytes; a few are stored per emitted photon).
pub const MAX_PHOTONS: u64 = 1 << 24;

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct PpmParams {
    /// Radius reduction: the fraction of new photons a pixel keeps, in (0, 1].
    pub alpha: f32,
    /// Initial gather radius in world units; by default `radius_pixels` pixel footprints at each pixel's first
    /// visible point.
    pub radius: Option<f32>,
    /// Initial radius in pixel footprints when `radius` is not given (default 3).
    pub radius_pixels: f32,
    /// Photons emitted per iteration; default: the image's pixel count.
    pub photons: Option<u64>,
    /// Longest light path in segments, as Mitsuba and `envlight` count them (the camera ray is segment 1):
    /// -1 unlimited, 1 emitters only, 2 direct light only.
    pub max_depth: i32,
    /// Longest eye path to a visible point in segments (the camera ray is segment 1), on top of `max_depth`; -1: no
    /// limit of its own. pbrt's SPPM limits eye and photon paths separately (`maxdepth` each).
    pub eye_depth: i32,
    /// Longest photon path to a stored photon in segments (the emitted ray is segment 1), on top of `max_depth`; -1:
    /// no limit of its own.
    pub photon_depth: i32,
    pub mode: PpmMode,
    pub lookup: PhotonLookup,
    /// Glossy surfaces in the eye pass (stochastic mode; fixed mode always gathers on the first smooth surface).
    pub glossy: GlossyEye,
}

impl Default for PpmParams {
    fn default() -> Self {
        PpmParams {
            alpha: 0.7,
            radius: None,
            radius_pixels: 3.0,
            photons: None,
            max_depth: -1,
            eye_depth: -1,
            photon_depth: -1,
            mode: PpmMode::Stochastic,
            lookup: PhotonLookup::HashGrid,
            glossy: GlossyEye::Trace,
        }
    }
}

/// Most vertices an eye path or a photon path follows when `max_depth` is unlimited (Russian roulette ends photon
/// paths long before; this bounds specular loops).
pub const DEPTH_CAP: u32 = 256;

impl PpmParams {
    /// Most path segments, with the unlimited case capped.
    pub fn segments(&self) -> u32 {
        if self.max_depth < 0 { DEPTH_CAP } else { (self.max_depth as u32).min(DEPTH_CAP) }
    }

    /// Most eye path segments to a visible point (`eye_depth`, capped, and never more than `segments`).
    pub fn eye_segments(&self) -> u32 {
        let own = if self.eye_depth < 0 { DEPTH_CAP } else { (self.eye_depth as u32).min(DEPTH_CAP) };
        own.min(self.segments())
    }

    /// Most vertices a photon path follows: `photon_depth` segments (capped), and room in `segments` for the
    /// segment from the visible point to the camera.
    pub fn photon_vertices(&self) -> u32 {
        let own = if self.photon_depth < 0 { DEPTH_CAP } else { (self.photon_depth as u32).min(DEPTH_CAP) };
        own.min(self.segments().saturating_sub(1))
    }

    /// Whether eye paths trace on through glossy surfaces (stochastic mode with `glossy: trace`).
    pub fn traces_glossy(&self) -> bool {
        self.mode == PpmMode::Stochastic && self.glossy == GlossyEye::Trace
    }

    /// Check every parameter; the error names it.
    pub fn validate(&self) -> Result<()> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(PrismError::invalid(format!("ppm: alpha must be in (0, 1], got {}", self.alpha)));
        }
        if let Some(r) = self.radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(PrismError::invalid(format!("ppm: radius must be a positive number, got {r}")));
        }
        if !(self.radius_pixels.is_finite() && self.radius_pixels > 0.0) {
            return Err(PrismError::invalid(format!(
                "ppm: radius_pixels must be a positive number, got {}",
                self.radius_pixels
            )));
        }
        if let Some(n) = self.photons {
            if n == 0 {
                return Err(PrismError::invalid("ppm: photons must be at least 1"));
            }
            if n > MAX_PHOTONS {
                return Err(PrismError::invalid(format!(
                    "ppm: photons = {n} per iteration would need more than {} GiB of photon storage (at most {MAX_PHOTONS})",
                    (n * 64 * 3) >> 30
                )));
            }
        }
        for (name, v) in
            [("max_depth", self.max_depth), ("eye_depth", self.eye_depth), ("photon_depth", self.photon_depth)]
        {
            if v == 0 || v < -1 {
                return Err(PrismError::invalid(format!("ppm: {name} must be -1 (unlimited) or at least 1, got {v}")));
            }
        }
        Ok(())
    }
}
