//! Sampling points on a curved surface (revolution, patch) by area, with the exact pdf, for area lights.
//!
//! The parameter square `[0,1]^2` (the surface's uv) is cut into `n x n` cells; a cell is chosen in proportion to
//! its approximate area (the area element `|dp/du x dp/dv|` averaged over 3 x 3 points of the cell, times the
//! cell's size), then a uniform point in the cell. The choice is hierarchical (a row by the marginal distribution
//! with `u.y`, a column by the row's conditional distribution with `u.x`, each coordinate rescaled and reused for
//! the point in the cell), so stratified sample points stay stratified over the surface. The density in parameter space is therefore piecewise
//! constant and known exactly, `p(u, v) = P(cell) / cell size`, and the density by area on the surface is
//! `p(u, v) / |dp/du x dp/dv|` at the point: exact for the point actually sampled (no approximation enters the
//! pdf, only the choice of cells, which affects variance, not bias). `pdf` of a point hit by a ray uses the hit's
//! uv and its `dpdu`, `dpdv`, so sampling and pdf agree everywhere. The total area returned is the same
//! quadrature (used to weigh lights, never in a pdf).

use glam::Vec2;

/// Cells per parameter axis.
pub const CELLS: usize = 32;

/// Points of a parameter square drawn by approximate surface area, with their exact density (see the module
/// notes).
#[derive(Clone, Debug)]
pub struct ParamAreaSampler {
    n: usize,
    /// Cumulative row probabilities (the last is 1).
    row_cdf: Vec<f32>,
    /// Per row, the cumulative conditional probabilities of its cells (the last of each row is 1).
    col_cdf: Vec<f32>,
    /// Probability of each cell, row-major (v rows, u columns).
    prob: Vec<f32>,
    area: f32,
}

/// Index `k` of the bin of a cumulative distribution containing `x`, and `x` rescaled into that bin.
fn pick(cdf: &[f32], x: f32) -> (usize, f32) {
    let k = cdf.partition_point(|&c| c <= x).min(cdf.len() - 1);
    let lo = if k == 0 { 0.0 } else { cdf[k - 1] };
    let w = cdf[k] - lo;
    let r = if w > 0.0 { ((x - lo) / w).clamp(0.0, 1.0 - f32::EPSILON) } else { 0.5 };
    (k, r)
}

/// Normalised running sums of `w` (uniform when they sum to zero).
fn cumulative(w: &[f64]) -> Vec<f32> {
    let total: f64 = w.iter().sum();
    let mut acc = 0.0;
    let mut out: Vec<f32> = w
        .iter()
        .map(|x| {
            acc += if total > 0.0 { *x } else { 1.0 };
            (acc / if total > 0.0 { total } else { w.len() as f64 }) as f32
        })
        .collect();
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
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
        let w = if total > 0.0 { weights.clone() } else { vec![1.0; n * n] };
        let wt: f64 = w.iter().sum();
        let rows: Vec<f64> = w.chunks(n).map(|r| r.iter().sum()).collect();
        let row_cdf = cumulative(&rows);
        let col_cdf = w.chunks(n).flat_map(cumulative).collect();
        let prob = w.iter().map(|x| (x / wt) as f32).collect();
        ParamAreaSampler { n, row_cdf, col_cdf, prob, area: total as f32 }
    }

    /// Approximate total area (quadrature).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// A parameter point `(u, v)` and its density in parameter space.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (i, ry) = pick(&self.row_cdf, u.y);
        let (j, rx) = pick(&self.col_cdf[i * self.n..(i + 1) * self.n], u.x);
        let h = 1.0 / self.n as f32;
        let p = Vec2::new((j as f32 + rx) * h, (i as f32 + ry) * h);
        (p, self.pdf(p))
    }

    /// Density in parameter space at `(u, v)`.
    pub fn pdf(&self, uv: Vec2) -> f32 {
        let c = |x: f32| ((x.clamp(0.0, 1.0) * self.n as f32) as usize).min(self.n - 1);
        self.prob[c(uv.y) * self.n + c(uv.x)] * (self.n * self.n) as f32
    }
}
