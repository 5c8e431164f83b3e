//! Sampling points on a curved surface (revolution, patch) by area, with the exact pdf, for area lights.
//!
//! The parameter square `[0,1]^2` (the surface's uv) is cut into `n x n` cells; a cell is chosen in proportion to
//! its approximate area (the area element `|dp/du x dp/dv|` averaged over 3 x 3 points of the cell, times the
//! cell's size), then a uniform point in the cell. The density in parameter space is therefore piecewise
//! constant and known exactly, `p(u, v) = P(cell) / cell size`, and the density by area on the surface is
//! `p(u, v) / |dp/du x dp/dv|` at the point: exact for the point actually sampled (no approximation enters the
//! pdf, only the choice of cells, which affects variance, not bias). `pdf` of a point hit by a ray uses the hit's
//! uv and its `dpdu`, `dpdv`, so sampling and pdf agree everywhere. The total area returned is the same
//! quadrature (used to weigh lights, never in a pdf).

use glam::Vec2;

/// Cells per parameter axis.
pub const CELLS: usize = 32;

#[derive(Clone, Debug)]
pub struct ParamAreaSampler {
    n: usize,
    /// Cumulative cell probabilities, row-major (v rows, u columns); the last is 1.
    cdf: Vec<f32>,
    prob: Vec<f32>,
    area: f32,
}

impl ParamAreaSampler {
    /// `area_element(u, v) = |dp/du x dp/dv|` in world units.
    pub fn new(area_element: impl Fn(f32, f32) -> f32) -> ParamAreaSampler {
        let n = CELLS;
        let h = 1.0 / n as f32;
        let mut weights = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                let mut sum = 0.0f64;
                for a in 0..3 {
                    for b in 0..3 {
                        let u = (j as f32 + (b as f32 + 0.5) / 3.0) * h;
                        let v = (i as f32 + (a as f32 + 0.5) / 3.0) * h;
                        let e = area_element(u, v);
                        sum += if e.is_finite() { e as f64 } else { 0.0 };
                    }
                }
                weights.push(sum / 9.0 * (h * h) as f64);
            }
        }
        let total: f64 = weights.iter().sum();
        // A surface of zero measured area still gets a valid (uniform) distribution.
        let (weights, total) = if total > 0.0 { (weights, total) } else { (vec![1.0; n * n], (n * n) as f64) };
        let mut acc = 0.0;
        let mut cdf = Vec::with_capacity(n * n);
        let mut prob = Vec::with_capacity(n * n);
        for w in &weights {
            acc += w;
            cdf.push((acc / total) as f32);
            prob.push((w / total) as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let area = if total > 0.0 { weights.iter().sum::<f64>() as f32 } else { 0.0 };
        ParamAreaSampler { n, cdf, prob, area }
    }

    /// Approximate total area (quadrature).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// A parameter point `(u, v)` and its density in parameter space.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let k = self.cdf.partition_point(|&c| c <= u.x).min(self.cdf.len() - 1);
        let lo = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let ux = ((u.x - lo) / (self.cdf[k] - lo).max(f32::MIN_POSITIVE)).clamp(0.0, 1.0 - f32::EPSILON);
        let (i, j) = (k / self.n, k % self.n);
        let h = 1.0 / self.n as f32;
        let p = Vec2::new((j as f32 + ux) * h, (i as f32 + u.y.clamp(0.0, 1.0 - f32::EPSILON)) * h);
        (p, self.prob[k] * (self.n * self.n) as f32)
    }

    /// Density in parameter space at `(u, v)`.
    pub fn pdf(&self, uv: Vec2) -> f32 {
        let c = |x: f32| ((x.clamp(0.0, 1.0) * self.n as f32) as usize).min(self.n - 1);
        self.prob[c(uv.y) * self.n + c(uv.x)] * (self.n * self.n) as f32
    }
}
