//! Which light next-event estimation samples at a path vertex: one light chosen in proportion to its estimated
//! power (area lights: pi A L, times 2 if two-sided; point: 4 pi I; directional and environment: the power they
//! send through the scene's bounding sphere), luminance of each. Slot `lights.len()` stands for the environment.

use crate::lights::{LightSet, LightSource};
use crate::math::luminance;
use crate::primitives::Primitives;
use std::f32::consts::PI;

pub struct LightChoice {
    cdf: Vec<f32>,
    prob: Vec<f32>,
}

impl LightChoice {
    pub fn new(lights: &LightSet, prims: &Primitives) -> Self {
        let r = 0.5 * prims.bounds.diagonal().length().max(1e-3);
        let mut power: Vec<f32> = lights
            .lights
            .iter()
            .map(|l| match l {
                LightSource::Area(a) => {
                    PI * a.area(prims) * luminance(a.radiance) * if a.two_sided { 2.0 } else { 1.0 }
                }
                LightSource::Point { intensity, .. } => 4.0 * PI * luminance(*intensity),
                LightSource::Directional { irradiance, .. } => PI * r * r * luminance(*irradiance),
            })
            .collect();
        if let Some(env) = &lights.environment {
            let avg = match &env.map {
                None => luminance(env.radiance),
                Some(m) => {
                    let mut sum = 0.0f64;
                    for (k, img) in m.images.iter().enumerate() {
                        for y in 0..img.height {
                            for x in 0..img.width {
                                sum += luminance(img.texel(x, y)) as f64 * m.texel_solid_angle(k, x, y) as f64;
                            }
                        }
                    }
                    (sum / (4.0 * std::f64::consts::PI)) as f32 * luminance(env.radiance)
                }
            };
            power.push(PI * PI * r * r * avg);
        }
        let total: f32 = power.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            power.iter_mut().for_each(|p| *p = 1.0);
        }
        let total: f32 = power.iter().sum();
        let prob: Vec<f32> = power.iter().map(|p| p / total).collect();
        let mut acc = 0.0;
        let cdf = prob
            .iter()
            .map(|p| {
                acc += p;
                acc
            })
            .collect();
        LightChoice { cdf, prob }
    }

    pub fn is_empty(&self) -> bool {
        self.prob.is_empty()
    }

    /// A light slot and its probability.
    #[inline]
    pub fn choose(&self, u: f32) -> (usize, f32) {
        let i = self.cdf.partition_point(|&c| c <= u).min(self.prob.len() - 1);
        (i, self.prob[i])
    }

    #[inline]
    pub fn prob(&self, slot: usize) -> f32 {
        self.prob[slot]
    }
}
