//! The core systems of the stages after Load/Propagate:
//! - BuildAccel: [`build_scene_system`] flattens the entities into primitives, builds the chosen accelerator and
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
//! save the film (complete passes only) beside the first image output, so no work is lost.

mod flatten;
mod progress;
pub mod propagate;

pub use flatten::{flatten_shapes, place_lights};
pub use progress::ProgressReporter;
pub use propagate::propagate_transforms;

use crate::Resources;
use crate::components::{Camera, WorldFromLocal};
use hecs::World;
use prism_core::accel::Accel;
use prism_core::camera::CameraRig;
use prism_core::error::{PrismError, Result};
use prism_core::film::{Film, FilmHeader, ShardAxis, read_film, write_film};
use prism_core::integrator::{PassInfo, PassOutput};
use prism_core::io::{Image, write_image};
use prism_core::lights::LightSet;
use prism_core::primitives::EntityPrims;
use prism_core::scene::Scene;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Entities with area lights and their primitive ranges, from BuildAccel to Prepare.
struct Emitters(Vec<(hecs::Entity, EntityPrims)>);

pub fn build_scene_system(world: &mut World, res: &mut Resources) -> Result<()> {
    let t0 = Instant::now();
    let camera = {
        let mut q = world.query::<(&Camera, Option<&WorldFromLocal>)>();
        let (cam, wfl) = q.iter().next().ok_or_else(|| PrismError::invalid("the scene has no camera"))?;
        CameraRig::new(cam, &wfl.map(|w| w.0).unwrap_or_default())
            .ok_or_else(|| PrismError::invalid("camera: eye, target and up do not define a view"))?
    };
    let (prims, emitters) = flatten_shapes(world, &res.meshes, &res.materials).map_err(|e| in_scene_file(res, e))?;
    if prims.skipped_degenerate > 0 {
        eprintln!("warning: skipped {} degenerate (zero-area or non-finite) mesh triangles", prims.skipped_degenerate);
    }
    let st = &res.settings;
    let samples = st.spp.map(|spp| st.width as u64 * st.height as u64 * spp as u64);
    let splits = prism_core::accel::SpatialSplits::for_samples(samples, prims.num_bounded() as u64);
    let accel = Accel::build_with(st.accel, &prims, splits)?;
    res.insert(Emitters(emitters));
    res.scene = Some(Scene {
        camera,
        prims,
        accel,
        lights: LightSet::default(),
        materials: prism_core::material::MaterialSet::new(res.materials.clone()),
        textures: res.textures.clone(),
        globals: res.globals,
        cancel: res.cancel.clone(),
    });
    res.progress.setup += t0.elapsed();
    Ok(())
}

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

pub fn build_lights_system(world: &mut World, res: &mut Resources) -> Result<()> {
    let emitters = res.get::<Emitters>().map(|e| e.0.clone()).unwrap_or_default();
    let lights = place_lights(world, &res.scene()?.prims, &emitters).map_err(|e| in_scene_file(res, e))?;
    if let Some(scene) = res.scene.as_mut() {
        scene.lights = lights;
    }
    Ok(())
}

pub fn prepare_integrator_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    let t0 = Instant::now();
    let mut integrator = res.integrators.create(&res.settings.integrator)?;
    integrator.prepare(res.scene()?, &res.settings)?;
    if res.settings.adaptive && !integrator.adapts_samples() {
        eprintln!(
            "warning: adaptive sampling has no effect with the `{}` integrator (it applies to per-pixel estimators)",
            res.settings.integrator.name
        );
    }
    let mut film = Film::new(res.settings.width, res.settings.height);
    let (k, n) = res.settings.shard;
    if n > 1 && integrator.shard_axis() == ShardAxis::Rows {
        film.rows = Some((k, n));
    }
    res.film = Some(film);
    if let Some(path) = res.resume.clone() {
        resume(res, &mut *integrator, &path)?;
    }
    res.integrator = Some(integrator);
    skip_to_own_pass(res);
    res.progress.setup += t0.elapsed();
    if res.show_progress {
        res.insert(ProgressReporter::new(&res.settings));
    }
    if res.cancel.load(Ordering::Relaxed) {
        res.progress.finished = true;
        res.progress.interrupted = true;
    }
    Ok(())
}

