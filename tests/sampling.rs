//! Samplers against their own pdfs (chi-square goodness of fit on the sphere), light sampling against the light's
//! `pdf` (what multiple importance sampling relies on), and pixel patterns (uniform coverage, stratification).

use crate::common::{app_from_ron, chi_square};
use glam::{Vec2, Vec3A};
use prism::math::Frame;
use prism::sampling::{PixelPattern, Rng, permute, stratified_2d, warp};
use prism::settings::Overrides;
use std::f64::consts::PI;

const THETA_BINS: usize = 20;
const PHI_BINS: usize = 40;

/// How directions are binned: equal-area (cos theta, phi) cells over the cap `cos theta >= zmin` around `frame.n`,
/// each integrated on a `sub x sub` grid for the expected counts. Lights use a cap hugging the light so most
/// cells lie inside it and the silhouette cells are integrated finely.
pub(crate) struct Binning {
    pub(crate) frame: Frame,
    pub(crate) zmin: f64,
    pub(crate) sub: usize,
}

impl Binning {
    pub(crate) fn sphere() -> Self {
        Binning { frame: Frame::from_normal(Vec3A::Z), zmin: -1.0, sub: 12 }
    }

    fn bin(&self, d: Vec3A) -> Option<usize> {
        let l = self.frame.to_local(d);
        let z = (l.z as f64).clamp(-1.0, 1.0);
        if z < self.zmin {
            return None;
        }
        let ti = (((z - self.zmin) / (1.0 - self.zmin) * THETA_BINS as f64) as usize).min(THETA_BINS - 1);
        let phi = (l.y as f64).atan2(l.x as f64).rem_euclid(2.0 * PI);
        let pi = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
        Some(ti * PHI_BINS + pi)
    }

    /// Expected counts per bin for `n` samples from a solid-angle pdf.
    fn expected(&self, pdf: &dyn Fn(Vec3A) -> f64, n: usize) -> Vec<f64> {
        let sub = self.sub;
        let span = 1.0 - self.zmin;
        let cell = 2.0 * PI * span / (THETA_BINS * PHI_BINS) as f64 / (sub * sub) as f64;
        let mut out = vec![0.0; THETA_BINS * PHI_BINS];
        for ti in 0..THETA_BINS {
            for pi in 0..PHI_BINS {
                let mut acc = 0.0;
                for a in 0..sub {
                    for b in 0..sub {
                        let z = self.zmin + span * (ti as f64 + (a as f64 + 0.5) / sub as f64) / THETA_BINS as f64;
                        let phi = 2.0 * PI * (pi as f64 + (b as f64 + 0.5) / sub as f64) / PHI_BINS as f64;
                        let r = (1.0 - z * z).max(0.0).sqrt();
                        let local = Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                        acc += pdf(self.frame.to_world(local)) * cell;
                    }
                }
                out[ti * PHI_BINS + pi] = acc * n as f64;
            }
        }
        out
    }
}

/// Chi-square test of `n` samples from `sample` against `pdf`; also checks that the pdf integrates to 1.
fn check_sampler(name: &str, sample: &mut dyn FnMut(Vec2) -> Option<Vec3A>, pdf: &dyn Fn(Vec3A) -> f64, n: usize) {
    check_sampler_with(name, sample, pdf, n, true, &Binning::sphere())
}

/// As [`check_sampler`]; `normalized` false for samplers that may return no sample (one-sided lights), whose pdf
/// integrates to the acceptance probability.
pub(crate) fn check_sampler_with(
    name: &str,
    sample: &mut dyn FnMut(Vec2) -> Option<Vec3A>,
    pdf: &dyn Fn(Vec3A) -> f64,
    n: usize,
    normalized: bool,
    binning: &Binning,
) {
    let mut rng = Rng::new(0x5eed, name.len() as u64);
    let mut observed = vec![0.0; THETA_BINS * PHI_BINS];
    for _ in 0..n {
        if let Some(d) = sample(rng.next_2d()) {
            let b = binning.bin(d).unwrap_or_else(|| panic!("{name}: sample {d:?} outside the binned cap"));
            observed[b] += 1.0;
        }
    }
    let exp = binning.expected(pdf, n);
    let total: f64 = exp.iter().sum::<f64>() / n as f64;
    // The midpoint rule over cells cut by a light's silhouette is the only integration error (~1e-3 for lights).
    let tol = if binning.zmin > -1.0 { 5e-3 } else { 2e-3 };
    if normalized {
        assert!((total - 1.0).abs() < tol, "{name}: pdf integrates to {total}, not 1");
    }
    let (stat, df, p) = chi_square(&observed, &exp);
    assert!(p > 1e-3, "{name}: chi-square {stat:.1} with {df} dof, p = {p:.2e}: samples do not follow pdf()");
}

