//! The Prepare stage: the lights resolved to world space, the chosen integrator instantiated and prepared, the
//! film made (resumed from a `.prism-film` file when asked), and the first pass this process renders found.

use super::build::Emitters;
use super::resume::resume;
use super::{ProgressReporter, in_scene_file, place_lights};
use crate::Resources;
use hecs::World;
use prism_core::error::Result;
use prism_core::film::{Film, ShardAxis};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Resolve the scene's lights to world space (area lights over the primitives BuildAccel recorded) into the render
/// scene.
pub fn build_lights_system(world: &mut World, res: &mut Resources) -> Result<()> {
    let emitters = res.get::<Emitters>().map(|e| e.0.clone()).unwrap_or_default();
    let lights = place_lights(world, &res.scene()?.prims, &emitters).map_err(|e| in_scene_file(res, e))?;
    if let Some(scene) = res.scene.as_mut() {
        scene.lights = lights;
    }
    Ok(())
}

/// Instantiate and prepare the chosen integrator, make the film (row-sharded where the integrator shards by rows),
/// resume it from `resume` when given, skip to this process's first pass and create the progress bar.
pub fn prepare_integrator_system(_world: &mut World, res: &mut Resources) -> Result<()> {
    let t0 = Instant::now();
    let mut integrator = res.integrators.create(&res.settings.integrator)?;
    if res.settings.spp.is_none() {
        res.settings.pass_spp = integrator.samples_per_timed_pass(res.settings.pass_spp).max(1);
    }
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
    if res.settings.noise.is_some() {
        film.track_noise(None);
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

/// Advance to the next pass this process renders (shards by passes skip the other shards' passes).
pub(super) fn skip_to_own_pass(res: &mut Resources) {
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
