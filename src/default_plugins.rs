//! The plugins the `prism` binary ships: the engine's stage systems, the scene loaders and every built-in integrator
//! (`phong`, `envlight`, `ppm`, `vcm`, `debug`). It lives at the top of the crate graph, so the engine names no plugin.

use prism_engine::{App, CorePlugin, Plugin};

/// Every built-in plugin: `App::with(DefaultPlugins)` renders any scene the binary renders.
pub struct DefaultPlugins;

impl Plugin for DefaultPlugins {
    fn name(&self) -> &str {
        "default"
    }

    fn build(&self, app: &mut App) {
        app.add_plugin(CorePlugin);
        app.add_plugin(prism_load::LoadPlugin);
        app.add_plugin(prism_phong::PhongPlugin);
        app.add_plugin(prism_envlight::EnvlightPlugin);
        app.add_plugin(prism_ppm::PpmPlugin);
        app.add_plugin(prism_vcm::VcmPlugin);
        app.add_plugin(prism_debug::DebugPlugin);
    }
}
