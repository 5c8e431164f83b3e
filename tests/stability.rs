//! Where methods fail: NaN samples never reach the film, an interrupted render keeps what it had, the time budget
//! ends the render when spent, degenerate and huge geometry is handled.

use crate::common::{app_from_ron, render_ron, spp};
use glam::Vec3;
use prism::app::{Plugin, Stage};
use prism::geometry::Ray;
use prism::integrator::{PerPixel, PixelIntegrator};
use prism::scene::Scene;
use prism::settings::Overrides;
use std::sync::atomic::Ordering;

struct NanEveryOther;

impl PixelIntegrator for NanEveryOther {
    fn radiance(&self, _scene: &Scene, ray: Ray, _sampler: &mut prism::sampling::Sampler) -> Vec3 {
        if ray.dir.x > 0.0 { Vec3::NAN } else { Vec3::ONE }
    }
}

struct NanPlugin;

impl Plugin for NanPlugin {
    fn name(&self) -> &str {
        "nan"
    }
    fn build(&self, app: &mut prism::App) {
        app.register_integrator("nan", Box::new(|_| Ok(Box::new(PerPixel::new(NanEveryOther)))));
    }
}

#[test]
fn nan_samples_never_reach_the_film_and_are_counted() {
    let mut app = app_from_ron("(camera: (size: (16, 16)), render: (integrator: nan, spp: 2))", Overrides::default());
    app.add_plugin(NanPlugin);
    app.run().unwrap();
    let film = app.resources.film.as_ref().unwrap();
    assert!(film.image().iter().all(|p| p.is_finite()));
    assert_eq!(film.nonfinite, 16 * 8 * 2, "half the pixels, 2 samples each");
}

#[test]
fn an_interrupted_render_keeps_the_passes_it_finished() {
    let dir = crate::common::scratch("interrupt");
    let out = dir.join("partial.exr");
    let mut app = app_from_ron(
        "(camera: (size: (16, 16)), entities: [(shape: Sphere(), light: Area(radiance: (1, 1, 1)))], render: (spp: 8, passes: 8))",
        Overrides::default(),
    );
    app.resources.outputs = vec![out.clone()];
    // Simulate Ctrl-C arriving during the third pass.
    app.add_system(Stage::Accumulate, "interrupt_after_two_passes", |_, res| {
        if res.progress.passes_done == 2 {
            res.cancel.store(true, Ordering::Relaxed);
        }
        Ok(())
    });
    app.run().unwrap();
    let p = &app.resources.progress;
    assert!(p.interrupted, "the render reports the interruption");
    assert_eq!(p.passes_done, 2, "the pass in flight when cancelled does not count as complete");
    let img = prism::io::read_exr(&out).expect("what was rendered was written");
    assert!(img.get(8, 8).x > 0.5, "the sphere light is in the written image");
}

#[test]
fn the_time_budget_ends_the_render_inside_a_pass_that_would_outlast_it() {
    // A scene of a million samples per pixel: its passes hold 62,500 each, minutes of work. The budget's watchdog
    // cuts the first one short; its finished tiles are shown, and it does not count as done.
    let mut app = app_from_ron(
        "(camera: (size: (64, 64)), render: (integrator: envlight, spp: 1000000), entities: [(shape: Sphere())])",
        Overrides { time_budget: Some(0.3), spp_unlimited: true, ..Default::default() },
    );
    let t0 = std::time::Instant::now();
    app.run().unwrap();
    let took = t0.elapsed().as_secs_f64();
    assert!(took < 20.0, "a 0.3 s budget took {took} s");
    assert_eq!(app.resources.progress.passes_done, 0, "the cut pass does not count");
    assert!(!app.resources.progress.interrupted, "a spent budget is the end of the render, not an interruption");
    assert_eq!(app.resources.settings.pass_spp, 62_500);
}

#[test]
fn photon_mapping_under_a_time_budget_runs_one_iteration_per_pass() {
    let mut app = app_from_ron(
        "(camera: (size: (16, 16)), render: (integrator: ppm, spp: 4096), entities: [(shape: Sphere())])",
        Overrides { time_budget: Some(0.5), spp_unlimited: true, ..Default::default() },
    );
    app.run().unwrap();
    assert_eq!(app.resources.settings.pass_spp, 1, "a cut pass loses at most one iteration");
    assert!(app.resources.progress.passes_done >= 1);
}

