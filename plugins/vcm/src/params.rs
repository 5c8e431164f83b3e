//! The `vcm` plugin's parameters, their defaults and their checks (each error names the parameter).

use prism_core::error::{PrismError, Result};
use serde::Deserialize;

/// Which strategies make up the estimator.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum VcmMode {
    /// Light tracing: light paths connected to the camera, plus emission the camera sees directly or through
    /// specular surfaces only.
    Light,
    /// Bidirectional path tracing: every connection of a camera vertex and a light vertex (light tracing and
    /// next-event estimation included), weighted by MIS.
    Bdpt,
    /// Bidirectional photon mapping: merging at every camera vertex, weighted by MIS.
    Bpm,
    /// Vertex connection and merging: both, weighted together.
    #[default]
    Vcm,
}

/// The MIS heuristic.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum Heuristic {
    /// The balance heuristic (weights proportional to the strategies' densities).
    #[default]
    Balance,
    /// The power heuristic with exponent 2.
    Power,
}

/// Most light paths per iteration accepted (each stores a few vertices of about 240 bytes).
pub const MAX_LIGHT_PATHS: u64 = 1 << 21;

/// Most path segments when `max_depth` is unlimited (Russian roulette ends paths long before; this bounds
/// specular loops).
pub const DEPTH_CAP: u32 = 256;

/// The `vcm` integrator's parameters.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct VcmParams {
    /// Which strategies.
    pub mode: VcmMode,
    /// Longest path in segments, as `envlight` counts them (the camera ray is segment 1): -1 unlimited.
    pub max_depth: i32,
    /// Merging radius in world units at the first iteration; by default `radius_pixels` pixel footprints at the
    /// median distance the camera sees.
    pub radius: Option<f32>,
    /// The default radius in pixel footprints (positive).
    pub radius_pixels: f32,
    /// Radius reduction: iteration `k` (from 0) merges within `radius (k + 1)^((alpha - 1) / 2)`, in (0, 1].
    pub alpha: f32,
    /// Light paths per iteration; default the image's pixel count.
    pub light_paths: Option<u64>,
    /// The MIS heuristic.
    pub heuristic: Heuristic,
}

impl Default for VcmParams {
    fn default() -> Self {
        VcmParams {
            mode: VcmMode::Vcm,
            max_depth: -1,
            radius: None,
            radius_pixels: 2.0,
            alpha: 2.0 / 3.0,
            light_paths: None,
            heuristic: Heuristic::Balance,
        }
    }
}

impl VcmParams {
    /// Most path segments, with the unlimited case capped.
    pub fn segments(&self) -> u32 {
        if self.max_depth < 0 { DEPTH_CAP } else { (self.max_depth as u32).min(DEPTH_CAP) }
    }

    /// Whether connections (light tracing, next-event estimation, camera-light vertex pairs) are used.
    pub fn connects(&self) -> bool {
        matches!(self.mode, VcmMode::Bdpt | VcmMode::Vcm)
    }

    /// Whether merging is used.
    pub fn merges(&self) -> bool {
        matches!(self.mode, VcmMode::Bpm | VcmMode::Vcm)
    }

    /// Check every parameter; the error names it.
    pub fn validate(&self) -> Result<()> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(PrismError::invalid(format!("vcm: alpha must be in (0, 1], got {}", self.alpha)));
        }
        if let Some(r) = self.radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(PrismError::invalid(format!("vcm: radius must be a positive number, got {r}")));
        }
        if !(self.radius_pixels.is_finite() && self.radius_pixels > 0.0) {
            return Err(PrismError::invalid(format!(
                "vcm: radius_pixels must be a positive number, got {}",
                self.radius_pixels
            )));
        }
        if let Some(n) = self.light_paths
            && !(1..=MAX_LIGHT_PATHS).contains(&n)
        {
            return Err(PrismError::invalid(format!("vcm: light_paths must be 1 to {MAX_LIGHT_PATHS}, got {n}")));
        }
        if self.max_depth == 0 || self.max_depth < -1 {
            return Err(PrismError::invalid(format!(
                "vcm: max_depth must be -1 (unlimited) or at least 1, got {}",
                self.max_depth
            )));
        }
        Ok(())
    }
}
