//! What a rough dielectric coat lets through to the base beneath it and reflects back down, as Mitsuba 3's
//! `roughplastic` precomputes them (`src/bsdfs/roughplastic.cpp`, `include/mitsuba/render/microfacet.h`):
//!
//! - `T(mu)`: the share of light arriving at cosine `mu` that the GGX interface of width `alpha` and relative index
//!   `eta` transmits, `int G1(wt, m) (1 - F(wi.m)) dD_v(m)` over the visible normals `m` of `wi` (`wt` the refracted
//!   direction), by a 32 x 32 Gauss-Legendre rule on the visible-normal sampler's square; tabulated at 64 evenly
//!   spaced `mu` in `[0, 1]` (the first at 1e-6) and interpolated linearly;
//! - `R_int = 2 int_0^1 R(mu) mu dmu`: the interface's reflectance from inside (index `1 / eta`) for light the
//!   diffuse base sends up, `R(mu)` by a 128 x 128 rule (total internal reflection makes it steep; 64 x 64 for the
//!   rows of a textured width), the integral as the mean over the same 64 `mu` (Mitsuba's rule, kept so the two
//!   agree to the last digit that matters).
//!
//! A table is built once per (`eta`, `alpha`) and kept for the process's life ([`RoughInterface::get`]): one row
//! for a constant `alpha`, and for a textured one 16 rows at `alpha = max(1e-3, (k / 15)^2)`, interpolated
//! linearly in `sqrt(alpha)`. The cells are computed in parallel: a constant width's row is 1.1 M microfacet
//! evaluations, a textured width's 16 rows 5.2 M.

use super::microfacet::{ggx_g1, sample_visible};
use crate::math::fresnel_dielectric;
use glam::{Vec2, Vec3A};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// Cosines at which `T` is tabulated.
const MU_RES: usize = 64;
/// Rows of a table for a textured `alpha`.
const ALPHA_ROWS: usize = 16;
/// The smallest coat width (the plastic lobe's clamp).
const MIN_ALPHA: f32 = 1e-3;

/// The tables built so far, by (`eta`, `alpha` or `None`) bits.
type Tables = HashMap<(u32, Option<u32>), &'static RoughInterface>;

/// `T(mu)` and `R_int` of one coat index for one `alpha` or a range of them.
#[derive(Debug, PartialEq)]
pub struct RoughInterface {
    /// The `alpha` of each row, increasing.
    alphas: Vec<f32>,
    /// `T` at the `MU_RES` cosines, row after row.
    t: Vec<f32>,
    /// `R_int` per row.
    r_int: Vec<f32>,
}

/// A table at one `alpha`: the row below it and the weight of the row above.
#[derive(Clone, Copy, Debug)]
pub struct InterfaceAt {
    table: &'static RoughInterface,
    row: u32,
    w: f32,
}

impl PartialEq for InterfaceAt {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.table, other.table) && self.row == other.row && self.w == other.w
    }
}

impl InterfaceAt {
    /// `T(mu)`, the coat's transmittance for light arriving at cosine `mu` (clamped to `[0, 1]`).
    #[inline]
    pub fn transmittance(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (MU_RES - 1) as f32;
        let i = (x as usize).min(MU_RES - 2);
        let f = x - i as f32;
        let row = |r: usize| {
            let t = &self.table.t[r * MU_RES..];
            t[i] + f * (t[i + 1] - t[i])
        };
        let r = self.row as usize;
        if self.w == 0.0 { row(r) } else { row(r) + self.w * (row(r + 1) - row(r)) }
    }

    /// `R_int`, the coat's reflectance from below for diffuse light.
    #[inline]
    pub fn internal_reflectance(&self) -> f32 {
        let r = self.row as usize;
        let ri = &self.table.r_int;
        if self.w == 0.0 { ri[r] } else { ri[r] + self.w * (ri[r + 1] - ri[r]) }
    }
}

