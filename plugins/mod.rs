//! Integrator plugins, one folder each. They are compiled as modules of the `prism` crate (so the binary has them
//! built in) but use only the public API an external crate could use: `Plugin`, `App::register_integrator`,
//! `PixelIntegrator`/`PerPixel`, `Integrator` (for multi-pass methods such as `ppm`) and the render `Scene`.

pub mod debug;
pub mod envlight;
pub mod phong;
pub mod ppm;

use crate::app::App;

/// Add every built-in integrator plugin.
pub fn add_builtin_plugins(app: &mut App) {
    app.add_plugin(phong::PhongPlugin);
    app.add_plugin(envlight::EnvlightPlugin);
    app.add_plugin(ppm::PpmPlugin);
    app.add_plugin(debug::DebugPlugin);
}
