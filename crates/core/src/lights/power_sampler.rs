//! Which light a sample goes to: one light chosen in proportion to the luminance of its power (`LightSet::power`:
//! area lights `pi A L` (x2 two-sided), point `4 pi I`, spot its cone integral, directional and environment the
//! power they send through the scene's bounding disk). Slot `lights.len()` stands for the environment. If every
//! power is zero or not finite, lights are chosen uniformly (so a dark light never makes a NaN).

use crate::lights::LightSet;
use crate::math::luminance;
use crate::primitives::Primitives;

/// The choice of a light slot in proportion to the luminance of its power.
#[derive(Clone, Debug)]
pub struct PowerLightSampler {
    cdf: Vec<f32>,
    prob: Vec<f32>,
    /// False when every light's power is zero (the choice is then uniform, and nothing is emitted).
    pub has_power: bool,
}

impl PowerLightSampler {
    /// The distribution over the slots of `lights` (the environment, if any, last).
    pub fn new(lights: &LightSet, prims: &Primitives) -> Self {
        let slots = lights.len() + lights.environment.is_some() as usize;
        let mut power: Vec<f64> = (0..slots).map(|i| luminance(lights.power(i, prims)).max(0.0) as f64).collect();
        let total: f64 = power.iter().sum();
        let has_power = total > 0.0 && total.is_finite();
        if !has_power {
            power.iter_mut().for_each(|p| *p = 1.0);
        }
        let total: f64 = power.iter().sum();
        let prob: Vec<f32> = power.iter().map(|p| (p / total) as f32).collect();
        let mut acc = 0.0f64;
        let mut cdf: Vec<f32> = power
            .iter()
            .map(|p| {
                acc += p / total;
                acc as f32
            })
            .collect();
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        PowerLightSampler { cdf, prob, has_power }
    }

    /// Number of slots (lights plus the environment).
    pub fn len(&self) -> usize {
        self.prob.len()
    }

    /// True when there is no slot: no light and no environment.
    pub fn is_empty(&self) -> bool {
        self.prob.is_empty()
    }

    /// A light slot and its probability (call only when not empty).
    #[inline]
    pub fn choose(&self, u: f32) -> (usize, f32) {
        let i = self.cdf.partition_point(|&c| c <= u).min(self.prob.len() - 1);
        (i, self.prob[i])
    }

    /// A light slot, its probability, and `u` rescaled to [0, 1) within the slot's interval (for reuse).
    #[inline]
    pub fn choose_remapped(&self, u: f32) -> (usize, f32, f32) {
        let (i, p) = self.choose(u);
        let lo = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let r = if p > 0.0 { ((u - lo) / p).clamp(0.0, 1.0 - f32::EPSILON) } else { 0.0 };
        (i, p, r)
    }

    /// The probability of choosing `slot` (`slot < len()`).
    #[inline]
    pub fn prob(&self, slot: usize) -> f32 {
        self.prob[slot]
    }
}
