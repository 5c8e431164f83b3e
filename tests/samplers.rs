//! Samplers, pixel filters and the thin lens:
//! - the Sobol sampler stratifies the first 2^k samples of a pixel in every 2D request (one point per elementary
//!   interval of every shape: a (0,k,2)-net) and every 1D request, at every dimension a path uses;
//! - points computed sixteen at a time by the vector kernel, and a sampler answering from them, are the one-point
//!   function's numbers bit for bit;
//! - its dimensions are uncorrelated with each other and neighbouring pixels' errors are uncorrelated in a render;
//! - every sampler is unbiased (the white furnace's sphere is 0.8 whatever the sampler), deterministic across
//!   thread counts, and converges faster with Sobol than independent on a smooth direct-lighting integral;
//! - filter importance sampling draws film offsets with the filter's own density (chi-square), with the 6.837
//!   filters' supports;
//! - the thin lens with aperture 0 is the pinhole bit for bit, and a point in the plane of focus stays sharp.

use crate::common::{chi_square, render_ron, scene_path};
use glam::{Vec2, Vec3, Vec3A};
use prism::camera::CameraRig;
use prism::components::{Camera, Projection};
use prism::integrator::lens_sample_index;
use prism::sampling::{
    PixelFilter, Rng, SOBOL_BATCH, Sampler, SamplerKind, SobolBatch, nested_uniform_scramble, sobol_dim1_fast,
    sobol_dim1_reference, sobol_dim1_reversed, sobol_owen_1d_point, sobol_owen_1d_reversed, sobol_owen_2d,
    sobol_owen_2d_batch, sobol_owen_2d_keyed, sobol_owen_2d_reference, warp,
};
use prism::settings::Overrides;

fn sobol(key: u32) -> Sampler {
    Sampler::new(SamplerKind::Sobol, key, Rng::new(1, 1))
}

#[test]
fn sobol_table_equals_the_bit_loop() {
    let mut rng = Rng::new(3, 3);
    for i in (0..4096).chain((0..4096).map(|_| rng.next_u32())) {
        assert_eq!(sobol_dim1_fast(i), sobol_dim1_reference(i), "index {i}");
    }
}

/// The fast Sobol points (scrambled in the bit-reversed domain, three reversals per 2D point) are the points of
/// the definition (nested uniform scrambles of the index and of each coordinate), bit for bit.
#[test]
fn sobol_points_in_the_reversed_domain_equal_the_definition() {
    let mut rng = Rng::new(5, 5);
    for _ in 0..20_000 {
        let (i, seed, k) = (rng.next_u32() >> (rng.next_u32() % 32), rng.next_u32(), rng.next_u32());
        assert_eq!(sobol_owen_2d(i, seed), sobol_owen_2d_reference(i, seed), "index {i} seed {seed}");
        let one = nested_uniform_scramble(nested_uniform_scramble(i, k).reverse_bits(), seed);
        assert_eq!(sobol_owen_1d_reversed(i.reverse_bits(), k, seed), one, "index {i} keys {k} {seed}");
        // The sampler's entry point, compiled for GFNI where the CPU has it: the same number.
        assert_eq!(sobol_owen_1d_point(i.reverse_bits(), k, seed), one, "GFNI dispatch: index {i} keys {k} {seed}");
    }
}

/// The dimensions a path tracer draws for 3 vertices after the camera's: (1D, 2D, 1D, 2D, 1D) per vertex.
const REQUESTS: [u8; 4 + 15] = [2, 2, 1, 2, 1, 2, 1, 1, 2, 1, 2, 1, 1, 2, 1, 2, 1, 0, 0];

