//! The `envlight` plugin: the quad-tree and piecewise-constant environment samplers against their own pdfs on
//! every map (chi-square, normalisation, sample/pdf agreement), and the path tracer against ground truth: the
//! white furnace, irradiance pi L under a uniform sky, an environment map's irradiance by quadrature, a closed
//! emitting enclosure (L = Le / (1 - rho)), energy conservation through glass, and Mitsuba's Cornell box.

use crate::common::{app_from_ron, chi_square, data, refs, render_file, render_ron, scene_path, scratch, spp};
use glam::{Vec2, Vec3, Vec3A};
use prism::compare::compare;
use prism::envmap::{EnvImage, EnvMap};
use prism::io::read_exr;
use prism::plugins::envlight::{Piecewise2D, QuadTree};
use prism::sampling::Rng;
use prism::settings::Overrides;
use std::path::PathBuf;

fn all_maps() -> Vec<(String, EnvMap)> {
    let mut maps = vec![];
    for f in [
        "probulator_ennis_256x128",
        "probulator_grace_256x128",
        "probulator_pisa_256x128",
        "probulator_uffizi_256x128",
        "probulator_wells_256x128",
        "quarry_01_1k",
        "venice_sunset_1k",
    ] {
        maps.push((f.to_string(), EnvMap::load(&[data(&format!("envmaps/equirect/{f}.hdr"))], None).unwrap()));
    }
    for f in ["grace_cross", "stpeters_cross"] {
        maps.push((f.to_string(), EnvMap::load(&[data(&format!("envmaps/cross/{f}.hdr"))], None).unwrap()));
    }
    let faces: Vec<PathBuf> = ["px", "nx", "py", "ny", "pz", "nz"]
        .iter()
        .map(|f| data(&format!("envmaps/cube_faces/pisaHDR/{f}.hdr")))
        .collect();
    maps.push(("pisa_faces".into(), EnvMap::load(&faces, None).unwrap()));
    maps.push(("synthetic_sun".into(), synthetic_sun()));
    maps
}

/// A dim uniform sky with a single texel 10^5 times brighter.
fn synthetic_sun() -> EnvMap {
    let (w, h) = (128, 64);
    let mut texels = vec![Vec3::splat(0.05); (w * h) as usize];
    texels[(20 * w + 77) as usize] = Vec3::splat(5000.0);
    EnvMap::equirect(EnvImage { width: w, height: h, texels })
}

/// Chi-square of `n` samples binned by blocks of texels, against expected counts from `pdf` (exact per texel:
/// pdf(direction of texel centre) x texel solid angle is the texel's probability for a piecewise-constant pdf);
/// also checks that the pdf integrates to 1 and that each sample's pdf equals pdf() of its direction.
fn check_env_sampler(
    name: &str,
    map: &EnvMap,
    sample: &dyn Fn(Vec2) -> Option<(Vec3A, f32)>,
    pdf: &dyn Fn(Vec3A) -> f32,
    exact_texels: bool,
) {
    let block = |k: usize, x: u32, y: u32| {
        let img = &map.images[k];
        let (bx, by) = ((img.width / 32).max(1), (img.height / 16).max(1));
        let per = (img.width / bx) * (img.height / by);
        k * per as usize + ((y / by) * (img.width / bx) + x / bx) as usize
    };
    let nbins = map.images.len() * block(0, map.images[0].width - 1, map.images[0].height - 1)
        / map.images.len().max(1)
        + map.images.len() * 1000;
    let mut expected = vec![0.0f64; nbins];
    let mut integral = 0.0f64;
    for (k, img) in map.images.iter().enumerate() {
        for y in 0..img.height {
            for x in 0..img.width {
                let uv = Vec2::new((x as f32 + 0.5) / img.width as f32, (y as f32 + 0.5) / img.height as f32);
                let p = pdf(map.direction(k, uv)) as f64 * map.texel_solid_angle(k, x, y) as f64;
                expected[block(k, x, y)] += p;
                integral += p;
            }
        }
    }
    let tol = if exact_texels { 1e-3 } else { 5e-3 };
    assert!((integral - 1.0).abs() < tol, "{name}: pdf integrates to {integral} over the sphere");
    let n = 1_000_000;
    let mut observed = vec![0.0f64; nbins];
    let mut rng = Rng::new(0xe17, name.len() as u64);
    let mut mismatches = 0;
    for _ in 0..n {
        let Some((d, p)) = sample(rng.next_2d()) else { continue };
        let p2 = pdf(d);
        if (p - p2).abs() > 1e-3 * p.max(p2) {
            mismatches += 1;
        }
        let (k, uv) = map.coords(d);
        let img = &map.images[k];
        let (x, y) = (
            ((uv.x * img.width as f32) as u32).min(img.width - 1),
            ((uv.y * img.height as f32) as u32).min(img.height - 1),
        );
        observed[block(k, x, y)] += 1.0;
    }
    // pdf() re-derives the texel from the direction; a float round trip can land a sample lying within 1e-7 of a
    // leaf edge in the neighbouring leaf (a measure-zero set, harmless for MIS). Anything more is a real mismatch.
    assert!(mismatches <= n / 1000, "{name}: {mismatches} samples whose pdf differs from pdf()");
    let exp: Vec<f64> = expected.iter().map(|e| e * n as f64).collect();
    let (stat, df, p) = chi_square(&observed, &exp);
    assert!(p > 1e-3, "{name}: chi-square {stat:.1} ({df} dof), p = {p:.2e}");
}

