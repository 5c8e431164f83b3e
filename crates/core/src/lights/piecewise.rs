//! The piecewise-constant 2D baseline (marginal/conditional inversion, as in pbrt-v3's `Distribution2D`): texel
//! weights are `luminance x Jacobian at the texel centre` (sin(theta) of the row centre for equirect), rows are
//! chosen by the marginal CDF and columns by the row's conditional CDF, both inverted continuously. Kept to
//! measure the quad-tree against (`envlight(env_sampling: piecewise)`).

use crate::envmap::EnvMap;
use crate::math::luminance;
use glam::{Vec2, Vec3A};

/// A 1D piecewise-constant distribution over `n` equal bins of [0, 1).
#[derive(Clone, Debug)]
struct Distribution1D {
    func: Vec<f64>,
    cdf: Vec<f64>,
    integral: f64,
}

impl Distribution1D {
    fn new(func: Vec<f64>) -> Self {
        let n = func.len();
        let mut cdf = vec![0.0; n + 1];
        for i in 0..n {
            cdf[i + 1] = cdf[i] + func[i] / n as f64;
        }
        let integral = cdf[n];
        if integral > 0.0 {
            cdf.iter_mut().for_each(|c| *c /= integral);
        }
        Distribution1D { func, cdf, integral }
    }

    /// Continuous sample in [0, 1) and the bin it fell in.
    fn sample(&self, u: f32) -> (f32, usize) {
        let u = u as f64;
        let i = self.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(self.func.len() - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let du = if width > 0.0 { (u - self.cdf[i]) / width } else { 0.0 };
        (((i as f64 + du) / self.func.len() as f64) as f32, i)
    }

    /// Density (w.r.t. [0,1)) of bin `i`.
    fn pdf(&self, i: usize) -> f64 {
        if self.integral > 0.0 { self.func[i] / self.integral } else { 0.0 }
    }
}

/// Piecewise-constant sampling of an environment map's texels by luminance times solid angle (see the module
/// notes).
#[derive(Clone, Debug)]
pub struct Piecewise2D {
    /// Per image: marginal over rows and one conditional per row.
    images: Vec<(Distribution1D, Vec<Distribution1D>)>,
    /// Image choice (6 cube faces) by total weight.
    image_choice: Distribution1D,
}

impl Piecewise2D {
    /// The distribution over `map`'s texels; `None` when the map is black.
    pub fn build(map: &EnvMap) -> Option<Piecewise2D> {
        let mut images = vec![];
        let mut totals = vec![];
        for img in &map.images {
            let rows: Vec<Distribution1D> = (0..img.height)
                .map(|y| {
                    Distribution1D::new(
                        (0..img.width)
                            .map(|x| {
                                let uv = Vec2::new(
                                    (x as f32 + 0.5) / img.width as f32,
                                    (y as f32 + 0.5) / img.height as f32,
                                );
                                luminance(img.texel(x, y)).max(0.0) as f64 * map.jacobian(uv) as f64
                            })
                            .collect(),
                    )
                })
                .collect();
            let marginal = Distribution1D::new(rows.iter().map(|r| r.integral).collect());
            totals.push(marginal.integral);
            images.push((marginal, rows));
        }
        let image_choice = Distribution1D::new(totals);
        (image_choice.integral > 0.0).then_some(Piecewise2D { images, image_choice })
    }

    /// A unit direction in the map's frame and its solid-angle pdf, from `u` in the unit square; `None` where the
    /// pdf comes out zero or not finite (a direction on a singular row of the panorama).
    pub fn sample(&self, map: &EnvMap, u: Vec2) -> Option<(Vec3A, f32)> {
        let n = self.images.len();
        let (uk, k) = self.image_choice.sample(u.x);
        let ux = (uk * n as f32 - k as f32).clamp(0.0, 1.0 - f32::EPSILON);
        let (marginal, rows) = &self.images[k];
        let (v, row) = marginal.sample(u.y);
        let (uu, col) = rows[row].sample(ux);
        let uv = Vec2::new(uu, v);
        let pdf_uv = marginal.pdf(row) * rows[row].pdf(col) * self.image_choice.pdf(k) / n as f64;
        let j = map.jacobian(uv);
        let pdf = (pdf_uv / j as f64) as f32;
        (pdf > 0.0 && pdf.is_finite()).then(|| (map.direction(k, uv), pdf))
    }

    /// Solid-angle pdf with which [`Piecewise2D::sample`] draws the unit direction `dir` (map's frame).
    pub fn pdf(&self, map: &EnvMap, dir: Vec3A) -> f32 {
        let (k, uv) = map.coords(dir);
        let n = self.images.len();
        let (marginal, rows) = &self.images[k];
        let h = rows.len();
        let w = rows[0].func.len();
        let row = ((uv.y * h as f32) as usize).min(h - 1);
        let col = ((uv.x * w as f32) as usize).min(w - 1);
        let pdf_uv = marginal.pdf(row) * rows[row].pdf(col) * self.image_choice.pdf(k) / n as f64;
        let j = map.jacobian(uv);
        if j <= 0.0 { 0.0 } else { (pdf_uv / j as f64) as f32 }
    }
}
