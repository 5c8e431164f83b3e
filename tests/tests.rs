//! Prism's test suite: one binary, one module per kind of evidence (DESIGN section 5).
//! Each test names the physics or the contract it checks.

mod common;

mod accel;
mod analytic;
mod converge;
mod curve_stability;
mod curves;
mod debug;
mod determinism;
mod envlight;
mod envmap;
mod geometry;
mod io;
mod mit6837;
mod patch_stability;
mod plugin;
mod sampling;
mod scenes;
mod stability;
