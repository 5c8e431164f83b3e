//! A custom integrator plugin, end to end: ambient occlusion, `ao(distance: D)`.
//!
//! An integrator plugin is two things: an estimator of the radiance along one camera ray ([`PixelIntegrator`]),
//! and a [`Plugin`] that registers it under a name with a factory that parses its parameters. Wrapped in
//! [`PerPixel`], the estimator renders in parallel tiles with deterministic per-pixel random numbers from the
//! chosen sampler, the pixel filter, adaptive sampling, shards and resumes — all without code of its own. The
//! built-in plugins (`plugins/phong`, `plugins/envlight`, `plugins/ppm`, `plugins/debug`) are made the same way,
//! one crate each, depending on `prism-core` and `prism-engine` only.
//!
//! Ambient occlusion: at the first hit, one cosine-distributed direction about the shading normal (turned towards
//! the viewer); the sample is 1 when nothing lies within `distance` that way, 0 otherwise. Its mean is the
//! cosine-weighted fraction of the hemisphere left open: exactly 1 on an unoccluded plane.
//!
//! ```sh
//! cargo run --release --example custom_integrator -- scenes/cornell_box.ron ao.png
//! ```
//!
//! `tests/examples.rs` renders with it and checks both the open plane and an occluded point.

use glam::Vec3;
use prism::app::{App, Plugin, SceneSource};
use prism::geometry::Ray;
use prism::integrator::{PerPixel, PixelIntegrator};
use prism::math::Frame;
use prism::sampling::Sampler;
use prism::sampling::warp::cosine_hemisphere;
use prism::scene::Scene;
use prism::{DefaultPlugins, PrismError, Result};
use serde::Deserialize;
use std::path::PathBuf;

/// The parameters the scene (`integrator: ao(distance: 0.5)`) or `--integrator 'ao(distance: 0.5)'` gives.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields, default)]
pub struct AoParams {
    /// How far an occluder counts, in scene units.
    pub distance: f32,
}

impl Default for AoParams {
    fn default() -> Self {
        AoParams { distance: 1.0 }
    }
}

/// The estimator: one occlusion ray per camera sample.
pub struct AmbientOcclusion {
    distance: f32,
}

impl PixelIntegrator for AmbientOcclusion {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let Some(s) = scene.trace(&ray) else {
            return Vec3::ZERO;
        };
        // Every random number comes from the sampler, in a fixed order: here one 2D point per sample.
        let n = if s.ns.dot(ray.dir) < 0.0 { s.ns } else { -s.ns };
        let dir = Frame::from_normal(n).to_world(cosine_hemisphere(sampler.next_2d()));
        // `spawn` offsets the origin off the surface by the hit point's error bound: no self-occlusion.
        let probe = Ray { tmax: self.distance, ..s.spawn(dir) };
        if scene.occluded(&probe) { Vec3::ZERO } else { Vec3::ONE }
    }
}

/// The plugin: registers `ao`.
pub struct AoPlugin;

impl Plugin for AoPlugin {
    fn name(&self) -> &str {
        "ao"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "ao",
            Box::new(|cfg| {
                // Unknown or mistyped parameters are errors at their file:line:column.
                let p: AoParams = cfg.parse_params()?;
                if p.distance.is_nan() || p.distance <= 0.0 {
                    return Err(PrismError::invalid(format!("ao: distance must be positive, got {}", p.distance)));
                }
                Ok(Box::new(PerPixel::new(AmbientOcclusion { distance: p.distance })))
            }),
        );
    }
}

/// An app that renders `scene` with `ao(distance: 0.5)`: the binary's plugins plus this one.
pub fn ao_app(scene: SceneSource) -> App {
    let mut app = App::with(DefaultPlugins);
    app.add_plugin(AoPlugin);
    app.resources.source = scene;
    app.resources.overrides.integrator = Some("ao(distance: 0.5)".into());
    app
}

#[allow(dead_code)]
fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let scene = args.next().unwrap_or_else(|| "scenes/cornell_box.ron".into());
    let output = args.next().unwrap_or_else(|| "ao.png".into());
    let mut app = ao_app(SceneSource::File(PathBuf::from(scene)));
    app.resources.outputs = vec![PathBuf::from(&output)];
    app.run()?;
    println!("wrote {output}");
    Ok(())
}
