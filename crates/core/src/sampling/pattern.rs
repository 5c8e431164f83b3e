//! Where the camera samples of a pixel fall inside it (box filter: every sample weighs the same).
//!
//! - `Random`: independent uniform positions.
//! - `Stratified`: the pixel cut into n x n strata (n = ceil(sqrt(k)) for k samples in the pass), one jittered
//!   sample per stratum chosen in random order, so any sample count stays unbiased.
//! - `Uniform`: the 6.837 course's regular grid: sample i of k at the centre of cell i of an n x n grid
//!   (n = ceil(sqrt(k))), no randomness (a deterministic quadrature, biased like the course's).
//! - `Rgss`: the 4-sample rotated grid (offsets 1/8, 3/8, 5/8, 7/8 on both axes, no two sharing a row or column);
//!   each group of 4 samples gets its own random toroidal shift (Cranley–Patterson rotation), which keeps the
//!   rotated-grid structure and makes the estimate unbiased when passes are averaged.

use super::{Rng, hash_u64, permute, stratified_2d};
use glam::Vec2;

/// How the independent sampler places a pixel's camera samples (see the module notes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PixelPattern {
    /// Independent uniform positions.
    Random,
    /// One jittered sample per stratum of an n x n grid, strata in random order (the default).
    #[default]
    Stratified,
    /// The 6.837 course's regular grid of cell centres, no randomness.
    Uniform,
    /// The 4-sample rotated grid, each group of four shifted at random.
    Rgss,
}

const RGSS: [Vec2; 4] =
    [Vec2::new(0.125, 0.625), Vec2::new(0.375, 0.125), Vec2::new(0.625, 0.875), Vec2::new(0.875, 0.375)];

impl PixelPattern {
    /// The pattern of a name: `random` (or `independent`), `stratified` (or `jitter`), `uniform`, `rgss`; `None`
    /// for any other.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "random" | "independent" => Some(Self::Random),
            "stratified" | "jitter" => Some(Self::Stratified),
            "uniform" => Some(Self::Uniform),
            "rgss" => Some(Self::Rgss),
            _ => None,
        }
    }

    /// The pattern's canonical name (what [`PixelPattern::parse`] reads back).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Random => "random",
            Self::Stratified => "stratified",
            Self::Uniform => "uniform",
            Self::Rgss => "rgss",
        }
    }

    /// Position in `[0,1)^2` of sample `i` of `count` samples of one pixel in one pass. `scramble` is a per-pixel
    /// random key drawn once per pass.
    #[inline]
    pub fn offset(&self, i: u32, count: u32, scramble: u32, rng: &mut Rng) -> Vec2 {
        match self {
            Self::Random => rng.next_2d(),
            Self::Stratified => stratified_2d(i, count, scramble, rng),
            Self::Uniform => {
                let n = ((count as f32).sqrt().ceil().max(1.0) as u32).min(65535);
                let cell = i % (n * n);
                Vec2::new(((cell % n) as f32 + 0.5) / n as f32, ((cell / n) as f32 + 0.5) / n as f32)
            }
            Self::Rgss => {
                let group = i / 4;
                let in_group = count.saturating_sub(group * 4).min(4);
                // A partial last group takes a random subset of the 4 points; each stays uniform once shifted.
                let k = if in_group == 4 { i % 4 } else { permute(i % 4, 4, scramble ^ group) };
                // One shift per group, derived from the pixel's key so all 4 samples of the group share it.
                let h = hash_u64(((scramble as u64) << 32) | group as u64);
                let shift = Vec2::new(
                    (h >> 40) as f32 * (1.0 / 16_777_216.0),
                    ((h >> 8) & 0xFF_FFFF) as f32 * (1.0 / 16_777_216.0),
                );
                let p = RGSS[k as usize] + shift;
                Vec2::new(p.x.fract(), p.y.fract())
            }
        }
    }
}
