//! Integrator plugins, one folder each. They are compiled as modules of the `prism` crate (so the binary has them
//! built in) but use only the public API an external crate could use: `Plugin`, `App::register_integrator`,
//! `PixelIntegrator`/`PerPixel`, `Integrator` (for multi-pass methods such as `ppm`) and the render `Scene`.

pub mod debug;
pub mod envlight;
pub mod phong;
pub mod ppm;
