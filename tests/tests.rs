//! Prism's test suite: one binary, one module per kind of evidence (DESIGN section 5).
//! Each test names the physics or the contract it checks.

mod common;

mod accel;
mod analytic;
mod appearance;
mod converge;
mod debug;
mod determinism;
mod envlight;
mod envmap;
mod geometry;
mod io;
mod lights;
mod microfacet;
mod mit6837;
mod mit6837_solid;
mod plugin;
mod ppm;
mod report;
mod resume;
mod samplers;
mod sampling;
mod scenes;
mod stability;