#[test]
fn degenerate_mesh_triangles_are_skipped_not_fatal() {
    let dir = crate::common::scratch("degenerate");
    let obj = dir.join("degenerate.obj");
    // Collinear and coincident corners; a non-finite vertex is corrupt data, an error with its line
    // (`reliability::obj_with_a_non_finite_vertex_is_an_error_at_its_line`).
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n").unwrap();
    let text = format!(
        "(camera: (eye: (0.3, 0.3, 2), target: (0.3, 0.3, 0), size: (8, 8)), entities: [(shape: Mesh(path: \"{}\"))])",
        obj.display()
    );
    let mut app = app_from_ron(&text, Overrides::default());
    app.setup().unwrap();
    let s = app.resources.scene.as_ref().unwrap();
    assert_eq!(s.prims.num_tris(), 1);
    assert_eq!(s.prims.skipped_degenerate, 2, "a collinear and a coincident-corner triangle");
}

#[test]
fn huge_and_tiny_scales_render_without_nans_or_acne() {
    // A directional light on a sphere at scale 1e-3 and 1e5: the lit hemisphere is exactly rho/pi E cos, so no
    // pixel on it may be darkened by self-shadowing.
    for scale in [1e-3f32, 1e5] {
        let text = format!(
            "(camera: (eye: (0, 0, {}), fov: 30, size: (24, 24)),
              materials: {{\"m\": Lambert(albedo: (1, 1, 1))}},
              entities: [(shape: Sphere(radius: {scale}), material: \"m\"), (light: Directional(irradiance: (3.14159265, 3.14159265, 3.14159265), direction: (0, 0, -1)))])",
            4.0 * scale
        );
        let img = render_ron(&text, spp(1));
        for p in &img.pixels {
            assert!(p.is_finite());
        }
        // Centre pixel faces the light head-on: radiance = rho/pi * E = 1.
        let c = img.get(12, 12).x;
        assert!((c - 1.0).abs() < 0.01, "scale {scale}: centre {c}");
        // Every covered pixel is lit (radiance > 0): no acne.
        let covered = img.pixels.iter().filter(|p| p.x > 0.0).count();
        assert!(covered > 100, "scale {scale}: {covered} lit pixels");
    }
}

#[test]
fn an_empty_scene_renders_its_background() {
    let img = render_ron("(camera: (size: (4, 4)), background: (0.25, 0.5, 1))", spp(1));
    assert!(img.pixels.iter().all(|p| *p == Vec3::new(0.25, 0.5, 1.0)));
}

/// A plugin integrator whose tiles hold fewer counts than pixels.
struct MalformedTiles;

impl prism::integrator::Integrator for MalformedTiles {
    fn render_pass(
        &mut self,
        _scene: &Scene,
        pass: &prism::integrator::PassInfo,
        _cancel: &std::sync::atomic::AtomicBool,
    ) -> prism::integrator::PassOutput {
        let (w, h) = (pass.settings.width, pass.settings.height);
        let tile = prism::integrator::Tile { x0: 0, y0: 0, w, h };
        let n = (w * h) as usize;
        let t = prism::integrator::TileSamples {
            tile,
            counts: vec![1; n - 1],
            sums: vec![prism::film::FixedRgb::from_rgb(1.0, 1.0, 1.0); n],
            nonfinite: 0,
        };
        prism::integrator::PassOutput::Samples(vec![t])
    }
}

#[test]
fn a_plugin_tile_that_does_not_fit_the_film_is_an_error_not_a_panic() {
    let mut app =
        app_from_ron("(camera: (size: (8, 8)), render: (integrator: bad_tiles, spp: 1))", Overrides::default());
    app.register_integrator("bad_tiles", Box::new(|_| Ok(Box::new(MalformedTiles))));
    let err = app.run().unwrap_err().to_string();
    assert!(err.contains("integrator `bad_tiles` returned a malformed tile") && err.contains("63 counts"), "{err}");
}