/// The film header describing this render's progress.
fn film_header(res: &Resources) -> FilmHeader {
    let axis = res.integrator.as_ref().map_or(ShardAxis::Passes, |i| i.shard_axis());
    FilmHeader {
        width: res.settings.width,
        height: res.settings.height,
        passes_done: res.progress.passes_done,
        passes: res.settings.passes,
        spp_done: res.progress.spp_done,
        shard: res.settings.shard,
        axis,
        fingerprint: res.settings.fingerprint(res.scene_hash),
        integrator: prism_core::settings::describe_plugin(&res.settings.integrator),
    }
}

/// Load a `.prism-film` file into the film, the progress and the integrator.
fn resume(
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
    res.film = Some(film);
    res.progress.passes_done = h.passes_done;
    res.progress.spp_done = h.spp_done;
    res.progress.spp_resumed = h.spp_done;
    if h.passes_done >= res.settings.passes {
        res.progress.finished = true;
    }
    Ok(())
}

/// Advance to the next pass this process renders (shards by passes skip the other shards' passes).
fn skip_to_own_pass(res: &mut Resources) {
    let (k, n) = res.settings.shard;
    let by_passes = res.integrator.as_ref().is_none_or(|i| i.shard_axis() == ShardAxis::Passes);
    if n > 1 && by_passes {
        let p = &mut res.progress.passes_done;
        while *p < res.settings.passes && *p % n != k {
            *p += 1;
        }
    }
    if res.progress.passes_done >= res.settings.passes {
        res.progress.finished = true;
    }
}

pub fn render_pass_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    if res.progress.finished {
        return Ok(());
    }
    let pass = res.progress.passes_done;
    let started = *res.progress.started.get_or_insert_with(Instant::now);
    let info = PassInfo {
        index: pass,
        spp: res.settings.samples_in_pass(pass),
        first_sample: res.settings.samples_before_pass(pass),
        settings: &res.settings,
    };
    let scene = res.scene.as_ref().ok_or_else(|| PrismError::invalid("no scene: the BuildAccel stage did not run"))?;
    let integrator =
        res.integrator.as_mut().ok_or_else(|| PrismError::invalid("no integrator: the Prepare stage did not run"))?;
    let cpu0 = prism_core::cpu_time::process_cpu_time();
    let out = integrator.render_pass(scene, &info, &res.cancel);
    res.progress.elapsed = started.elapsed();
    res.progress.cpu = match (res.progress.cpu, cpu0, prism_core::cpu_time::process_cpu_time()) {
        (Some(acc), Some(a), Some(b)) => Some(acc + b.saturating_sub(a)),
        _ => None,
    };
    res.pass_output = Some(out);
    Ok(())
}

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
    if res.cancel.load(Ordering::Relaxed) {
        p.finished = true;
        p.interrupted = true;
    } else if out_of_passes || out_of_time || finished_before {
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

/// Save the film (complete passes only) and the integrator's state where checkpoints go.
fn save_film(res: &Resources) -> Result<()> {
    let Some(path) = &res.film_path else { return Ok(()) };
    write_film_to(res, path)
}

fn write_film_to(res: &Resources, path: &std::path::Path) -> Result<()> {
    let film = res.film.as_ref().ok_or_else(|| PrismError::invalid("no film to write"))?;
    let state = res.integrator.as_ref().map(|i| i.save_state()).unwrap_or_default();
    write_film(path, &film_header(res), film, &state)
}

struct LastCheckpoint(Instant);

/// Whether a checkpoint is due after a pass: `every` since the last one or, before the first, since the render
/// started (`since_start`). The first comes one interval into the render, not after its first pass: a render shorter
/// than the interval writes none (its outputs are written when it finishes), and the write — images and the film,
/// one thread's work — does not stall the threads of every short render.
pub fn checkpoint_due(since_last: Option<Duration>, since_start: Duration, every: Duration) -> bool {
    since_last.unwrap_or(since_start) >= every
}

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

fn write_outputs(res: &Resources) -> Result<()> {
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