#[test]
fn uniform_sphere_sampling_follows_its_pdf() {
    check_sampler(
        "uniform_sphere",
        &mut |u| Some(warp::uniform_sphere(u)),
        &|_| warp::uniform_sphere_pdf() as f64,
        200_000,
    );
}

#[test]
fn cosine_hemisphere_sampling_follows_cos_over_pi() {
    check_sampler(
        "cosine_hemisphere",
        &mut |u| Some(warp::cosine_hemisphere(u)),
        &|d| warp::cosine_hemisphere_pdf(d) as f64,
        200_000,
    );
}

#[test]
fn uniform_hemisphere_sampling_follows_its_pdf() {
    check_sampler(
        "uniform_hemisphere",
        &mut |u| Some(warp::uniform_hemisphere(u)),
        &|d| warp::uniform_hemisphere_pdf(d) as f64,
        200_000,
    );
}

#[test]
fn phong_lobe_sampling_follows_normalised_cos_power_in_a_tilted_frame() {
    for exponent in [1.0f32, 10.0, 60.0] {
        let axis = Vec3A::new(0.3, -0.5, 0.81).normalize();
        let f = Frame::from_normal(axis);
        check_sampler(
            &format!("phong_lobe_{exponent}"),
            &mut |u| Some(f.to_world(warp::phong_lobe(u, exponent))),
            &|d| warp::phong_lobe_pdf(f.to_local(d), exponent) as f64,
            200_000,
        );
    }
}

#[test]
fn cone_sampling_follows_its_pdf() {
    let cos_max = 0.7f32;
    check_sampler(
        "cone",
        &mut |u| Some(warp::uniform_cone(u, cos_max)),
        &|d| if d.z >= cos_max { warp::uniform_cone_pdf(cos_max) as f64 } else { 0.0 },
        200_000,
    );
}

#[test]
fn triangle_sampling_is_uniform_in_area() {
    // Histogram of barycentric positions over a 2D grid of the reference triangle: uniform density 2.
    let mut rng = Rng::new(3, 4);
    let n = 200_000;
    let g = 20;
    let mut obs = vec![0.0; g * g];
    for _ in 0..n {
        let (_, b1, b2) = warp::uniform_triangle(rng.next_2d());
        assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6);
        obs[((b1 * g as f32) as usize).min(g - 1) * g + ((b2 * g as f32) as usize).min(g - 1)] += 1.0;
    }
    // Expected: area of each grid cell inside the triangle b1 + b2 <= 1, times density 2.
    let mut exp = vec![0.0; g * g];
    let sub = 16;
    for i in 0..g {
        for j in 0..g {
            let mut inside = 0;
            for a in 0..sub {
                for b in 0..sub {
                    let x = (i as f64 + (a as f64 + 0.5) / sub as f64) / g as f64;
                    let y = (j as f64 + (b as f64 + 0.5) / sub as f64) / g as f64;
                    inside += (x + y <= 1.0) as u32;
                }
            }
            exp[i * g + j] = n as f64 * 2.0 * inside as f64 / (sub * sub) as f64 / (g * g) as f64;
        }
    }
    let (stat, df, p) = chi_square(&obs, &exp);
    assert!(p > 1e-3, "chi-square {stat:.1} ({df} dof), p = {p:.2e}");
}

