//! The `envlight` plugin: the quad-tree and piecewise-constant environment samplers against their own pdfs on
//! every map (chi-square, normalisation, sample/pdf agreement), and the path tracer against ground truth: the
//! white furnace, irradiance pi L under a uniform sky, an environment map's irradiance by quadrature, a closed
//! emitting enclosure (L = Le / (1 - rho)), energy conservation through glass, and Mitsuba's Cornell box.

use crate::common::{app_from_ron, chi_square, data, render_file, render_ron, scene_path, scratch, spp};
use glam::{Vec2, Vec3, Vec3A};
use prism::envmap::{EnvImage, EnvMap};
use prism::lights::{Piecewise2D, QuadTree};
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
    // pbrt-v4's equal-area octahedral square (PFM), from Bitterli's classroom.
    maps.push((
        "classroom_skydome".into(),
        EnvMap::load(&[data("bitterli/classroom/textures/Skydome.pfm")], None).unwrap(),
    ));
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
        // The lit quadrant, plus the one-texel border its bilinear filtering lights (x wraps around).
        let in_x = uv.x < 0.5 + 1.0 / 64.0 || uv.x > 1.0 - 1.0 / 64.0;
        assert!(in_x && uv.y < 0.5 + 1.0 / 32.0, "sampled the black part at {uv}");
    }
    // Deep in the black quadrants the tree stays coarse and the pdf is zero.
    let black = half.direction(0, Vec2::new(0.875, 0.875));
    assert!(t.leaf_texels(&half, black) >= 64, "{} texels", t.leaf_texels(&half, black));
    assert_eq!(t.pdf(&half, black), 0.0);
    assert!(
        QuadTree::build(&EnvMap::equirect(EnvImage { width: 8, height: 4, texels: vec![Vec3::ZERO; 32] })).is_none()
    );
}

/// Pixels of the furnace image fully on the sphere and fully off it: the sphere's image radius is
/// tan(asin(1/4)) / tan(20 deg) * 64 = 45.40 px.
fn furnace_masks(w: u32) -> (Vec<usize>, Vec<usize>) {
    let r = (0.25f64.asin().tan() / 20f64.to_radians().tan()) * w as f64 / 2.0;
    let c = w as f64 / 2.0;
    let (mut on, mut off) = (vec![], vec![]);
    for y in 0..w {
        for x in 0..w {
            let d = ((x as f64 + 0.5 - c).powi(2) + (y as f64 + 0.5 - c).powi(2)).sqrt();
            if d <= r - 0.75 {
                on.push((y * w + x) as usize);
            } else if d >= r + 0.75 {
                off.push((y * w + x) as usize);
            }
        }
    }
    (on, off)
}

#[test]
fn white_furnace_sphere_renders_its_albedo_and_the_sky_exactly_one() {
    for integrator in ["envlight", "envlight(max_depth: 2)", "envlight(env_sampling: uniform)", "envlight(mis: false)"]
    {
        let img = render_file(
            &scene_path("furnace.ron"),
            Overrides { integrator: Some(integrator.into()), spp: Some(16), ..Default::default() },
        );
        let (on, off) = furnace_masks(img.width);
        assert_eq!(on.len(), 6280, "covered-pixel count as in ../shared/refs/furnace.md");
        let mean = on.iter().map(|&i| img.pixels[i].x as f64).sum::<f64>() / on.len() as f64;
        assert!((mean - 0.8).abs() < 0.004, "{integrator}: sphere mean {mean} (exact 0.8)");
        assert!(off.iter().all(|&i| img.pixels[i] == Vec3::ONE), "{integrator}: background must be exactly 1");
    }
}