#[test]
fn sobol_prefixes_are_stratified_in_every_dimension_a_path_uses() {
    for key in [0u32, 1, 0xdead_beef, 12345] {
        for k in [2u32, 4, 6, 8] {
            let n = 1usize << k;
            let mut s = sobol(key);
            // points[request][sample]
            let mut points: Vec<Vec<Vec2>> = vec![vec![]; REQUESTS.len()];
            for i in 0..n as u32 {
                s.start(i);
                for (r, &kind) in REQUESTS.iter().enumerate() {
                    match kind {
                        2 => points[r].push(s.next_2d()),
                        1 => points[r].push(Vec2::new(s.next_1d(), 0.5)),
                        _ => {}
                    }
                }
            }
            for (r, &kind) in REQUESTS.iter().enumerate() {
                match kind {
                    2 => {
                        // Every elementary interval shape 2^a x 2^(k-a) holds exactly one point.
                        for a in 0..=k {
                            let (nx, ny) = (1usize << a, 1usize << (k - a));
                            let mut seen = vec![0u8; n];
                            for p in &points[r] {
                                let cell = ((p.y * ny as f32) as usize).min(ny - 1) * nx
                                    + ((p.x * nx as f32) as usize).min(nx - 1);
                                seen[cell] += 1;
                            }
                            assert!(
                                seen.iter().all(|&c| c == 1),
                                "key {key}, 2^{k} samples, request {r}: intervals {nx}x{ny} not stratified"
                            );
                        }
                    }
                    1 => {
                        let mut seen = vec![0u8; n];
                        for p in &points[r] {
                            seen[((p.x * n as f32) as usize).min(n - 1)] += 1;
                        }
                        assert!(seen.iter().all(|&c| c == 1), "key {key}, 2^{k}, 1D request {r} not stratified");
                    }
                    _ => {}
                }
            }
        }
    }
}

