//! The Accumulate stage: the pass merged into the film, progress reported, checkpoints written, and the decision
//! whether another pass runs (pass count, time budget, noise target, cancellation).

use super::ProgressReporter;
use super::output::write_outputs;
use super::prepare::skip_to_own_pass;
use super::resume::save_film;
use crate::Resources;
use hecs::World;
use prism_core::error::{PrismError, Result};
use prism_core::integrator::PassOutput;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Merge `pass_output` into the film (committed only when the pass is complete), advance the progress to this
/// process's next pass, mark the render finished (passes done, time budget crossed, or cancelled: interrupted),
/// update the progress bar and write a checkpoint when one is due. Errors on a tile outside the film.
pub fn accumulate_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    let Some(out) = res.pass_output.take() else {
        return Ok(());
    };
    let film = res.film.as_mut().ok_or_else(|| PrismError::invalid("no film: the Prepare stage did not run"))?;
    if let PassOutput::Samples(tiles) = &out
        && let Some(t) = tiles.iter().find(|t| !t.fits(film.width, film.height))
    {
        return Err(PrismError::invalid(format!(
            "integrator `{}` returned a malformed tile at ({}, {}) size {}x{} with {} sums and {} counts",
            res.settings.integrator.name,
            t.tile.x0,
            t.tile.y0,
            t.tile.w,
            t.tile.h,
            t.sums.len(),
            t.counts.len()
        )));
    }
    let complete = match &out {
        PassOutput::Samples(tiles) => tiles.len() == prism_core::film::tiles(film.width, film.height).len(),
        PassOutput::Estimate { complete, .. } => *complete,
    };
    film.merge(&out, complete);
    let p = &mut res.progress;
    if complete {
        p.spp_done += res.settings.samples_in_pass(p.passes_done) as u64;
        p.passes_done += 1;
    }
    skip_to_own_pass(res);
    let p = &mut res.progress;
    let s = &res.settings;
    let elapsed = p.elapsed.as_secs_f64();
    let out_of_passes = p.passes_done >= s.passes;
    let finished_before = p.finished;
    let out_of_time = s.time_budget.is_some_and(|t| elapsed >= t);
    // The noise target is checked after complete passes only (a pass cut short adds nothing to the film).
    let mut quiet_enough = false;
    if let Some(target) = s.noise
        && complete
    {
        let film = res.film.as_ref();
        let estimate = res.integrator.as_ref().and_then(|i| i.relative_error()).or_else(|| film?.relative_error());
        p.noise = estimate;
        quiet_enough = estimate.is_some_and(|e| e <= target as f64);
        p.noise_met |= quiet_enough;
    }
    // A noise target without a sample count or time budget still ends.
    let out_of_samples = s.spp.is_none() && s.time_budget.is_none() && p.spp_done >= MAX_NOISE_SPP;
    if res.cancel.load(Ordering::Relaxed) {
        p.finished = true;
        p.interrupted = true;
    } else if out_of_passes || out_of_time || quiet_enough || out_of_samples || finished_before {
        p.finished = true;
    }
    let (passes_done, spp_done, finished) = (p.passes_done, p.spp_done, p.finished);
    if let Some(bar) = res.get::<ProgressReporter>() {
        let note = res.integrator.as_ref().and_then(|i| i.status());
        bar.update(passes_done, spp_done, elapsed, note.as_deref());
    }
    // Checkpoint: keep what was rendered on disk (images and the resumable film) while long renders run.
    if !finished
        && let Some(every) = res.checkpoint_every
        && checkpoint_due(res.get::<LastCheckpoint>().map(|c| c.0.elapsed()), res.progress.elapsed, every)
    {
        write_outputs(res)?;
        save_film(res)?;
        res.insert(LastCheckpoint(Instant::now()));
    }
    Ok(())
}

pub(super) struct LastCheckpoint(Instant);

/// Most samples per pixel a render with a noise target and neither a sample count nor a time budget takes.
pub const MAX_NOISE_SPP: u64 = 1 << 16;

/// Whether a checkpoint is due after a pass: `every` since the last one or, before the first, since the render
/// started (`since_start`). The first comes one interval into the render, not after its first pass: a render shorter
/// than the interval writes none (its outputs are written when it finishes), and the write — images and the film,
/// one thread's work — does not stall the threads of every short render.
pub fn checkpoint_due(since_last: Option<Duration>, since_start: Duration, every: Duration) -> bool {
    since_last.unwrap_or(since_start) >= every
}
