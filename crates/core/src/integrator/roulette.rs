//! Russian roulette for path tracers: when a path ends early, and what its survivors carry.
//!
//! A path that survives with probability `q` has its throughput divided by `q`, so the estimate stays unbiased
//! whatever `q` is; `q` only trades time (shorter paths) against variance (the survivors' larger weights). The rule
//! here is a **throughput threshold**: a path survives for sure while its throughput `max(beta) eta^2` (the
//! radiance scaling `1/eta^2` of the refractions so far undone, as in Mitsuba, so a path inside glass is not a
//! dimmer path) is at least `threshold`, and with probability `max(beta) eta^2 / threshold` below it. Dim paths
//! end early, where they cost as much as bright ones but carry little; bright paths are never cut, which is where
//! roulette's extra weight becomes variance.
//!
//! Parameters (`envlight`): `rr_depth`, the first path segment after which roulette is played, and `rr_threshold`.
//! Mitsuba's rule is `threshold = 1` with survival capped at 0.95 from `rr_depth = 5` on. Prism's defaults are
//! `rr_depth = 1` and `threshold = 0.5`; `docs/decisions/0016-russian-roulette-threshold.md` gives the measurements
//! behind them. So that every path ends even in a lossless scene with unlimited depth (mirrors, clear glass, white
//! walls), survival is capped at [`LONG_PATH_SURVIVAL`] from segment [`LONG_PATH_SEGMENTS`] on.
//!
//! [`mitsuba_survival`] is Mitsuba's rule itself, which `ppm`'s eye paths through glossy surfaces keep.

use glam::Vec3;

/// From this many path segments on, survival is capped at [`LONG_PATH_SURVIVAL`].
pub const LONG_PATH_SEGMENTS: i32 = 64;

/// The cap on survival of paths of [`LONG_PATH_SEGMENTS`] or more: a path that keeps its throughput forever still
/// ends after `1 / (1 - 0.95) = 20` further segments on average.
pub const LONG_PATH_SURVIVAL: f32 = 0.95;

/// The default throughput below which roulette is played (`envlight`'s `rr_threshold`).
pub const DEFAULT_THRESHOLD: f32 = 0.5;

/// Survival probability of a path after `segments` path segments with throughput `beta` and radiance scaling
/// `eta2` (the product of `eta^2` over its refractions), under threshold `threshold` (`> 0`, finite). In `(0, 1]`
/// for a positive throughput; the caller divides the throughput of a survivor by it.
#[inline(always)]
pub fn survival(beta: Vec3, eta2: f32, threshold: f32, segments: i32) -> f32 {
    let q = beta.max_element() * eta2 / threshold;
    let cap = if segments >= LONG_PATH_SEGMENTS { LONG_PATH_SURVIVAL } else { 1.0 };
    q.min(cap)
}

/// Mitsuba's rule: survival `min(max(beta) eta^2, 0.95)` (threshold 1, capped at every roulette). `ppm`'s eye paths
/// through glossy surfaces use it; `envlight` uses [`survival`].
#[inline(always)]
pub fn mitsuba_survival(beta: Vec3, eta2: f32) -> f32 {
    (beta.max_element() * eta2).min(LONG_PATH_SURVIVAL)
}