#[test]
fn sobol_dimensions_are_uncorrelated_and_uniform() {
    // Over 4096 samples of one pixel: correlation between the x coordinates of different requests (and between x
    // and y of one request) is within 4 / sqrt(n) of 0, and each coordinate's mean is 1/2.
    let n = 4096;
    let mut s = sobol(777);
    let mut cols: Vec<Vec<f64>> = vec![];
    for i in 0..n {
        s.start(i);
        let mut row = vec![];
        for _ in 0..6 {
            let p = s.next_2d();
            row.push(p.x as f64);
            row.push(p.y as f64);
            row.push(s.next_1d() as f64);
        }
        if cols.is_empty() {
            cols = vec![vec![]; row.len()];
        }
        for (c, v) in cols.iter_mut().zip(row) {
            c.push(v);
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    for (a, ca) in cols.iter().enumerate() {
        assert!((mean(ca) - 0.5).abs() < 0.01, "dimension {a} mean {}", mean(ca));
        for (b, cb) in cols.iter().enumerate().skip(a + 1) {
            let (ma, mb) = (mean(ca), mean(cb));
            let cov: f64 = ca.iter().zip(cb).map(|(x, y)| (x - ma) * (y - mb)).sum::<f64>() / n as f64;
            let corr = cov / (1.0 / 12.0);
            assert!(corr.abs() < 4.0 / (n as f64).sqrt(), "dimensions {a} and {b} correlate: {corr:.4}");
        }
    }
}

#[test]
fn samplers_are_deterministic_functions_of_index_and_dimension() {
    for kind in [SamplerKind::Independent, SamplerKind::Stratified, SamplerKind::Sobol] {
        let mut a = Sampler::new(kind, 99, Rng::new(5, 6));
        let mut b = Sampler::new(kind, 99, Rng::new(5, 6));
        for i in 0..64 {
            a.start(i);
            b.start(i);
            for _ in 0..10 {
                assert_eq!(a.next_2d(), b.next_2d());
                assert_eq!(a.next_1d(), b.next_1d());
            }
        }
    }
    // Sobol points do not depend on what was drawn before (progressive: sample 37 is sample 37).
    let mut a = sobol(4);
    a.start(37);
    let first = a.next_2d();
    let mut b = sobol(4);
    for i in 0..37 {
        b.start(i);
        b.next_2d();
    }
    b.start(37);
    assert_eq!(b.next_2d(), first);
}

/// The sampler caches each 2D dimension's scramble keys across a pixel's samples (they depend on the pixel key and
/// the dimension only). The cache must be invisible: a sampler that draws many samples, with 1D and 2D requests
/// interleaved at shifting parities and paths long enough that dimensions share cache slots (more than 64
/// dimensions), gives exactly the numbers of a fresh sampler per sample (whose cache is always empty).
#[test]
fn cached_scramble_keys_give_the_numbers_of_a_fresh_sampler() {
    let mut reused = sobol(0x5eed);
    let mut pattern = Rng::new(10, 11);
    for index in 0..40u32 {
        // The request pattern of this sample: 70 requests, 1D or 2D at random (a new pattern each sample, so a
        // dimension is sometimes the start of a 2D request and sometimes a 1D one, or the second half of a pair).
        let requests: Vec<bool> = (0..70).map(|_| pattern.next_u32() & 1 == 0).collect();
        let mut fresh = sobol(0x5eed);
        fresh.start(index);
        reused.start(index);
        for (r, &two) in requests.iter().enumerate() {
            if two {
                assert_eq!(reused.next_2d(), fresh.next_2d(), "sample {index} request {r}");
            } else {
                assert_eq!(reused.next_1d(), fresh.next_1d(), "sample {index} request {r}");
            }
        }
        assert!(reused.dimension() > 64, "the paths must reach past the cache's 64 dimensions");
    }
    // The stratified sampler's Sobol points (its first vertex's light and BSDF requests) go through the same cache.
    let mut reused = Sampler::new(SamplerKind::Stratified, 7, Rng::new(1, 2));
    for index in 0..40u32 {
        let mut fresh = Sampler::new(SamplerKind::Stratified, 7, Rng::new(1, 2));
        reused.start(index);
        fresh.start(index);
        reused.skip_2d();
        fresh.skip_2d();
        if index % 3 == 0 {
            // Shift the dimensions of this sample's Sobol requests.
            reused.next_1d();
            fresh.next_1d();
        }
        reused.next_2d();
        fresh.next_2d();
        for request in 2..4 {
            assert_eq!(reused.next_2d(), fresh.next_2d(), "stratified sample {index} request {request}");
        }
    }
}

const LIT_PLANE: &str = r#"(
    camera: (eye: (0, 3, 0), target: (0, 0, 0), up: (0, 0, -1), fov: 50, size: (48, 48)),
    render: (integrator: envlight(max_depth: 2)),
    materials: { "white": Lambert(albedo: (0.8, 0.8, 0.8)) },
    entities: [
        (shape: Quad(), material: "white", transform: [Rotate(axis: (1, 0, 0), degrees: -90), UniformScale(3)]),
        (shape: Quad(), light: Area(radiance: (4, 4, 4)), transform: [Translate((0.7, 1.2, 0.3)), Rotate(axis: (1, 0, 0), degrees: 60), UniformScale(0.5)]),
    ],
)"#;

fn render_plane(sampler: SamplerKind, spp: u32, seed: u64) -> Vec<Vec3> {
    render_ron(LIT_PLANE, Overrides { spp: Some(spp), sampler: Some(sampler), seed: Some(seed), ..Default::default() })
        .pixels
}

#[test]
fn sobol_render_has_no_correlation_between_neighbouring_pixels_and_lower_error() {
    // Soft shadows and irradiance from an area light: 2 spp renders against a 256 spp estimate. A sampler that
    // shared its scramble between pixels would make neighbouring errors correlate (structured noise); Sobol's
    // errors must be as uncorrelated as independent sampling's, and smaller.
    let reference = render_plane(SamplerKind::Sobol, 256, 11);
    let stats = |kind| {
        let img = render_plane(kind, 4, 3);
        let err: Vec<f32> = img.iter().zip(&reference).map(|(a, r)| a.x - r.x).collect();
        let w = 48;
        let (mut cov, mut var) = (0.0f64, 0.0f64);
        for y in 0..w {
            for x in 0..w - 1 {
                let (e0, e1) = (err[y * w + x] as f64, err[y * w + x + 1] as f64);
                cov += e0 * e1;
                var += e0 * e0;
            }
        }
        let rmse = (err.iter().map(|e| (*e as f64).powi(2)).sum::<f64>() / err.len() as f64).sqrt();
        (cov / var, rmse)
    };
    let (corr_sobol, rmse_sobol) = stats(SamplerKind::Sobol);
    let (corr_indep, rmse_indep) = stats(SamplerKind::Independent);
    eprintln!("neighbour error correlation: sobol {corr_sobol:.3}, independent {corr_indep:.3}");
    eprintln!("RMSE at 4 spp: sobol {rmse_sobol:.4}, independent {rmse_indep:.4}");
    assert!(corr_sobol.abs() < 0.1, "Sobol errors correlate between pixels: {corr_sobol}");
    assert!(rmse_sobol < 0.8 * rmse_indep, "Sobol {rmse_sobol} not below independent {rmse_indep}");
}

#[test]
fn every_sampler_renders_the_white_furnace_exactly() {
    // A diffuse sphere of albedo 0.8 under a uniform sky of radiance 1: every pixel on the sphere is 0.8 in
    // expectation, whatever the sampler (unbiasedness), within a tight tolerance on the image mean.
    for kind in [SamplerKind::Independent, SamplerKind::Stratified, SamplerKind::Sobol] {
        let img = crate::common::render_file(
            &scene_path("furnace.ron"),
            Overrides { spp: Some(16), sampler: Some(kind), size: Some((48, 48)), ..Default::default() },
        );
        let (w, h) = (img.width, img.height);
        let mut sum = 0.0f64;
        let mut count = 0;
        for y in 0..h {
            for x in 0..w {
                // Pixels well inside the sphere's silhouette (radius 1 seen from z = 4 with fov 40).
                let (dx, dy) = (x as f32 + 0.5 - w as f32 / 2.0, y as f32 + 0.5 - h as f32 / 2.0);
                if (dx * dx + dy * dy).sqrt() < 0.28 * w as f32 {
                    sum += img.get(x, y).x as f64;
                    count += 1;
                }
            }
        }
        let mean = sum / count as f64;
        assert!((mean - 0.8).abs() < 0.004, "{kind:?}: furnace sphere mean {mean}");
    }
}

#[test]
fn filter_importance_sampling_follows_each_filter() {
    // Histogram of film offsets on a grid over the filter's support, against the normalised filter integrated
    // per cell.
    for f in [
        PixelFilter::Box { radius: 0.5 },
        PixelFilter::Box { radius: 1.7 },
        PixelFilter::Tent { radius: 1.5 },
        PixelFilter::Gaussian { sigma: 0.6 },
    ] {
        let r = f.support();
        let g = 24;
        let cell = 2.0 * r / g as f32;
        let sub = 8;
        let mut expected = vec![0.0f64; g * g];
        for (c, e) in expected.iter_mut().enumerate() {
            let (cx, cy) = (c % g, c / g);
            for a in 0..sub {
                for b in 0..sub {
                    let x = -r + cell * (cx as f32 + (a as f32 + 0.5) / sub as f32);
                    let y = -r + cell * (cy as f32 + (b as f32 + 0.5) / sub as f32);
                    *e += f.weight(Vec2::new(x, y)) as f64;
                }
            }
        }
        let total: f64 = expected.iter().sum();
        let n = 200_000;
        expected.iter_mut().for_each(|e| *e *= n as f64 / total);
        let mut observed = vec![0.0f64; g * g];
        let mut rng = Rng::new(8, 8);
        for _ in 0..n {
            let d = f.warp(rng.next_2d());
            assert!(d.x.abs() <= r * 1.0001 && d.y.abs() <= r * 1.0001, "{f:?}: offset {d} outside the support");
            let cx = (((d.x + r) / cell) as usize).min(g - 1);
            let cy = (((d.y + r) / cell) as usize).min(g - 1);
            observed[cy * g + cx] += 1.0;
        }
        let (stat, df, p) = chi_square(&observed, &expected);
        assert!(p > 1e-3, "{f:?}: chi-square {stat:.1} ({df} dof), p = {p:.2e}");
    }
}

fn camera(aperture: f32, focus: f32) -> CameraRig {
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 3.9),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Perspective { fov_y: 39.3077 },
        width: 256,
        height: 256,
        aperture_radius: aperture,
        focus_distance: focus,
        ..Camera::default()
    };
    CameraRig::new(&cam, &glam::Affine3A::IDENTITY).unwrap()
}

