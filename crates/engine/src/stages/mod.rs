//! The engine's stage systems, one file per stage after Load (whose systems the loaders' plugin adds):
//! - Propagate: [`propagate_transforms`] composes nested transforms (`propagate.rs`);
//! - BuildAccel: [`build_scene_system`] flattens the entities into primitives (`flatten.rs`), builds the chosen accelerator and
//!   the camera;
//! - Prepare: [`build_lights_system`], [`prepare_integrator_system`] (instantiates the chosen integrator plugin and
//!   the film);
//! - Render: [`render_pass_system`] runs one pass of the integrator;
//! - Accumulate: [`accumulate_system`] merges it into the film, reports progress, writes checkpoints and decides
//!   whether another pass runs (pass count, time budget, cancellation);
//! - Output: [`output_system`] writes the images.
//!
//! Shards and resumes (`--shard K/N`, `--resume F`, `.prism-film` outputs): a shard renders the passes `p % N == K`
//! (or, for integrators that shard by pixel rows, every pass for the rows `y % N == K`); a resumed render loads the
//! film, its progress and the integrator's state, then continues with the next pass. Checkpoints and interruptions
//! save the film (complete passes only) beside the first image output, so no work is lost (`resume.rs`).

mod accumulate;
mod build;
mod flatten;
mod output;
mod prepare;
mod progress;
pub mod propagate;
mod render;
mod resume;

pub use accumulate::{accumulate_system, checkpoint_due};
pub use build::build_scene_system;
pub use flatten::{flatten_shapes, place_lights};
pub use output::{film_image, output_system};
pub use prepare::{build_lights_system, prepare_integrator_system};
pub use progress::ProgressReporter;
pub use propagate::propagate_transforms;
pub use render::render_pass_system;

use crate::Resources;
use prism_core::error::PrismError;

/// A scene error raised after Load names an entity but not the file: prefix the scene file's name.
pub fn in_scene_file(res: &Resources, e: PrismError) -> PrismError {
    let file = match &res.source {
        crate::SceneSource::File(p) => p.display().to_string(),
        crate::SceneSource::RonText { name, .. } => name.display().to_string(),
        crate::SceneSource::Prebuilt => return e,
    };
    match e {
        PrismError::Scene { context, message } if !context.starts_with(&file) => {
            PrismError::Scene { context: format!("{file}: {context}"), message }
        }
        other => other,
    }
}
