//! `vcm` (light tracing, BDPT, bidirectional photon mapping, vertex connection and merging) against ground truth:
//! each strategy set alone converges to the path tracer's Cornell box (light tracing alone, connections alone,
//! merging alone, all of them: the MIS weights of the strategies used partition every path, so each set is
//! unbiased, and merging's bias shrinks with the radius); the BSDF's reverse density is the forward density of the
//! BSDF seen from the other side; bit-identical images across thread counts; a thin lens converges to the path tracer's depth of field; an
//! orthographic camera and bad
//! parameters are one-line errors. (The near-specular furnace is in `near_specular`; resumes and shards in
//! `resume`.)

use crate::common::{app_from_file, render_file, scene_path};
use glam::{Vec3, Vec3A};
use prism::bsdf::{Bsdf, ConductorFresnel, Lobe};
use prism::io::Image;
use prism::sampling::Rng;
use prism::settings::Overrides;

fn with(integrator: &str, spp: u32, size: u32) -> Overrides {
    Overrides { integrator: Some(integrator.into()), spp: Some(spp), size: Some((size, size)), ..Default::default() }
}

fn mean(img: &Image) -> Vec3 {
    let s: glam::DVec3 = img.pixels.iter().map(|p| p.as_dvec3()).sum();
    (s / img.pixels.len() as f64).as_vec3()
}

/// The text of `scenes/NAME` with `from` replaced by `to` (which must occur: the edit is what the test is about).
fn edited_scene(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(scene_path(name)).unwrap();
    assert!(text.contains(from), "{name} no longer contains {from:?}");
    text.replace(from, to)
}

#[test]
fn every_strategy_set_converges_to_the_path_tracers_cornell_box() {
    let scene = scene_path("cornell_box.ron");
    let reference = mean(&render_file(&scene, with("envlight(max_depth: -1)", 1024, 48)));
    for (mode, tol) in [("light", 0.01), ("bdpt", 0.01), ("bpm", 0.01), ("vcm", 0.01)] {
        let img = render_file(&scene, with(&format!("vcm(mode: {mode})"), 128, 48));
        let m = mean(&img);
        let rel = ((m - reference) / reference).abs().max_element();
        assert!(rel < tol, "vcm(mode: {mode}): image mean {m}, path tracer {reference} ({:.2}% off)", rel * 100.0);
    }
}

#[test]
fn the_caustic_box_matches_the_path_tracer_with_connections_and_with_merging() {
    let scene = scene_path("cornell_caustic.ron");
    let reference = mean(&render_file(&scene, with("envlight(max_depth: 12)", 1024, 40)));
    for mode in ["bdpt", "vcm"] {
        let m = mean(&render_file(&scene, with(&format!("vcm(mode: {mode}, max_depth: 12)"), 96, 40)));
        let rel = ((m - reference) / reference).abs().max_element();
        assert!(rel < 0.01, "vcm(mode: {mode}): caustic box mean {m}, path tracer {reference}");
    }
}

#[test]
fn light_a_rough_glass_sphere_transmits_is_merged_on_either_side_of_its_surface() {
    // Merging at a rough dielectric's surface takes light that arrived from inside as well as from outside: the
    // MIS weights count merging there, so refusing it (as for the far face of a thin wall) loses that share of
    // the transmitted light (0.8-0.9% of this image).
    let text = edited_scene(
        "cornell_caustic.ron",
        r#""glass": Glass(ior: 1.5)"#,
        r#""glass": RoughDielectric(alpha: 0.3, ior: 1.5)"#,
    );
    let reference = mean(&crate::common::render_ron(&text, with("envlight(max_depth: 12)", 2048, 48)));
    let m = mean(&crate::common::render_ron(&text, with("vcm(max_depth: 12)", 256, 48)));
    let rel = ((m - reference) / reference).abs().max_element();
    assert!(rel < 0.004, "vcm on a rough glass sphere: mean {m}, path tracer {reference} ({:.2}% off)", rel * 100.0);
}

/// A BSDF of `lobes` around +z seen from `wo`.
fn bsdf(wo: Vec3A, lobes: &[Lobe]) -> Option<Bsdf> {
    Bsdf::from_lobes(Vec3A::Z, wo, lobes)
}

