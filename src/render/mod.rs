//! The core systems of the stages after Load/Propagate:
//! - BuildAccel: [`build_scene_system`] flattens the entities into primitives, builds the chosen accelerator and
//!   the camera;
//! - Prepare: [`build_lights_system`], [`prepare_integrator_system`] (instantiates the chosen integrator plugin and
//!   the film);
//! - Render: [`render_pass_system`] runs one pass of the integrator;
//! - Accumulate: [`accumulate_system`] merges it into the film, reports progress, writes checkpoints and decides
//!   whether another pass runs (pass count, time budget, cancellation);
//! - Output: [`output_system`] writes the images.

mod progress;

pub use progress::ProgressReporter;

use crate::accel::Accel;
use crate::app::Resources;
use crate::camera::CameraRig;
use crate::components::{Camera, WorldFromLocal};
use crate::error::{PrismError, Result};
use crate::film::Film;
use crate::integrator::{PassInfo, PassOutput};
use crate::io::{Image, write_image};
use crate::lights::LightSet;
use crate::primitives::{EntityPrims, Primitives};
use crate::scene::Scene;
use hecs::World;
use std::sync::atomic::Ordering;
use std::time::Instant;

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
    let (prims, emitters) = Primitives::build(world, &res.meshes, &res.materials)?;
    if prims.skipped_degenerate > 0 {
        eprintln!("warning: skipped {} degenerate (zero-area or non-finite) mesh triangles", prims.skipped_degenerate);
    }
    let accel = Accel::build(res.settings.accel, &prims)?;
    res.insert(Emitters(emitters));
    res.scene = Some(Scene {
        camera,
        prims,
        accel,
        lights: LightSet::default(),
        materials: res.materials.clone(),
        textures: res.textures.clone(),
        globals: res.globals,
    });
    res.progress.setup += t0.elapsed();
    Ok(())
}

pub fn build_lights_system(world: &mut World, res: &mut Resources) -> Result<()> {
    let emitters = res.get::<Emitters>().map(|e| e.0.clone()).unwrap_or_default();
    let scene = res.scene.as_mut().ok_or_else(|| PrismError::invalid("no scene: the BuildAccel stage did not run"))?;
    scene.lights = LightSet::build(world, &scene.prims, &emitters)?;
    Ok(())
}

pub fn prepare_integrator_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    let t0 = Instant::now();
    let mut integrator = res.integrators.create(&res.settings.integrator)?;
    integrator.prepare(res.scene()?, &res.settings)?;
    res.integrator = Some(integrator);
    res.film = Some(Film::new(res.settings.width, res.settings.height));
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

pub fn render_pass_system(_world: &mut World, res: &mut Resources) -> Result<()> {
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
    let cpu0 = crate::cpu_time::process_cpu_time();
    let out = integrator.render_pass(scene, &info, &res.cancel);
    res.progress.elapsed = started.elapsed();
    res.progress.cpu = match (res.progress.cpu, cpu0, crate::cpu_time::process_cpu_time()) {
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
    film.merge(&out);
    let complete = match &out {
        PassOutput::Samples(tiles) => tiles.len() == crate::integrator::tiles(film.width, film.height).len(),
        PassOutput::Estimate { complete, .. } => *complete,
    };
    let p = &mut res.progress;
    if complete {
        p.spp_done += res.settings.samples_in_pass(p.passes_done) as u64;
        p.passes_done += 1;
    }
    let s = &res.settings;
    let elapsed = p.elapsed.as_secs_f64();
    let out_of_passes = p.passes_done >= s.passes;
    let out_of_time = s.time_budget.is_some_and(|t| elapsed >= t);
    if res.cancel.load(Ordering::Relaxed) {
        p.finished = true;
        p.interrupted = true;
    } else if out_of_passes || out_of_time {
        p.finished = true;
    }
    let (passes_done, spp_done, finished) = (p.passes_done, p.spp_done, p.finished);
    if let Some(bar) = res.get::<ProgressReporter>() {
        bar.update(passes_done, spp_done, elapsed);
    }
    // Checkpoint: keep what was rendered on disk while long renders run.
    if !finished
        && let Some(every) = res.checkpoint_every
        && res.get::<LastCheckpoint>().is_none_or(|c| c.0.elapsed() >= every)
    {
        write_outputs(res)?;
        res.insert(LastCheckpoint(Instant::now()));
    }
    Ok(())
}

struct LastCheckpoint(Instant);

pub fn output_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    if let Some(bar) = res.get::<ProgressReporter>() {
        bar.finish();
    }
    write_outputs(res)
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
        write_image(path, &img, res.settings.exposure)?;
    }
    Ok(())
}