/// Light sampling from a reference point against `LightSet::pdf` of the direction (traced to the light).
fn check_light_sampling(scene_ron: &str, p: Vec3A, name: &str, all_visible: bool) {
    let mut app = app_from_ron(scene_ron, Overrides::default());
    app.setup().unwrap();
    let scene = app.resources.scene.as_ref().unwrap();
    let lights = &scene.lights;
    // Bin over the cap around the light's bounds as seen from p.
    let b = scene.prims.bounds;
    let axis = (b.center() - p).normalize();
    let corners = (0..8).map(|i| {
        Vec3A::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    });
    let zmin = corners.map(|c| (c - p).normalize().dot(axis) as f64).fold(1.0, f64::min) - 0.01;
    let binning = Binning { frame: Frame::from_normal(axis), zmin: zmin.max(-1.0), sub: 24 };
    let mut rejected = 0usize;
    let n = 200_000;
    check_sampler_with(
        name,
        &mut |u| match lights.sample_li(0, &scene.prims, p, u) {
            Some(ls) => {
                // The pdf the sample reports must equal pdf() for the same point.
                let hit = scene.trace(&prism::geometry::Ray::new(p, ls.wi)).expect("sampled direction hits the light");
                let pdf2 = lights.pdf_li(0, &scene.prims, p, &hit);
                assert!((ls.pdf - pdf2).abs() <= 2e-3 * ls.pdf, "{name}: sample pdf {} vs pdf() {pdf2}", ls.pdf);
                Some(ls.wi)
            }
            None => {
                rejected += 1;
                None
            }
        },
        &|d| match scene.trace(&prism::geometry::Ray::new(p, d)) {
            Some(hit) if hit.light == 0 => lights.pdf_li(0, &scene.prims, p, &hit) as f64,
            _ => 0.0,
        },
        n,
        all_visible,
        &binning,
    );
    if all_visible {
        assert_eq!(rejected, 0, "{name}: samples from the lit side were rejected");
    }
}

#[test]
fn area_light_sampling_of_a_quad_matches_its_pdf() {
    let scene = r#"(camera: (), entities: [
        (shape: Quad(), light: Area(radiance: (1, 1, 1)), transform: [Translate((0.2, 0, 1)), Scale((0.8, 0.5, 1))]),
    ])"#;
    check_light_sampling(scene, Vec3A::new(0.1, 0.1, 2.0), "quad light", true);
}

#[test]
fn area_light_sampling_of_a_triangle_mesh_matches_its_pdf() {
    // A cube light of unequal faces (non-uniform scale) seen from outside: area-weighted triangle choice.
    let scene = r#"(camera: (), entities: [
        (shape: Cube, light: Area(radiance: (1, 1, 1)), transform: [Rotate(axis: (1, 1, 0), degrees: 30), Scale((0.5, 0.2, 0.3))]),
    ])"#;
    check_light_sampling(scene, Vec3A::new(0.4, 0.9, 0.7), "cube light", false);
}

#[test]
fn sphere_light_cone_sampling_matches_its_pdf() {
    let scene = r#"(camera: (), entities: [
        (shape: Sphere(center: (0, 0, 2), radius: 0.7), light: Area(radiance: (1, 1, 1))),
    ])"#;
    check_light_sampling(scene, Vec3A::new(0.2, 0.0, 0.0), "sphere light", true);
}

#[test]
fn ellipsoid_light_sampling_matches_its_pdf() {
    let scene = r#"(camera: (), entities: [
        (shape: Sphere(radius: 0.5), light: Area(radiance: (1, 1, 1)), transform: [Translate((0, 0, 2)), Scale((1.5, 0.6, 1))]),
    ])"#;
    // One-sided: only the visible half of the ellipsoid's samples carry light; the others are rejected.
    let mut app = app_from_ron(scene, Overrides::default());
    app.setup().unwrap();
    let s = app.resources.scene.as_ref().unwrap();
    let p = Vec3A::new(0.1, 0.2, 0.0);
    let mut rng = Rng::new(1, 2);
    // Monte Carlo estimate of the subtended solid angle, sum of 1/pdf over accepted samples / N, against a
    // brute-force count of directions hitting the ellipsoid.
    let n = 400_000;
    let mut est = 0.0f64;
    for _ in 0..n {
        if let Some(ls) = s.lights.sample_li(0, &s.prims, p, rng.next_2d()) {
            est += 1.0 / ls.pdf as f64;
        }
    }
    est /= n as f64;
    let mut hits = 0usize;
    for _ in 0..n {
        let d = warp::uniform_sphere(rng.next_2d());
        hits += s.trace(&prism::geometry::Ray::new(p, d)).is_some() as usize;
    }
    let omega = hits as f64 / n as f64 * 4.0 * PI;
    assert!((est - omega).abs() < 0.02 * omega, "solid angle by light sampling {est:.4} vs by counting {omega:.4}");
}

#[test]
fn stratified_points_cover_every_stratum_once_for_square_counts() {
    for n in [1u32, 4, 16, 64] {
        let k = (n as f32).sqrt() as u32;
        let mut rng = Rng::new(9, n as u64);
        let mut seen = vec![0; n as usize];
        for i in 0..n {
            let u = stratified_2d(i, n, 1234, &mut rng);
            assert!(u.x >= 0.0 && u.x < 1.0 && u.y >= 0.0 && u.y < 1.0);
            seen[((u.y * k as f32) as usize) * k as usize + (u.x * k as f32) as usize] += 1;
        }
        assert!(seen.iter().all(|&c| c == 1), "n = {n}: strata {seen:?}");
    }
}

