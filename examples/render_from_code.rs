//! Build a scene in code and render it: no scene file, the same entities a RON file would spawn.
//!
//! The scene is the white furnace: a diffuse sphere of albedo `a` inside a uniform environment of radiance 1. A
//! convex object never sees itself, so every pixel it covers is exactly `a` (and the sky around it 1) — a result
//! `tests/examples.rs` checks on this very scene.
//!
//! ```sh
//! cargo run --release --example render_from_code -- furnace.exr
//! ```
//!
//! Entities carry only the components they use: a `Shape` and a `MaterialId` for the sphere, a `Light` for the
//! sky, a `Camera`. Materials go into `resources.materials` (the `MaterialId` indexes it). `SceneSource::Prebuilt`
//! tells the Load stage that the world is already filled, so it only resolves the render settings.

use glam::Vec3;
use prism::app::{App, SceneSource};
use prism::components::{Camera, Light, MaterialId, Name, Projection, Shape};
use prism::material::Material;
use prism::{DefaultPlugins, Result};
use std::path::PathBuf;

/// An app holding the furnace scene: a sphere of `albedo`, seen by a `size` x `size` camera, rendered by
/// `envlight` with `spp` samples per pixel.
pub fn furnace_app(albedo: f32, size: u32, spp: u32) -> App {
    let mut app = App::with(DefaultPlugins);
    let res = &mut app.resources;
    res.source = SceneSource::Prebuilt;
    res.materials.push(Material::lambert("grey", Vec3::splat(albedo)));
    let world = &mut app.world;
    world.spawn((Name("ball".into()), Shape::Sphere { center: Vec3::ZERO, radius: 1.0 }, MaterialId(0)));
    world.spawn((Name("sky".into()), Light::Environment { radiance: Vec3::ONE, map: None }));
    world.spawn((
        Name("camera".into()),
        Camera {
            eye: Vec3::new(0.0, 0.0, 4.0),
            target: Vec3::ZERO,
            projection: Projection::Perspective { fov_y: 40.0 },
            width: size,
            height: size,
            ..Camera::default()
        },
    ));
    res.overrides.integrator = Some("envlight".into());
    res.overrides.spp = Some(spp);
    app
}

#[allow(dead_code)]
fn main() -> Result<()> {
    let output = std::env::args().nth(1).unwrap_or_else(|| "furnace.exr".into());
    let mut app = furnace_app(0.5, 128, 16);
    app.resources.outputs = vec![PathBuf::from(&output)];
    app.run()?;
    println!("wrote {output}: the sphere is 0.5 wherever it covers a pixel, the sky 1");
    Ok(())
}