#[test]
fn quadtree_samples_follow_its_pdf_on_every_map_and_a_one_texel_sun() {
    for (name, map) in all_maps() {
        let tree = QuadTree::build(&map).unwrap();
        check_env_sampler(
            &format!("quadtree {name}"),
            &map,
            &|u| tree.sample(&map, u).map(|s| (s.dir, s.pdf)),
            &|d| tree.pdf(&map, d),
            true,
        );
    }
}

#[test]
fn piecewise_constant_baseline_samples_follow_its_pdf() {
    for (name, map) in
        all_maps().into_iter().filter(|(n, _)| n.contains("grace") || n.contains("quarry") || n == "pisa_faces")
    {
        let pc = Piecewise2D::build(&map).unwrap();
        // Its weights use the Jacobian at texel centres, so the per-texel probability is exact only to first order.
        check_env_sampler(&format!("piecewise {name}"), &map, &|u| pc.sample(&map, u), &|d| pc.pdf(&map, d), false);
    }
}

#[test]
fn quadtree_refines_the_sun_and_leaves_black_and_uniform_regions_coarse() {
    let sun = synthetic_sun();
    let tree = QuadTree::build(&sun).unwrap();
    let sun_dir = sun.direction(0, Vec2::new(77.5 / 128.0, 20.5 / 64.0));
    assert_eq!(tree.leaf_texels(&sun, sun_dir), 1, "the sun is refined down to its own texel");
    // Elsewhere the sky is uniform in radiance; texel weights vary only with sin(theta), so leaves span many
    // texels near the equator (where sin(theta) is flat) and thin rows near the poles.
    let equator = sun.direction(0, Vec2::new(0.1, 0.5));
    assert!(tree.leaf_texels(&sun, equator) >= 8, "equator leaf of {} texels", tree.leaf_texels(&sun, equator));
    assert!(tree.leaf_count() < 128 * 64 / 3, "{} leaves for a uniform sky with one sun texel", tree.leaf_count());
    let mut rng = Rng::new(3, 3);
    // Bilinear lookups spread the sun over its 3x3 texel footprint (texels are 2.8 degrees): samples follow that
    // filtered sun, which holds 5000 / (5000 + sky) ~ 0.9 of the power.
    let footprint = (1.5f32 * 2.8125 * std::f32::consts::SQRT_2).to_radians().cos();
    let hits = (0..10_000)
        .filter(|_| tree.sample(&sun, rng.next_2d()).is_some_and(|s| s.dir.dot(sun_dir) > footprint))
        .count();
    assert!(hits > 8_500, "only {hits} of 10000 samples hit the sun's footprint");
    // A map that is black except one quadrant: the black part costs one leaf each and is never sampled.
    let mut texels = vec![Vec3::ZERO; 64 * 32];
    for y in 0..16 {
        for x in 0..32 {
            texels[y * 64 + x] = Vec3::ONE;
        }
    }
    let half = EnvMap::equirect(EnvImage { width: 64, height: 32, texels });
    let t = QuadTree::build(&half).unwrap();
    for _ in 0..10_000 {
        let s = t.sample(&half, rng.next_2d()).unwrap();
        let (_, uv) = half.coords(s.dir);
        // The lit quadrant, plus the one-texel border its bilinear filtering lights.
        assert!(uv.x < 0.5 + 1.0 / 64.0 && uv.y < 0.5 + 1.0 / 32.0, "sampled the black part at {uv}");
    }
    // Deep in the black quadrants the tree stays coarse and the pdf is zero.
    let black = half.direction(0, Vec2::new(0.875, 0.875));
    assert!(t.leaf_texels(&half, black) >= 64, "{} texels", t.leaf_texels(&half, black));
    assert_eq!(t.pdf(&half, black), 0.0);

