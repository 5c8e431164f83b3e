//! The Output stage: the images written (and, for an interrupted render, the film that resumes it; a completed
//! render's stale checkpoint film removed).

use super::ProgressReporter;
use super::accumulate::LastCheckpoint;
use super::resume::{save_film, write_film_to};
use crate::Resources;
use hecs::World;
use prism_core::error::{PrismError, Result};
use prism_core::io::{Image, write_image};

/// Write the image outputs; then save the film of an interrupted render (for `--resume`), or remove a completed
/// render's checkpoint film.
pub fn output_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    if let Some(bar) = res.get::<ProgressReporter>() {
        bar.finish();
    }
    write_outputs(res)?;
    if res.progress.interrupted {
        // Nothing is lost: the film resumes with `--resume`.
        save_film(res)?;
    } else if let Some(path) = &res.film_path
        && res.get::<LastCheckpoint>().is_some()
        && !res.outputs.iter().any(|o| o == path)
    {
        // A checkpoint's film is stale once the render completes.
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// The film's current image.
pub fn film_image(res: &Resources) -> Option<Image> {
    res.film.as_ref().map(|f| Image::new(f.width, f.height, f.image()))
}

pub(super) fn write_outputs(res: &Resources) -> Result<()> {
    if res.outputs.is_empty() {
        return Ok(());
    }
    let img = film_image(res).ok_or_else(|| PrismError::invalid("no film to write"))?;
    for path in &res.outputs {
        if prism_core::io::is_film_path(path) {
            write_film_to(res, path)?;
        } else {
            write_image(path, &img, res.settings.exposure)?;
        }
    }
    Ok(())
}
