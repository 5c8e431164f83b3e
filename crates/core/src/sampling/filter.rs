//! Pixel reconstruction filters by filter importance sampling (Ernst et al. 2006): each camera sample's film
//! position is drawn from the normalised filter around its pixel's centre, and the pixel is the plain mean of its
//! own samples. That is the filtered image in expectation, keeps the film a mean (so passes, shards and resumes
//! merge exactly) and keeps every pixel independent of its neighbours' samples (deterministic per pixel).
//!
//! Filters, with the MIT 6.837 course's definitions and radii (in pixels):
//! - `Box(radius)`: weight 1 where `|x| <= r` and `|y| <= r` (r = 0.5 is the pixel itself, the default);
//! - `Tent(radius)`: radial, `max(0, 1 - d / r)`;
//! - `Gaussian(sigma)`: radial, `exp(-d^2 / (2 sigma^2))`, support radius `2 sigma`.
//!
//! The radial warps are exact inverses of the filters' radial cdfs (the tent's is the inverse smoothstep), so a
//! stratified unit square stays stratified on the filter.

use glam::Vec2;
use std::f32::consts::TAU;

/// The pixel reconstruction filter camera samples are drawn from (see the module notes).
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub enum PixelFilter {
    /// Weight 1 within the square of half-width `radius` around the pixel centre.
    Box {
        /// Half-width in pixels (default 0.5: the pixel itself).
        #[serde(default = "half")]
        radius: f32,
    },
    /// Radial `max(0, 1 - d / radius)`.
    Tent {
        /// Support radius in pixels (default 1).
        #[serde(default = "one")]
        radius: f32,
    },
    /// Radial `exp(-d^2 / (2 sigma^2))`, cut off at `d = 2 sigma`.
    Gaussian {
        /// Standard deviation in pixels (default 0.5).
        #[serde(default = "half")]
        sigma: f32,
    },
}

fn half() -> f32 {
    0.5
}
fn one() -> f32 {
    1.0
}

impl Default for PixelFilter {
    fn default() -> Self {
        PixelFilter::Box { radius: 0.5 }
    }
}

/// Largest accepted filter radius in pixels.
pub const MAX_FILTER_RADIUS: f32 = 64.0;

impl PixelFilter {
    /// The filter's name in scenes and on the command line: `box`, `tent` or `gaussian`.
    pub fn name(&self) -> &'static str {
        match self {
            PixelFilter::Box { .. } => "box",
            PixelFilter::Tent { .. } => "tent",
            PixelFilter::Gaussian { .. } => "gaussian",
        }
    }

    /// Radius of the filter's support in pixels.
    pub fn support(&self) -> f32 {
        match *self {
            PixelFilter::Box { radius } | PixelFilter::Tent { radius } => radius,
            PixelFilter::Gaussian { sigma } => 2.0 * sigma,
        }
    }

    /// The filter's parameter is positive, finite and at most [`MAX_FILTER_RADIUS`].
    pub fn validate(&self) -> Result<(), String> {
        let (what, v) = match *self {
            PixelFilter::Box { radius } => ("box filter radius", radius),
            PixelFilter::Tent { radius } => ("tent filter radius", radius),
            PixelFilter::Gaussian { sigma } => ("gaussian filter sigma", sigma),
        };
        if v.is_finite() && v > 0.0 && self.support() <= MAX_FILTER_RADIUS {
            Ok(())
        } else {
            Err(format!("{what} must be positive with a support of at most {MAX_FILTER_RADIUS} pixels, got {v}"))
        }
    }

    /// The (unnormalised) filter weight at an offset from the pixel centre.
    pub fn weight(&self, d: Vec2) -> f32 {
        match *self {
            PixelFilter::Box { radius } => (d.x.abs() <= radius && d.y.abs() <= radius) as u32 as f32,
            PixelFilter::Tent { radius } => (1.0 - d.length() / radius).max(0.0),
            PixelFilter::Gaussian { sigma } => {
                if d.length() <= 2.0 * sigma {
                    (-d.length_squared() / (2.0 * sigma * sigma)).exp()
                } else {
                    0.0
                }
            }
        }
    }

    /// The normalised filter at an offset from the pixel centre: the density (per square pixel) with which
    /// [`PixelFilter::warp`] places a camera sample there. Light tracing weights a splat by it.
    pub fn density(&self, d: Vec2) -> f32 {
        let integral = match *self {
            PixelFilter::Box { radius } => 4.0 * radius * radius,
            PixelFilter::Tent { radius } => std::f32::consts::PI * radius * radius / 3.0,
            PixelFilter::Gaussian { sigma } => TAU * sigma * sigma * (1.0 - (-2.0f32).exp()),
        };
        self.weight(d) / integral
    }

    /// The offset from the pixel centre of the sample `u` in [0,1)^2, distributed as the normalised filter.
    #[inline]
    pub fn warp(&self, u: Vec2) -> Vec2 {
        match *self {
            PixelFilter::Box { radius } => (2.0 * u - Vec2::ONE) * radius,
            PixelFilter::Tent { radius } => {
                // Radial density (1 - t) t on t = d / r in [0, 1]: cdf 3 t^2 - 2 t^3 (smoothstep), inverted.
                let t = 0.5 - ((1.0 - 2.0 * u.x).clamp(-1.0, 1.0).asin() / 3.0).sin();
                polar(t * radius, u.y)
            }
            PixelFilter::Gaussian { sigma } => {
                // Radial density exp(-d^2 / 2 s^2) d on [0, 2 s]: cdf (1 - exp(-d^2 / 2 s^2)) / (1 - exp(-2)).
                let tail = 1.0 - (-2.0f32).exp();
                let d = sigma * (-2.0 * (1.0 - u.x * tail).max(f32::MIN_POSITIVE).ln()).max(0.0).sqrt();
                polar(d.min(2.0 * sigma), u.y)
            }
        }
    }
}

#[inline]
fn polar(r: f32, v: f32) -> Vec2 {
    let phi = TAU * v;
    Vec2::new(r * phi.cos(), r * phi.sin())
}