/// A chunk's camera rays made together (`CameraRig::generate_rays`, the pinhole's lanes computed side by side) are
/// the rays `generate_ray` makes one at a time, bit for bit: perspective and orthographic, mirrored and cropped
/// frames, a non-square image, chunks of 1 to 16 rays, film positions inside and outside the frame.
#[test]
fn camera_rays_made_sixteen_at_a_time_are_the_rays_made_one_at_a_time() {
    let mut rng = Rng::new(9, 9);
    let bits = |r: &prism::geometry::Ray| {
        (r.origin.to_array().map(f32::to_bits), r.dir.to_array().map(f32::to_bits), r.coherent)
    };
    for (projection, mirror, crop) in [
        (Projection::Perspective { fov_y: 39.3077 }, false, None),
        (Projection::Perspective { fov_y: 90.0 }, true, Some([0.1, 0.2, 0.7, 0.9])),
        (Projection::Orthographic { height: 2.5 }, false, None),
    ] {
        let cam = Camera {
            eye: Vec3::new(0.3, -0.2, 3.9),
            target: Vec3::new(0.1, 0.05, 0.0),
            up: Vec3::Y,
            projection,
            width: 320,
            height: 200,
            mirror,
            crop,
            ..Camera::default()
        };
        let rig = CameraRig::new(&cam, &glam::Affine3A::IDENTITY).unwrap();
        for n in 1..=16 {
            let films: Vec<Vec2> =
                (0..n).map(|_| Vec2::new(rng.next_f32() * 360.0 - 20.0, rng.next_f32() * 240.0 - 20.0)).collect();
            let mut rays = vec![prism::geometry::Ray::new(Vec3A::ZERO, Vec3A::Z); n];
            rig.generate_rays(&films, &mut rays);
            for (f, r) in films.iter().zip(&rays) {
                assert_eq!(bits(r), bits(&rig.generate_ray(*f)), "{projection:?}, film {f}");
            }
        }
    }
}