fn upper(rng: &mut Rng) -> Vec3A {
    let (u, v) = (rng.next_f32(), rng.next_f32());
    let z = 0.05 + 0.95 * u;
    let r = (1.0 - z * z).sqrt();
    let phi = std::f32::consts::TAU * v;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

#[test]
fn the_reverse_density_is_the_forward_density_of_the_bsdf_seen_from_the_other_direction() {
    let gold = ConductorFresnel::Schlick(Vec3::new(1.0, 0.78, 0.34));
    let cases: Vec<Vec<Lobe>> = vec![
        vec![Lobe::Diffuse { albedo: Vec3::splat(0.5) }],
        vec![Lobe::Conductor { alpha: 0.3, fresnel: gold, scale: Vec3::ONE }],
        vec![
            Lobe::Conductor { alpha: 0.1, fresnel: gold, scale: Vec3::ONE },
            Lobe::Diffuse { albedo: Vec3::new(0.2, 0.5, 0.8) },
        ],
    ];
    let mut rng = Rng::new(7, 11);
    for lobes in &cases {
        for _ in 0..200 {
            let (wo, wi) = (upper(&mut rng), upper(&mut rng));
            let (Some(a), Some(b)) = (bsdf(wo, lobes), bsdf(wi, lobes)) else { continue };
            let (rev, fwd) = (a.pdf_rev(wi), b.pdf(wo));
            assert!(
                (rev - fwd).abs() <= 1e-4 * fwd.max(1e-3),
                "{lobes:?}: pdf_rev {rev} from wo {wo} towards wi {wi}, forward pdf from wi {fwd}"
            );
        }
    }
}

#[test]
fn vcm_is_bit_identical_across_thread_counts() {
    for scene in ["cornell_caustic.ron", "cornell_rough.ron"] {
        let render = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| render_file(&scene_path(scene), with("vcm", 3, 40)))
        };
        let (a, b) = (render(1), render(2));
        assert!(
            a.pixels
                .iter()
                .zip(&b.pixels)
                .all(|(p, q)| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits)),
            "{scene}"
        );
    }
}

#[test]
fn a_thin_lens_converges_to_the_path_tracers_depth_of_field() {
    // Light vertices are connected to lens points of their own; the camera's density of a point is its ray's
    // density per unit film area from whichever lens point: light tracing alone, connections and merging all
    // converge to the path tracer's image of the thin-lens Cornell box.
    // A wide aperture focused in front of the box, so the whole box is blurred over many pixels at this size.
    let text = edited_scene(
        "dof.ron",
        "aperture_radius: 0.06, focus_distance: 3.4",
        "aperture_radius: 0.3, focus_distance: 1.5",
    );
    let size = 48;
    let reference = crate::common::render_ron(&text, with("envlight(max_depth: 8)", 2048, size));
    for (mode, tol) in [("light", 0.015), ("bdpt", 0.015), ("vcm", 0.015)] {
        let img = crate::common::render_ron(&text, with(&format!("vcm(mode: {mode}, max_depth: 8)"), 256, size));
        let (m, r) = (mean(&img), mean(&reference));
        let rel = ((m - r) / r).abs().max_element();
        assert!(rel < tol, "vcm(mode: {mode}) through a thin lens: mean {m}, path tracer {r}");
        // The blur is the lens's: the picture matches the path tracer's pixel by pixel up to noise (the
        // whole box is out of focus), not only in its mean.
        let err: f64 = img.pixels.iter().zip(&reference.pixels).map(|(a, b)| (*a - *b).length_squared() as f64).sum();
        let rmse = (err / (3.0 * img.pixels.len() as f64)).sqrt();
        assert!(rmse < 0.05, "vcm(mode: {mode}) through a thin lens: RMSE {rmse} against the path tracer");
    }
}

#[test]
fn an_orthographic_camera_and_bad_vcm_parameters_are_one_line_errors() {
    let text = edited_scene("cornell_box.ron", "size: (256, 256)", "size: (256, 256), orthographic: Some(2)");
    let mut app = crate::common::app_from_ron(&text, with("vcm", 1, 16));
    let err = app.run().expect_err("an orthographic camera").to_string();
    assert!(err.contains("orthographic") && !err.contains('\n'), "{err}");
    for (spec, needle) in [
        ("vcm(alpha: 0)", "alpha"),
        ("vcm(alpha: 1.5)", "alpha"),
        ("vcm(radius: 0)", "radius"),
        ("vcm(radius: NaN)", "radius"),
        ("vcm(radius_pixels: -1)", "radius_pixels"),
        ("vcm(light_paths: 0)", "light_paths"),
        ("vcm(light_paths: 100000000)", "light_paths"),
        ("vcm(max_depth: 0)", "max_depth"),
        ("vcm(max_depth: -2)", "max_depth"),
        ("vcm(mode: sideways)", "mode"),
        ("vcm(heuristic: maximum)", "heuristic"),
        ("vcm(gamma: 1)", "gamma"),
    ] {
        let mut app = app_from_file(&scene_path("cornell_box.ron"), with(spec, 1, 16));
        let err = app.run().expect_err(spec).to_string();
        assert!(err.contains(needle) && !err.contains('\n'), "{spec}: {err}");
    }
}
