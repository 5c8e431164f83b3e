//! The loaders' plugin: the Load stage's systems, which read the scene source (RON, OBJ, PLY, glTF, pbrt, 6.837),
//! spawn its entities, resolve the render settings, and check the outputs before any work is done.

use prism_engine::{App, Plugin, Stage};

/// The Load stage: `load_scene`, `apply_scene_overrides` (`--env`, `--sky`, the view), then `check_outputs`.
pub struct LoadPlugin;

impl Plugin for LoadPlugin {
    fn name(&self) -> &str {
        "load"
    }

    fn build(&self, app: &mut App) {
        app.add_system(Stage::Load, "load_scene", super::load_scene_system)
            .add_system(Stage::Load, "apply_scene_overrides", super::scene_overrides::apply_scene_overrides)
            .add_system(Stage::Load, "check_outputs", super::check_outputs_system);
    }
}
