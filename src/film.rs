//! The film: per-pixel linear HDR radiance sums (f64) and sample counts, so any prefix of a progressive render is a
//! valid image, including a pass cut short by cancellation (each pixel is the mean of its own samples).

use crate::integrator::{PassOutput, TileSamples};
use glam::{DVec3, Vec3};

#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    sum: Vec<DVec3>,
    count: Vec<u64>,
    /// Samples replaced by 0 because they were NaN or infinite.
    pub nonfinite: u64,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Film { width, height, sum: vec![DVec3::ZERO; n], count: vec![0; n], nonfinite: 0 }
    }

    pub fn add_tile(&mut self, t: &TileSamples) {
        for y in 0..t.tile.h {
            for x in 0..t.tile.w {
                let i = ((t.tile.y0 + y) * self.width + t.tile.x0 + x) as usize;
                self.sum[i] += t.sums[(y * t.tile.w + x) as usize].as_dvec3();
                self.count[i] += t.spp as u64;
            }
        }
        self.nonfinite += t.nonfinite as u64;
    }

    /// Replace the content by a whole-image estimate (each pixel counts as one sample).
    pub fn set_estimate(&mut self, image: &[Vec3]) {
        for (i, v) in image.iter().enumerate() {
            let v = if v.is_finite() { *v } else { Vec3::ZERO };
            self.sum[i] = v.as_dvec3();
            self.count[i] = 1;
        }
    }

    pub fn merge(&mut self, out: &PassOutput) {
        match out {
            PassOutput::Samples(tiles) => tiles.iter().for_each(|t| self.add_tile(t)),
            PassOutput::Estimate { image, .. } => self.set_estimate(image),
        }
    }

    /// Mean radiance of a pixel (0 if it has no samples yet).
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        let i = (y * self.width + x) as usize;
        if self.count[i] == 0 { Vec3::ZERO } else { (self.sum[i] / self.count[i] as f64).as_vec3() }
    }

    /// The current image, row-major from the top-left pixel.
    pub fn image(&self) -> Vec<Vec3> {
        self.sum
            .iter()
            .zip(&self.count)
            .map(|(s, &c)| if c == 0 { Vec3::ZERO } else { (*s / c as f64).as_vec3() })
            .collect()
    }

    /// Fewest and most samples any pixel has (they differ after a pass cut short).
    pub fn sample_range(&self) -> (u64, u64) {
        let min = self.count.iter().copied().min().unwrap_or(0);
        let max = self.count.iter().copied().max().unwrap_or(0);
        (min, max)
    }
}