#[test]
fn permutation_is_a_bijection() {
    for len in [1u32, 2, 3, 7, 16, 100, 1000] {
        for key in [0u32, 1, 0xdeadbeef] {
            let mut seen = vec![false; len as usize];
            for i in 0..len {
                let p = permute(i, len, key) as usize;
                assert!(!seen[p], "len {len} key {key}: {p} repeated");
                seen[p] = true;
            }
        }
    }
}

#[test]
fn every_pixel_pattern_is_uniform_over_the_pixel() {
    // The box filter integral needs each sample uniform on the pixel: mean 0.5 and variance 1/12 per axis, over many
    // pixels (keys), for sample counts that are and are not multiples of the pattern size.
    for pattern in [PixelPattern::Random, PixelPattern::Stratified, PixelPattern::Rgss] {
        for count in [1u32, 3, 4, 9, 10] {
            let mut rng = Rng::new(42, count as u64);
            let (mut sx, mut sxx, mut n) = (0.0f64, 0.0f64, 0.0f64);
            let mut grid = [0.0f64; 16];
            for key in 0..20_000u32 {
                let k = key.wrapping_mul(0x9E3779B9);
                for i in 0..count {
                    let o = pattern.offset(i, count, k, &mut rng);
                    assert!((0.0..1.0).contains(&o.x) && (0.0..1.0).contains(&o.y));
                    sx += o.x as f64;
                    sxx += (o.x as f64) * (o.x as f64);
                    n += 1.0;
                    grid[((o.y * 4.0) as usize) * 4 + (o.x * 4.0) as usize] += 1.0;
                }
            }
            let mean = sx / n;
            let var = sxx / n - mean * mean;
            assert!((mean - 0.5).abs() < 0.005, "{pattern:?} x{count}: mean {mean}");
            assert!((var - 1.0 / 12.0).abs() < 0.003, "{pattern:?} x{count}: variance {var}");
            let exp = vec![n / 16.0; 16];
            let (stat, _, p) = chi_square(&grid, &exp);
            assert!(p > 1e-4, "{pattern:?} x{count}: 4x4 histogram chi-square {stat:.1}, p = {p:.2e}");
        }
    }
}

#[test]
fn rgss_puts_four_samples_in_distinct_rows_and_columns() {
    let mut rng = Rng::new(0, 0);
    let pts: Vec<Vec2> = (0..4).map(|i| PixelPattern::Rgss.offset(i, 4, 77, &mut rng)).collect();
    // Undo the common toroidal shift by looking at pairwise differences: all 4 x and 4 y offsets are distinct
    // quarters (1/8, 3/8, 5/8, 7/8 shifted together).
    let mut xs: Vec<f32> = pts.iter().map(|p| ((p.x - pts[0].x).rem_euclid(1.0) * 4.0).round() % 4.0).collect();
    let mut ys: Vec<f32> = pts.iter().map(|p| ((p.y - pts[0].y).rem_euclid(1.0) * 4.0).round() % 4.0).collect();
    xs.sort_by(f32::total_cmp);
    ys.sort_by(f32::total_cmp);
    assert_eq!(xs, vec![0.0, 1.0, 2.0, 3.0]);
    assert_eq!(ys, vec![0.0, 1.0, 2.0, 3.0]);
}

#[test]
fn bsdf_sampling_of_a_diffuse_plus_phong_mixture_follows_its_pdf() {
    use prism::bsdf::{Bsdf, Lobe};
    let wo = Vec3A::new(0.64, 0.0, 0.77).normalize();
    let lobes =
        [Lobe::Diffuse { albedo: glam::Vec3::splat(0.3) }, Lobe::Phong { ks: glam::Vec3::splat(0.5), exponent: 20.0 }];
    let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &lobes).unwrap();
    let mut rng = Rng::new(8, 8);
    let mut sample = |u: Vec2| {
        let s = bsdf.sample(rng.next_f32(), u)?;
        assert!(!s.delta);
        // The weight is f |cos| / pdf of the same direction.
        let expect = bsdf.eval(s.wi) * s.wi.z / bsdf.pdf(s.wi);
        assert!((s.weight - expect).abs().max_element() <= 1e-4 * expect.max_element().max(1e-6));
        Some(s.wi)
    };
    // Lobe parts below the surface are rejected, so the pdf integrates to the acceptance rate, not 1.
    check_sampler_with("diffuse+phong bsdf", &mut sample, &|d| bsdf.pdf(d) as f64, 200_000, false, &Binning::sphere());
}