#[test]
fn thin_lens_of_aperture_zero_is_the_pinhole_and_the_focal_plane_is_sharp() {
    let pinhole = camera(0.0, 3.4);
    let lens = camera(0.06, 3.4);
    let mut rng = Rng::new(2, 2);
    for _ in 0..1000 {
        let film = Vec2::new(rng.next_f32() * 256.0, rng.next_f32() * 256.0);
        let a = pinhole.generate_ray(film);
        let b = pinhole.generate_ray_lens(film, rng.next_2d());
        assert_eq!((a.origin, a.dir), (b.origin, b.dir), "aperture 0 must be the pinhole exactly");
        // Rays through one film point from anywhere on the lens meet the pinhole ray at the focal plane
        // (camera-space depth 3.4: world z = 0.5).
        let c = lens.generate_ray_lens(film, rng.next_2d());
        let t_pin = (0.5 - a.origin.z) / a.dir.z;
        let t_lens = (0.5 - c.origin.z) / c.dir.z;
        let (p, q) = (a.at(t_pin), c.at(t_lens));
        assert!((p - q).length() < 1e-5, "focal point {p} vs {q}");
        assert!((c.origin - Vec3A::new(0.0, 0.0, 3.9)).length() <= 0.06 * 1.0001, "origin off the aperture");
    }
}

