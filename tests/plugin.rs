//! The plugin API from outside the crate: an integrator defined here, registered through `Plugin`, selected by
//! name, rendered by Prism's schedule; and a system added to a stage.

use glam::Vec3;
use prism::app::{App, Plugin, SceneSource, Stage};
use prism::geometry::Ray;
use prism::integrator::{PerPixel, PixelIntegrator};
use prism::sampling::Sampler;
use prism::scene::Scene;
use serde::Deserialize;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

/// Shades by the geometric normal facing the camera: n . (-d), a value known exactly for a sphere.
struct FacingRatio {
    scale: f32,
}

impl PixelIntegrator for FacingRatio {
    fn radiance(&self, scene: &Scene, ray: Ray, _sampler: &mut Sampler) -> Vec3 {
        match scene.trace(&ray) {
            Some(s) => Vec3::splat(self.scale * s.ng.dot(-ray.dir).max(0.0)),
            None => Vec3::ZERO,
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct FacingParams {
    scale: Option<f32>,
}

struct FacingPlugin {
    passes_seen: Arc<AtomicU32>,
}

impl Plugin for FacingPlugin {
    fn name(&self) -> &str {
        "facing-ratio"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "facing",
            Box::new(|cfg| {
                let p: FacingParams = cfg.parse_params()?;
                Ok(Box::new(PerPixel::new(FacingRatio { scale: p.scale.unwrap_or(1.0) })))
            }),
        );
        let seen = self.passes_seen.clone();
        app.add_system(Stage::Accumulate, "count_passes", move |_, _| {
            seen.fetch_add(1, Ordering::Relaxed);
            Ok(())
        });
    }
}

#[test]
fn an_integrator_defined_outside_the_crate_renders_through_the_plugin_api() {
    let passes_seen = Arc::new(AtomicU32::new(0));
    let mut app = App::with(prism::DefaultPlugins);
    app.add_plugin(FacingPlugin { passes_seen: passes_seen.clone() });
    app.resources.source = SceneSource::RonText {
        text: "(camera: (eye: (0, 0, 4), fov: 30, size: (33, 33)), render: (integrator: facing(scale: 0.5), spp: 4, passes: 2),
               entities: [(shape: Sphere())])"
            .into(),
        name: PathBuf::from("plugin.ron"),
        base_dir: PathBuf::from("."),
    };
    app.run().unwrap();
    assert_eq!(passes_seen.load(Ordering::Relaxed), 2, "the plugin's Accumulate system ran once per pass");
    let img = prism::stages::film_image(&app.resources).unwrap();
    // The centre pixel looks straight at the sphere: facing ratio ~1, times the parameter 0.5.
    let c = img.get(16, 16).x;
    assert!((c - 0.5).abs() < 0.01, "centre {c}");
    assert_eq!(img.get(0, 0), Vec3::ZERO, "corner misses the sphere");
    assert!(app.plugin_names().iter().any(|n| n == "facing-ratio") && app.plugin_names().iter().any(|n| n == "phong"));
}

#[test]
fn unknown_plugin_parameters_are_rejected_with_their_position() {
    let mut app = App::with(prism::DefaultPlugins);
    app.add_plugin(FacingPlugin { passes_seen: Arc::new(AtomicU32::new(0)) });
    app.resources.source = SceneSource::RonText {
        text: "(camera: (),\n render: (integrator: facing(scael: 2)))".into(),
        name: PathBuf::from("p.ron"),
        base_dir: PathBuf::from("."),
    };
    let err = app.run().unwrap_err().to_string();
    assert!(err.starts_with("p.ron:2:") && err.contains("scael"), "{err}");
}

#[test]
fn the_schedule_runs_stages_in_the_documented_order() {
    let app = App::with(prism::DefaultPlugins);
    let order: Vec<Vec<&str>> = Stage::ALL.iter().map(|s| app.schedule().system_names(*s)).collect();
    assert_eq!(order[0], ["load_scene", "apply_scene_overrides", "check_outputs"]);
    assert_eq!(order[1], ["propagate_transforms"]);
    assert_eq!(order[2], ["build_scene"]);
    assert_eq!(order[3], ["build_lights", "prepare_integrator"]);
    assert_eq!(order[4], ["render_pass"]);
    assert_eq!(order[5], ["accumulate"]);
    assert_eq!(order[6], ["write_outputs"]);
}