#[test]
fn dielectric_sampling_reflects_with_the_fresnel_probability() {
    use prism::bsdf::{Bsdf, Lobe};
    use prism::math::fresnel_dielectric;
    let glass = Lobe::Dielectric { r: glam::Vec3::ONE, t: glam::Vec3::ONE, eta: 1.5 };
    for cos in [1.0f32, 0.5, 0.1] {
        let wo = Vec3A::new((1.0 - cos * cos).sqrt(), 0.0, cos);
        let bsdf = Bsdf::from_lobes(Vec3A::Z, wo, &[glass]).unwrap();
        let mut rng = Rng::new(2, cos.to_bits() as u64);
        let n = 100_000;
        let mut reflected = 0;
        for _ in 0..n {
            let s = bsdf.sample(rng.next_f32(), rng.next_2d()).unwrap();
            assert!(s.delta);
            if s.wi.z > 0.0 {
                reflected += 1;
                assert!((s.weight - glam::Vec3::ONE).abs().max_element() < 1e-6, "reflection weight T/p");
            } else {
                // Radiance scales by 1/eta^2 entering the denser medium.
                assert!((s.weight.x - 1.0 / (1.5 * 1.5)).abs() < 1e-5);
                // Snell: sin_t = sin_i / eta.
                let sin_t = (s.wi.x * s.wi.x + s.wi.y * s.wi.y).sqrt();
                assert!((sin_t - (1.0 - cos * cos).sqrt() / 1.5).abs() < 1e-5);
            }
        }
        let f = fresnel_dielectric(cos, 1.5) as f64;
        let got = reflected as f64 / n as f64;
        let sigma = (f * (1.0 - f) / n as f64).sqrt();
        assert!((got - f).abs() < 5.0 * sigma + 1e-4, "cos {cos}: reflected {got}, Fresnel {f}");
    }
}

#[test]
fn scrambled_sobol_points_are_uniform_progressive_and_stratified() {
    use prism::sampling::sobol_owen_2d;
    // Every prefix of 2^k points of one pixel's sequence is a (0, k, 2)-net: one point in each of the 2^k elementary
    // intervals of every shape (here 2^a x 2^(k-a) cells).
    for seed in [1u32, 77, 0xdead_beef] {
        for k in [2u32, 4, 6, 8] {
            let n = 1u32 << k;
            let pts: Vec<Vec2> = (0..n).map(|i| sobol_owen_2d(i, seed)).collect();
            for a in 0..=k {
                let (nx, ny) = (1u32 << a, 1u32 << (k - a));
                let mut seen = vec![0u32; n as usize];
                for p in &pts {
                    seen[((p.y * ny as f32) as u32 * nx + (p.x * nx as f32) as u32) as usize] += 1;
                }
                assert!(seen.iter().all(|&c| c == 1), "seed {seed}, 2^{k} points, {nx}x{ny} cells: {seen:?}");
            }
        }
    }
    // Across pixels (seeds) each point is uniform: chi-square of point 5 of many sequences on a 16x16 grid.
    let n = 100_000;
    let mut obs = vec![0.0; 256];
    for seed in 0..n {
        let p = sobol_owen_2d(5, seed * 2_654_435_761);
        obs[(p.y * 16.0) as usize * 16 + (p.x * 16.0) as usize] += 1.0;
    }
    let (stat, df, p) = chi_square(&obs, &vec![n as f64 / 256.0; 256]);
    assert!(p > 1e-3, "chi-square {stat:.1} ({df} dof), p = {p:.2e}");
}

/// The concentric map's sine and cosine polynomials on [-pi/4, pi/4] agree with f64 sin and cos to 3e-7 (a few
/// f32 ulps), so disk and cosine-hemisphere samples are where the exact map puts them.
#[test]
fn quarter_circle_sine_and_cosine_match_f64() {
    let mut worst = 0f64;
    for i in 0..=200_000 {
        let x = (i as f64 / 100_000.0 - 1.0) * std::f64::consts::FRAC_PI_4;
        let (s, c) = prism::sampling::warp::sin_cos_quarter(x as f32);
        let xf = x as f32 as f64;
        worst = worst.max((s as f64 - xf.sin()).abs()).max((c as f64 - xf.cos()).abs());
    }
    assert!(worst < 3e-7, "largest error {worst}");
}
