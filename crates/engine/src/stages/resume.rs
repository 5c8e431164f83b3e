//! Saved renders: the `.prism-film` header of this render's progress, loading a saved film into the film, the
//! progress and the integrator (`--resume`), and saving it (checkpoints, interruptions, `.prism-film` outputs).

use crate::Resources;
use prism_core::error::{PrismError, Result};
use prism_core::film::{FilmHeader, ShardAxis, read_film, write_film};

/// The film header describing this render's progress.
fn film_header(res: &Resources) -> FilmHeader {
    let axis = res.integrator.as_ref().map_or(ShardAxis::Passes, |i| i.shard_axis());
    FilmHeader {
        width: res.settings.width,
        height: res.settings.height,
        passes_done: res.progress.passes_done,
        // A render the noise target ended is complete with the passes it did (so its shards merge).
        passes: if res.progress.noise_met { res.progress.passes_done } else { res.settings.passes },
        spp_done: res.progress.spp_done,
        shard: res.settings.shard,
        axis,
        fingerprint: res.settings.fingerprint(res.scene_hash),
        integrator: prism_core::settings::describe_plugin(&res.settings.integrator),
    }
}

/// Load a `.prism-film` file into the film, the progress and the integrator.
pub(super) fn resume(
    res: &mut Resources,
    integrator: &mut dyn prism_core::integrator::Integrator,
    path: &std::path::Path,
) -> Result<()> {
    let f = read_film(path)?;
    let expected = FilmHeader { passes_done: f.header.passes_done, spp_done: f.header.spp_done, ..film_header(res) };
    let h = &f.header;
    if (h.width, h.height) != (expected.width, expected.height) {
        return Err(PrismError::format(
            path,
            format!("film is {}x{}, the render {}x{}", h.width, h.height, expected.width, expected.height),
        ));
    }
    if h.integrator != expected.integrator {
        return Err(PrismError::format(
            path,
            format!("film was rendered with `{}`, not `{}`", h.integrator, expected.integrator),
        ));
    }
    if h.shard != expected.shard {
        return Err(PrismError::format(
            path,
            format!(
                "film is shard {}/{}, the render shard {}/{}",
                h.shard.0, h.shard.1, expected.shard.0, expected.shard.1
            ),
        ));
    }
    if h.fingerprint != expected.fingerprint {
        return Err(PrismError::format(
            path,
            "film was rendered from a different scene file or settings (spp, passes, size, sampler, seed ...)",
        ));
    }
    integrator.load_state(&f.state).map_err(|e| PrismError::format(path, e.to_string()))?;
    let mut film = f.film;
    film.rows = res.film.as_ref().and_then(|x| x.rows);
    if res.settings.noise.is_some() {
        film.track_noise(f.noise);
    }
    res.film = Some(film);
    res.progress.passes_done = h.passes_done;
    res.progress.spp_done = h.spp_done;
    res.progress.spp_resumed = h.spp_done;
    if h.passes_done >= res.settings.passes {
        res.progress.finished = true;
    }
    // A film that already meets the noise target renders no further pass.
    let noise = integrator.relative_error().or_else(|| res.film.as_ref().and_then(|f| f.relative_error()));
    res.progress.noise = noise;
    if res.settings.noise.is_some_and(|t| noise.is_some_and(|e| e <= t as f64)) {
        res.progress.finished = true;
        res.progress.noise_met = true;
    }
    Ok(())
}

/// Save the film (complete passes only) and the integrator's state where checkpoints go.
pub(super) fn save_film(res: &Resources) -> Result<()> {
    let Some(path) = &res.film_path else { return Ok(()) };
    write_film_to(res, path)
}

pub(super) fn write_film_to(res: &Resources, path: &std::path::Path) -> Result<()> {
    let film = res.film.as_ref().ok_or_else(|| PrismError::invalid("no film to write"))?;
    let state = res.integrator.as_ref().map(|i| i.save_state()).unwrap_or_default();
    write_film(path, &film_header(res), film, &state)
}