/// The thin lens's pairing (`lens_sample_index`): within a block of samples (a pixel's whole render, or the set an
/// explicit pattern stratifies over) each sample takes the lens point of a sample of the same block through a
/// permutation, so the block's lens points are the block's own set (its stratification kept) and only which pixel
/// point each meets changes; `next_2d_of(j)` is the point sample `j`'s own request would get.
#[test]
fn lens_points_are_a_permutation_of_the_blocks_own() {
    for count in [1u32, 2, 3, 4, 16, 64, 100, 1000] {
        for key in [0u32, 1, 0xdead_beef] {
            for start in [0u64, 16, 1 << 20] {
                let mut taken: Vec<u64> =
                    (0..count).map(|p| lens_sample_index(start + p as u64, p, count, key)).collect();
                taken.sort_unstable();
                let block: Vec<u64> = (start..start + count as u64).collect();
                assert_eq!(taken, block, "block of {count} from {start}, key {key}: not a permutation");
            }
        }
    }
    // Not the identity (the pairing does change), and different keys give different pairings.
    let pairing = |key| (0..64u32).map(|p| lens_sample_index(p as u64, p, 64, key)).collect::<Vec<_>>();
    assert!(pairing(3).iter().enumerate().filter(|&(p, &j)| p as u64 != j).count() > 32);
    assert_ne!(pairing(3), pairing(4));
    for (i, j) in [(0u32, 5u32), (3, 3), (10, 1000), (77, 0)] {
        let (mut a, mut b) = (sobol(7), sobol(7));
        a.start(i);
        a.next_2d();
        let p = a.next_2d_of(j);
        b.start(j);
        b.next_2d();
        assert_eq!(p, b.next_2d(), "sample {i} borrowing sample {j}'s point");
        assert_eq!(a.dimension(), b.dimension());
        assert_eq!(
            a.next_2d(),
            {
                b.start(i);
                b.next_2d();
                b.next_2d();
                b.next_2d()
            },
            "later dimensions stay sample {i}'s"
        );
    }
}

#[test]
fn dof_scene_matches_mitsubas_thin_lens_reference() {
    // The Cornell box through a thin lens (aperture 0.06, focus 3.4), against Mitsuba's `thinlens` render: image
    // mean within 1%, error falling like 1/sqrt(spp).
    let rmse = crate::common::rmse_against_reference("dof.ron", "dof.exr", &[4, 16, 64], 0.01);
    for k in 0..2 {
        let ratio = rmse[k] / rmse[k + 1];
        assert!((1.6..3.5).contains(&ratio), "RMSE ratio {ratio:.2} between {rmse:?}");
    }
}

/// A deferred dimension's number is the one `next_1d` gives at that point of the sequence, whether or not the
/// numbers deferred before it were ever computed (so an estimator that skips unused numbers renders the same
/// image bit for bit), for every sampler.
#[test]
fn deferred_dimensions_give_the_numbers_next_1d_would() {
    for kind in [SamplerKind::Sobol, SamplerKind::Stratified, SamplerKind::Independent] {
        for index in [0u32, 1, 7, 1000] {
            let mut eager = Sampler::new(kind, 0x1234_5678, Rng::new(9, 9));
            let mut lazy = Sampler::new(kind, 0x1234_5678, Rng::new(9, 9));
            eager.start(index);
            lazy.start(index);
            for v in 0..6 {
                let e = (eager.next_1d(), eager.next_2d(), eager.next_1d(), eager.next_1d());
                let (a, b, c, d) = (lazy.defer_1d(), lazy.next_2d(), lazy.defer_1d(), lazy.defer_1d());
                // Use only some of them, in another order.
                if v % 2 == 0 {
                    assert_eq!(lazy.get_1d(c), e.2, "{kind:?} index {index} vertex {v}");
                }
                assert_eq!(lazy.get_1d(d), e.3, "{kind:?} index {index} vertex {v}");
                assert_eq!(lazy.get_1d(a), e.0, "{kind:?} index {index} vertex {v}");
                assert_eq!(b, e.1, "{kind:?} index {index} vertex {v}");
            }
            assert_eq!(eager.dimension(), lazy.dimension());
        }
    }
}

