//! # Prism
//!
//! A physically based CPU ray tracer built as a data-oriented ECS: scene files spawn entities (`hecs`) that carry
//! transform, shape, material and light components; scheduled systems propagate transforms, flatten shapes into
//! primitives (triangles, and analytic shapes: spheres, ellipsoids, surfaces of revolution and Bézier patches
//! intersected exactly), build an accelerator (an 8-wide BVH, obvhs's CWBVH, an SAH kd-tree, a uniform grid, or
//! brute force), prepare lights and the chosen integrator plugin (`phong`, `envlight`, `ppm`, `vcm`, `debug`), and render
//! progressive passes into an exact, mergeable HDR film written as EXR or PNG.
//!
//! This crate is the facade over the workspace, whose crate graph is the layering
//! (`core < engine < load < plugins < lab < prism`): it re-exports every crate under the paths users write
//! (`prism::scene::Scene`, `prism::app::App`, `prism::plugins::ppm`), holds the set of plugins the binary ships
//! ([`DefaultPlugins`]) and the command line ([`cli`]).
//!
//! Start with [`App`] (stages, systems, plugins), [`integrator`] (the interface plugins implement) and the book under
//! `docs/` (the scene format, the plugin reference, the architecture).

pub mod cli;
mod default_plugins;

pub use default_plugins::DefaultPlugins;

pub use prism_core::{
    PrismError, Result, accel, alpha, bsdf, camera, cpu_time, envmap, error, film, geometry, integrator, io, lights,
    limits, material, math, mesh, mesh_tangents, primitives, ron_error, sampling, scene, settings, shapes, texture,
};
pub use prism_engine::{App, Plugin, Resources, Stage, components, stages};
pub use prism_lab::{accel_bench, chart, compare, converge, fuzz, ray_file, ray_sets, report};

/// The engine: [`App`], [`Plugin`], the schedule, the resources (`prism_engine`).
pub use prism_engine as app;
/// The scene loaders (`prism_load`).
pub use prism_load as load;

/// The integrator plugins the binary ships, one crate each.
pub mod plugins {
    pub use prism_debug as debug;
    pub use prism_envlight as envlight;
    pub use prism_phong as phong;
    pub use prism_ppm as ppm;
    pub use prism_vcm as vcm;
}
