//! Prism's test suite: one binary, one module per kind of evidence (DESIGN section 5).
//! Each test names the physics or the contract it checks.

mod common;

mod accel;
mod accel_cli;
mod adaptive;
mod analytic;
mod appearance;
mod bitterli;
mod bvh_build;
mod bvh_traversal;
mod clear_shadows;
mod converge;
mod curve_stability;
mod curves;
mod debug;
mod determinism;
mod docs;
mod envlight;
mod envmap;
mod exactness;
mod examples;
mod fuzz_replay;
mod geometry;
mod hostile;
mod import_gltf;
mod import_pbrt;
mod import_ply;
mod io;
mod layers;
mod lights;
mod microfacet;
mod mit6837;
mod mit6837_solid;
mod patch_stability;
mod plugin;
mod ppm;
mod reliability;
mod reliability_work;
mod report;
mod resume;
mod samplers;
mod sampling;
mod scenes;
mod stability;
mod untrusted_formats;