/// The second Sobol dimension without a table (a superset XOR over the index's bits, by Lucas's theorem) is the
/// generator matrix's product, reversed: checked on every basis vector (both maps are linear over GF(2), so that
/// proves them equal) and on random indices.
#[test]
fn the_table_free_second_sobol_dimension_is_the_generator_matrix() {
    let mut rng = Rng::new(12, 13);
    for i in (0..32).map(|b| 1u32 << b).chain((0..4096).map(|_| rng.next_u32())) {
        assert_eq!(sobol_dim1_reversed(i), sobol_dim1_reference(i).reverse_bits(), "index {i:#x}");
    }
}

/// Sixteen Sobol points computed at once (the vector kernel, dispatched for this CPU) are the one-point
/// function's, bit for bit, in every lane and dimension.
#[test]
fn batched_sobol_points_equal_the_one_point_function() {
    let mut rng = Rng::new(14, 15);
    for _ in 0..500 {
        let index_rev: [u32; SOBOL_BATCH] = std::array::from_fn(|_| rng.next_u32());
        let keys: Vec<[[u32; SOBOL_BATCH]; 3]> =
            (0..5).map(|_| std::array::from_fn(|_| std::array::from_fn(|_| rng.next_u32()))).collect();
        let mut out = vec![[[0.0f32; SOBOL_BATCH]; 2]; keys.len()];
        sobol_owen_2d_batch(&index_rev, &keys, &mut out);
        for (d, (k, o)) in keys.iter().zip(&out).enumerate() {
            for l in 0..SOBOL_BATCH {
                let one = sobol_owen_2d_keyed(index_rev[l], [k[0][l], k[1][l], k[2][l]]);
                assert_eq!((o[0][l].to_bits(), o[1][l].to_bits()), (one.x.to_bits(), one.y.to_bits()), "{d} {l}");
            }
        }
    }
}

/// Sixteen cosine-weighted directions computed at once (the vector kernel, dispatched for this CPU) are the
/// one-point function's, bit for bit: random points, the disk's centre, the square's corners and its diagonals
/// (where the concentric map changes wedge).
#[test]
fn batched_cosine_directions_equal_the_one_point_function() {
    let mut rng = Rng::new(16, 17);
    let special = [0.0, 0.5, 1.0 - f32::EPSILON / 2.0, 0.25, 0.75, 0.5 + f32::EPSILON, 0.5 - f32::EPSILON / 2.0];
    let pairs = special.len() * special.len();
    for round in 0..300 {
        let point = |l: usize, rng: &mut Rng| {
            if round * SOBOL_BATCH < pairs {
                let i = (round * SOBOL_BATCH + l) % pairs;
                (special[i % special.len()], special[i / special.len()])
            } else if l.is_multiple_of(4) {
                let x = rng.next_f32();
                (x, x)
            } else {
                (rng.next_f32(), rng.next_f32())
            }
        };
        let points: Vec<(f32, f32)> = (0..SOBOL_BATCH).map(|l| point(l, &mut rng)).collect();
        let u = [std::array::from_fn(|l| points[l].0), std::array::from_fn(|l| points[l].1)];
        let mut out = [[0.0f32; SOBOL_BATCH]; 3];
        warp::cosine_hemisphere_lanes(&u, &mut out);
        for l in 0..SOBOL_BATCH {
            let one = warp::cosine_hemisphere(Vec2::new(u[0][l], u[1][l]));
            let lane = [out[0][l], out[1][l], out[2][l]];
            assert_eq!(lane.map(f32::to_bits), one.to_array().map(f32::to_bits), "({}, {})", u[0][l], u[1][l]);
        }
    }
}

