//! # Prism
//!
//! A physically based CPU ray tracer built as a data-oriented ECS: scene files spawn entities (`hecs`) that carry
//! transform, shape, material and light components; scheduled systems propagate transforms, flatten shapes into
//! primitives (triangles, and analytic shapes in [`shapes`]: spheres, ellipsoids, surfaces of revolution and
//! Bézier patches intersected exactly), build an accelerator (BVH via obvhs, SAH kd-tree, uniform grid, or brute
//! force), prepare lights and the chosen integrator plugin (`phong`, `envlight`, `debug`), and render progressive
//! passes into a linear HDR film written as EXR or PNG.
//!
//! Start with [`app::App`] (stages, systems, plugins), [`integrator`] (the interface plugins implement) and the
//! scene format in the README.

pub mod accel;
pub mod alpha;
pub mod app;
pub mod bsdf;
pub mod camera;
pub mod chart;
pub mod cli;
pub mod compare;
pub mod components;
pub mod converge;
pub mod cpu_time;
mod default_plugins;
pub mod envmap;
pub mod error;
pub mod film;
pub mod fuzz;
pub mod geometry;
pub mod integrator;
pub mod io;
pub mod lights;
pub mod limits;
pub mod load;
pub mod material;
pub mod math;
pub mod mesh;
pub mod mesh_tangents;
pub mod primitives;
pub mod propagate;
pub mod render;
pub mod report;
pub mod ron_error;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod shapes;
pub mod texture;

#[path = "../plugins/mod.rs"]
pub mod plugins;

pub use app::{App, Plugin, Resources, Stage};
pub use default_plugins::DefaultPlugins;
pub use error::{PrismError, Result};