#[test]
fn a_lambertian_plane_under_a_uniform_sky_receives_pi_l() {
    // E = pi L, so L_out = rho L; the plane hides the lower hemisphere.
    let scene = "(camera: (eye: (0, 5, 0), target: (0, 0, 0), up: (0, 0, -1), orthographic: 2, size: (16, 16)),
        render: (integrator: envlight(max_depth: 2)),
        materials: {\"m\": Lambert(albedo: (0.5, 0.25, 1))},
        entities: [(shape: Plane(), material: \"m\"), (light: Environment(radiance: (2, 2, 2)))])";
    let img = render_ron(scene, spp(64));
    let m = img.mean();
    assert!((m - Vec3::new(1.0, 0.5, 2.0)).abs().max_element() < 0.01, "mean {m}, expected rho L = (1, 0.5, 2)");
}

#[test]
fn irradiance_from_an_environment_map_matches_quadrature() {
    // A white Lambertian quad facing up under the Grace probe, tilted 15 degrees so its sky is off-axis:
    // L_out = E / pi with E = sum of L(d) max(0, n.d) dw over a fine grid of directions. Each pixel is an
    // independent estimate, so their spread gives the standard error of the image mean: the mean must lie within
    // 4 standard errors of the quadrature (a confidence-interval test, not a fixed tolerance).
    let map_path = data("envmaps/equirect/probulator_grace_256x128.hdr");
    let scene = format!(
        "(camera: (eye: (0, 5, 0), target: (0, 0, 0), up: (0, 0, -1), orthographic: 0.5, size: (16, 16)),
          render: (integrator: envlight(max_depth: 2)),
          materials: {{\"m\": Lambert(albedo: (1, 1, 1))}},
          entities: [(shape: Quad(), material: \"m\", transform: [Rotate(axis: (1, 0, 0), degrees: -90)]),
                     (light: Environment(map: \"{}\"), transform: [Rotate(axis: (1, 0, 1), degrees: 15)])])",
        map_path.display()
    );
    let img = render_ron(&scene, spp(1024));
    let mut app = app_from_ron(&scene, Overrides::default());
    app.setup().unwrap();
    let env = app.resources.scene.as_ref().unwrap().lights.environment.clone().unwrap();
    let n = 1024;
    let mut e = glam::DVec3::ZERO;
    for i in 0..n {
        for j in 0..2 * n {
            let theta = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
            let phi = (j as f64 + 0.5) / (2 * n) as f64 * std::f64::consts::TAU;
            let d = Vec3A::new((theta.sin() * phi.cos()) as f32, theta.cos() as f32, (theta.sin() * phi.sin()) as f32);
            let dw = theta.sin() * (std::f64::consts::FRAC_PI_2 / n as f64) * (std::f64::consts::TAU / (2 * n) as f64);
            e += env.eval(d).as_dvec3() * theta.cos() * dw;
        }
    }
    let expect = e / std::f64::consts::PI;
    let px: Vec<glam::DVec3> = img.pixels.iter().map(|p| p.as_dvec3()).collect();
    let mean = px.iter().sum::<glam::DVec3>() / px.len() as f64;
    let var = px.iter().map(|p| (*p - mean) * (*p - mean)).sum::<glam::DVec3>() / (px.len() - 1) as f64;
    let stderr = (var / px.len() as f64).powf(0.5);
    for c in 0..3 {
        assert!(stderr[c] < 0.01 * expect[c], "channel {c}: standard error {} too large for a useful test", stderr[c]);
        assert!(
            (mean[c] - expect[c]).abs() < 4.0 * stderr[c],
            "channel {c}: rendered {} +- {}, quadrature {}",
            mean[c],
            stderr[c],
            expect[c]
        );
    }
}

#[test]
fn a_closed_emitting_diffuse_enclosure_reaches_le_over_one_minus_rho() {
    // Inside a sphere that both emits Le and reflects diffusely with albedo rho, radiance is the geometric series
    // Le (1 + rho + rho^2 + ...) = Le / (1 - rho): tests multi-bounce paths, Russian roulette and MIS together.
    let scene = "(camera: (size: (8, 8), eye: (0, 0, 0.5), target: (0, 0, 0)),
        render: (integrator: envlight),
        materials: {\"wall\": Lambert(albedo: (0.5, 0.5, 0.5))},
        entities: [(shape: Sphere(radius: 2), material: \"wall\", light: Area(radiance: (1, 1, 1), two_sided: true))])";
    let img = render_ron(scene, spp(256));
    let m = img.mean().x;
    assert!((m - 2.0).abs() < 0.02, "mean {m}, expected Le / (1 - rho) = 2");
}

/// The roulette rule itself (`prism::integrator::roulette::survival`): bright paths survive surely, dim ones in
/// proportion to their throughput over the threshold, refraction's 1/eta^2 is undone, and from segment 64 on
/// survival is capped at 0.95 so that every path ends.
#[test]
fn roulette_survival_is_throughput_over_threshold_capped_only_on_long_paths() {
    use prism::integrator::roulette::{LONG_PATH_SEGMENTS, LONG_PATH_SURVIVAL, survival};
    assert_eq!(survival(Vec3::splat(0.8), 1.0, 0.5, 3), 1.0);
    assert_eq!(survival(Vec3::new(0.1, 0.5, 0.2), 1.0, 0.5, 3), 1.0);
    assert!((survival(Vec3::new(0.1, 0.2, 0.05), 1.0, 0.5, 3) - 0.4).abs() < 1e-6);
    // Threshold 1: survival equals the throughput (Mitsuba's rule without its cap).
    assert!((survival(Vec3::splat(0.3), 1.0, 1.0, 3) - 0.3).abs() < 1e-6);
    // Inside glass of index 1.5 a lossless path carries 1 / 2.25; with eta^2 undone it is a bright path.
    assert_eq!(survival(Vec3::splat(1.0 / 2.25), 2.25, 0.5, 3), 1.0);
    assert_eq!(survival(Vec3::ONE, 1.0, 0.5, LONG_PATH_SEGMENTS - 1), 1.0);
    assert_eq!(survival(Vec3::ONE, 1.0, 0.5, LONG_PATH_SEGMENTS), LONG_PATH_SURVIVAL);
    assert_eq!(survival(Vec3::splat(10.0), 1.0, 0.5, 1000), LONG_PATH_SURVIVAL);
}

/// Russian roulette only trades time for variance: with any start and threshold, the enclosure above (albedo 0.8,
/// so paths of many bounces matter: Le / (1 - rho) = 5) renders its exact radiance. Each rule's mean is judged
/// against its own standard error over the pixels; a rule that forgot to divide a survivor's throughput by its
/// survival probability would lose a fifth of the light or more.
#[test]
fn every_roulette_rule_keeps_the_enclosure_at_le_over_one_minus_rho() {
    for (rr_depth, threshold) in [(1, 0.5), (1, 1.0), (3, 0.25), (5, 1.0), (1, 4.0)] {
        let scene = format!(
            "(camera: (size: (16, 16), eye: (0, 0, 0.5), target: (0, 0, 0)),
            render: (integrator: envlight(rr_depth: {rr_depth}, rr_threshold: {threshold}), sampler: independent),
            materials: {{\"wall\": Lambert(albedo: (0.8, 0.8, 0.8))}},
            entities: [(shape: Sphere(radius: 2), material: \"wall\",
                        light: Area(radiance: (1, 1, 1), two_sided: true))])"
        );
        let n = 64u32;
        let img = render_ron(&scene, spp(n));
        let values: Vec<f64> = img.pixels.iter().map(|p| p.x as f64).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (values.len() - 1) as f64;
        let se = (var / values.len() as f64).sqrt();
        assert!(
            (mean - 5.0).abs() < 4.0 * se + 0.01,
            "rr_depth {rr_depth}, rr_threshold {threshold}: mean {mean} (exact 5, standard error {se})"
        );
    }
}

/// Every path ends, even where nothing absorbs: inside a closed white (albedo 1) sphere with unlimited depth a
/// path's throughput stays 1, so roulette by a threshold alone would never stop it; survival is capped at 0.95
/// from segment 64 on. The render must finish (a watchdog fails the test after two minutes instead of hanging);
/// there is no light, so the image is black.
#[test]
fn paths_end_in_a_lossless_enclosure_with_unlimited_depth() {
    let scene = "(camera: (size: (8, 8), eye: (0, 0, 0.5), target: (0, 0, 0)),
        render: (integrator: envlight(max_depth: -1)),
        materials: {\"wall\": Lambert(albedo: (1, 1, 1))},
        entities: [(shape: Sphere(radius: 2), material: \"wall\")])";
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(render_ron(scene, spp(16)));
    });
    let img = rx.recv_timeout(std::time::Duration::from_secs(120)).expect("the render did not finish: paths never end");
    assert!(img.pixels.iter().all(|p| *p == Vec3::ZERO));
}

#[test]
fn glass_and_mirror_under_a_uniform_sky_conserve_energy() {
    let scene = "(camera: (eye: (0, 0, 4), fov: 35, size: (24, 24)),
        render: (integrator: envlight),
        materials: {\"glass\": Glass(ior: 1.5), \"mirror\": Mirror()},
        entities: [(shape: Sphere(center: (-0.6, 0, 0), radius: 0.5), material: \"glass\"),
                   (shape: Sphere(center: (0.6, 0, 0), radius: 0.5), material: \"mirror\"),
                   (light: Environment(radiance: (1, 1, 1)))])";
    let img = render_ron(scene, spp(64));
    for p in &img.pixels {
        assert!((p.x - 1.0).abs() < 0.05, "pixel {p}");
    }
    assert!((img.mean().x - 1.0).abs() < 2e-3, "mean {}", img.mean().x);
}

#[test]
fn cornell_box_matches_mitsubas_path_traced_reference_and_converges() {
    let rmse = crate::common::rmse_against_reference("cornell_box.ron", "cornell.exr", &[4, 16, 64], 0.01);
    // Unbiased Monte Carlo: each 4x in samples divides the RMSE by at least ~2 (1/sqrt(spp)); stratification of the
    // pixel and first-bounce samples makes it a little faster, but never like 1/spp (that would mean a bias
    // vanishing, not noise averaging out).
    for k in 0..2 {
        let ratio = rmse[k] / rmse[k + 1];
        assert!((1.6..3.5).contains(&ratio), "RMSE ratio {ratio:.2} between {:?}", &rmse);
    }
}

#[test]
fn bad_environment_light_settings_are_rejected() {
    let dir = scratch("envsettings");
    let bad = [
        ("(camera: (), entities: [(light: Environment(map: \"missing.hdr\"))])", "missing.hdr"),
        ("(camera: (), entities: [(light: Environment(scale: -1))])", "scale"),
        ("(camera: (), entities: [(light: Environment()), (light: Environment())])", "only one environment"),
        ("(camera: (), entities: [(shape: Sphere(), light: Environment())])", "cannot have a shape"),
        ("(camera: (), render: (integrator: envlight(max_depth: 0)))", "max_depth"),
        ("(camera: (), render: (integrator: envlight(env_sampling: magic)))", "magic"),
    ];
    for (text, needle) in bad {
        let path = dir.join("s.ron");
        std::fs::write(&path, text).unwrap();
        let o =
            crate::common::prism(&["render", path.to_str().unwrap(), "-o", dir.join("o.png").to_str().unwrap(), "-q"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.starts_with("error:") && err.contains(needle), "{text}: {err}");
        assert!(!err.contains("panicked"));
    }
}

/// Russian roulette and refraction: radiance crossing into glass is scaled by 1/eta^2 and restored on the way out,
/// so a path inside a glass sphere is not a dimmer path. A clear sphere (ior 1.5) in a white furnace (uniform sky
/// of radiance 1) is exactly 1 everywhere. With roulette from the first vertex and threshold 1 (survival equal to
/// the throughput), a path through the glass whose 1/eta^2 is undone survives each roulette with about the
/// Fresnel transmittance, 0.96, and a path with n roulettes has per-sample variance of about (1/0.96)^n - 1 (small
/// for the few interfaces most paths cross); judging by beta alone would survive with about 0.43 inside the glass
/// and give 1/0.43 - 1 = 1.3 or more for every path that enters it.
#[test]
fn roulette_inside_glass_undoes_the_radiance_scaling_of_refraction() {
    let scene = "(camera: (eye: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (64, 64)),
        render: (integrator: envlight(max_depth: -1, rr_depth: 1, rr_threshold: 1), sampler: independent),
        materials: {\"glass\": Glass(ior: 1.5)},
        entities: [(shape: Sphere(), material: \"glass\"), (light: Environment(radiance: (1, 1, 1)))])";
    let n = 16u32;
    let img = render_ron(scene, spp(n));
    let (on, _) = furnace_masks(img.width);
    let values: Vec<f64> = on.iter().map(|&i| img.pixels[i].y as f64).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    // Per-sample variance from the spread of per-pixel means of n samples each.
    let var = values.iter().map(|v| (v - 1.0).powi(2)).sum::<f64>() / values.len() as f64 * n as f64;
    let se = (var / n as f64 / values.len() as f64).sqrt();
    assert!((mean - 1.0).abs() < 4.0 * se + 1e-3, "sphere mean {mean} (exact 1, standard error {se})");
    assert!(var < 0.5, "per-sample variance {var}: roulette kills paths inside the glass (beta-only rule: > 1.3)");
}
