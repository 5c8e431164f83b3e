//! The engine's plugin: the stage systems every render needs after its scene is loaded (transforms, primitives and
//! the accelerator, lights, the integrator and film, passes, outputs), in stage order. The Load stage's systems come
//! from the loaders' plugin; the integrators from theirs.

use super::{App, Plugin, Stage};

/// The engine's stage systems (everything but Load).
pub struct CorePlugin;

impl Plugin for CorePlugin {
    fn name(&self) -> &str {
        "core"
    }

    fn build(&self, app: &mut App) {
        app.add_system(Stage::Propagate, "propagate_transforms", crate::stages::propagate::propagate_transforms)
            .add_system(Stage::BuildAccel, "build_scene", crate::stages::build_scene_system)
            .add_system(Stage::Prepare, "build_lights", crate::stages::build_lights_system)
            .add_system(Stage::Prepare, "prepare_integrator", crate::stages::prepare_integrator_system)
            .add_system(Stage::Render, "render_pass", crate::stages::render_pass_system)
            .add_system(Stage::Accumulate, "accumulate", crate::stages::accumulate_system)
            .add_system(Stage::Output, "write_outputs", crate::stages::output_system);
    }
}