impl RoughInterface {
    /// The table for index `eta` and a constant `alpha` (`Some`) or any `alpha` (`None`, for a textured width),
    /// built on first use and shared afterwards.
    pub fn get(eta: f32, alpha: Option<f32>) -> &'static RoughInterface {
        static CACHE: OnceLock<Mutex<Tables>> = OnceLock::new();
        let alpha = alpha.map(|a| a.clamp(MIN_ALPHA, 1.0));
        let key = (eta.to_bits(), alpha.map(f32::to_bits));
        let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
        if let Some(t) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
            return t;
        }
        let alphas = match alpha {
            Some(a) => vec![a],
            None => (0..ALPHA_ROWS).map(|k| ((k as f32 / (ALPHA_ROWS - 1) as f32).powi(2)).max(MIN_ALPHA)).collect(),
        };
        let table: &'static RoughInterface = Box::leak(Box::new(Self::build(eta, alphas)));
        cache.lock().unwrap_or_else(|e| e.into_inner()).entry(key).or_insert(table)
    }

    fn build(eta: f32, alphas: Vec<f32>) -> Self {
        use rayon::prelude::*;
        let (n32, w32) = gauss_legendre(32);
        // A constant width gets Mitsuba's 128 x 128 rule for R(mu); the rows of a textured width 64 x 64 (4 times
        // cheaper; R_int moves by less than 0.1%).
        let (nr, wr) = gauss_legendre(if alphas.len() == 1 { 128 } else { 64 });
        let mus: Vec<f32> = (0..MU_RES).map(|i| (i as f32 / (MU_RES - 1) as f32).max(1e-6)).collect();
        // (T(mu), R(mu) mu) for every (row, mu), in parallel: 16 rows are 5 M microfacet evaluations.
        let cells: Vec<(f32, f64)> = (0..alphas.len() * MU_RES)
            .into_par_iter()
            .map(|k| {
                let (alpha, mu) = (alphas[k / MU_RES], mus[k % MU_RES]);
                let wi = Vec3A::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
                let t = quadrature(&n32, &w32, |u| transmitted(wi, alpha, eta, u)) as f32;
                let r = quadrature(&nr, &wr, |u| reflected(wi, alpha, 1.0 / eta, u)) * mu as f64;
                (t, r)
            })
            .collect();
        let t = cells.iter().map(|c| c.0).collect();
        let r_int = cells
            .chunks(MU_RES)
            .map(|row| (2.0 * row.iter().map(|c| c.1).sum::<f64>() / MU_RES as f64) as f32)
            .collect();
        RoughInterface { alphas, t, r_int }
    }

    /// The table at `alpha` (clamped to the rows' range).
    #[inline]
    pub fn at(&'static self, alpha: f32) -> InterfaceAt {
        if self.alphas.len() == 1 {
            return InterfaceAt { table: self, row: 0, w: 0.0 };
        }
        let x = alpha.clamp(0.0, 1.0).sqrt() * (ALPHA_ROWS - 1) as f32;
        let x = if x.is_finite() { x } else { 0.0 };
        let row = (x as usize).min(ALPHA_ROWS - 2);
        // Rows below sqrt(MIN_ALPHA) * 15 hold MIN_ALPHA: the weight still interpolates in sqrt(alpha).
        InterfaceAt { table: self, row: row as u32, w: x - row as f32 }
    }
}

/// `G1(wt, m) (1 - F)` for the visible normal at `u`: the light of `wi` that refracts through facet `m` and escapes
/// the masking of the other facets.
fn transmitted(wi: Vec3A, alpha: f32, eta: f32, u: Vec2) -> f32 {
    let m = sample_visible(wi, alpha, u);
    let cos = wi.dot(m);
    let f = fresnel_dielectric(cos, eta);
    match crate::math::refract(wi, m, eta) {
        Some(wt) if wt.z * wi.z < 0.0 => ggx_g1(wt.normalize(), m, alpha) * (1.0 - f),
        _ => 0.0,
    }
}

/// `G1(wr, m) F` for the visible normal at `u`: the light of `wi` that facet `m` reflects out of the coat.
fn reflected(wi: Vec3A, alpha: f32, eta: f32, u: Vec2) -> f32 {
    let m = sample_visible(wi, alpha, u);
    let wr = 2.0 * wi.dot(m) * m - wi;
    if wr.z <= 0.0 {
        return 0.0;
    }
    ggx_g1(wr, m, alpha) * fresnel_dielectric(wi.dot(m), eta)
}

/// `int f` over `[0, 1]^2` by the tensor Gauss-Legendre rule of `nodes` and `weights` (on `[-1, 1]`).
fn quadrature(nodes: &[f64], weights: &[f64], f: impl Fn(Vec2) -> f32) -> f64 {
    let mut sum = 0.0f64;
    for (x, wx) in nodes.iter().zip(weights) {
        for (y, wy) in nodes.iter().zip(weights) {
            let u = Vec2::new((0.5 * x + 0.5) as f32, (0.5 * y + 0.5) as f32);
            sum += f(u) as f64 * wx * wy;
        }
    }
    0.25 * sum
}

/// The `n` nodes and weights of the Gauss-Legendre rule on `[-1, 1]` (Newton's iteration on `P_n`).
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut nodes, mut weights) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        nodes.push(x);
        weights.push(2.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}
