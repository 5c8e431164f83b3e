//! The Render stage: one pass of the integrator over the render scene, timed (wall and CPU).

use crate::Resources;
use hecs::World;
use prism_core::error::{PrismError, Result};
use prism_core::integrator::PassInfo;
use std::time::Instant;

/// Render pass `progress.passes_done` into `pass_output`, adding its wall and CPU time to the progress; nothing once
/// the render is finished. Errors when BuildAccel or Prepare did not run.
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