/// A sampler handed a batch's points answers with the numbers it would have computed: every request of a path
/// of eight vertices (1D and 2D, the batched dimensions and the others) for sixteen samples, with the batch naming
/// dimensions the path asks for, one it asks for as 1D numbers and one it never reaches. Both ways a chunk is
/// filled: lanes from two pixels (`set_lanes` over part of the chunk) and one pixel's whole chunk (its own path).
/// And a batch cut down to its first dimensions (`SobolBatch::keep`, as a tile does once it has seen how far its
/// paths go): the dimensions it no longer computes are computed alone, to the same numbers. The BSDF points come
/// with their cosine-weighted directions computed ahead, which are `warp::cosine_hemisphere`'s bit for bit.
#[test]
fn a_sampler_given_batched_points_gives_the_numbers_it_would_compute() {
    // Vertex v's dimensions as `envlight` draws them: 1D, 2D, 1D, 2D, 1D from 4 + 7 v.
    let dims: Vec<u32> = (0..4u32).flat_map(|v| [4 + 7 * v + 1, 4 + 7 * v + 4]).chain([7, 500]).collect();
    let directions: Vec<u32> = (0..4u32).map(|v| 4 + 7 * v + 4).collect();
    let mut cut = SobolBatch::new(&dims, &directions);
    cut.keep(0);
    assert_eq!(cut.dims(), &dims[..1], "a batch keeps at least one dimension");
    // Lanes of the first pixel; the rest are the second pixel's; all dimensions, or the first three.
    for (first_pixel_lanes, keep) in [(10, None), (SOBOL_BATCH, None), (10, Some(3)), (SOBOL_BATCH, Some(3))] {
        let mut pixels = [sobol(0xabc), sobol(0xdef)];
        let mut batch = SobolBatch::new(&dims, &directions);
        if let Some(k) = keep {
            batch.keep(k);
            assert_eq!(batch.dims(), &dims[..k]);
        }
        let owner = |lane: usize| {
            let p = usize::from(lane >= first_pixel_lanes);
            (p, 3 + (lane - p * first_pixel_lanes) as u32)
        };
        batch.set_lanes(0, first_pixel_lanes, &mut pixels[0], 3);
        if first_pixel_lanes < SOBOL_BATCH {
            batch.set_lanes(first_pixel_lanes, SOBOL_BATCH - first_pixel_lanes, &mut pixels[1], 3);
        }
        batch.compute();
        for lane in 0..SOBOL_BATCH {
            let (p, index) = owner(lane);
            let (s, mut fresh) = (&mut pixels[p], sobol([0xabc, 0xdef][p]));
            s.start(index);
            fresh.start(index);
            for r in [&mut *s, &mut fresh] {
                r.skip_2d();
                r.skip_2d();
            }
            batch.load(lane, s);
            for v in 0..8 {
                let a = (s.next_1d(), s.next_2d(), s.next_1d());
                let b = (fresh.next_1d(), fresh.next_2d(), fresh.next_1d());
                assert_eq!(a, b, "{first_pixel_lanes} lanes of the first pixel: lane {lane} vertex {v}");
                let (d, u) = (s.next_direction_2d(), fresh.next_2d());
                assert_eq!(d.u, u, "lane {lane} vertex {v}: the BSDF point");
                let (ahead, now) = (d.cosine_hemisphere(), warp::cosine_hemisphere(u));
                assert_eq!(
                    ahead.to_array().map(f32::to_bits),
                    now.to_array().map(f32::to_bits),
                    "lane {lane} vertex {v}"
                );
                assert_eq!(s.next_1d(), fresh.next_1d());
            }
        }
    }
}
