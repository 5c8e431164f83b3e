//! The Render stage: one pass of the integrator over the render scene, timed (wall and CPU). Under a time budget a
//! watchdog stops the pass when the budget is spent, as Ctrl-C stops it (the integrators check the same flag after
//! every sample or tile), so a render ends at its budget however large its passes.

use crate::Resources;
use hecs::World;
use prism_core::error::{PrismError, Result};
use prism_core::integrator::{Integrator, PassInfo, PassOutput};
use prism_core::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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
    let out = match res.settings.time_budget {
        Some(budget) => {
            let left = Duration::from_secs_f64((budget - started.elapsed().as_secs_f64()).max(0.0));
            render_until(&mut **integrator, scene, &info, &res.cancel, Instant::now() + left)
        }
        None => integrator.render_pass(scene, &info, &res.cancel),
    };
    res.progress.elapsed = started.elapsed();
    res.progress.cpu = match (res.progress.cpu, cpu0, prism_core::cpu_time::process_cpu_time()) {
        (Some(acc), Some(a), Some(b)) => Some(acc + b.saturating_sub(a)),
        _ => None,
    };
    res.pass_output = Some(out);
    Ok(())
}

/// Longest a watchdog sleeps between looks at the clock and at Ctrl-C.
const WATCH_STEP: Duration = Duration::from_millis(5);

/// One pass that stops at `deadline` or when `cancel` is set, whichever comes first: a watchdog thread raises the
/// flag the integrator checks, and is woken as soon as the pass ends.
fn render_until(
    integrator: &mut dyn Integrator,
    scene: &Scene,
    info: &PassInfo,
    cancel: &AtomicBool,
    deadline: Instant,
) -> PassOutput {
    let (stop, done) = (AtomicBool::new(false), AtomicBool::new(false));
    std::thread::scope(|sc| {
        let watchdog = sc.spawn(|| {
            while !done.load(Ordering::Acquire) {
                let now = Instant::now();
                if cancel.load(Ordering::Relaxed) || now >= deadline {
                    stop.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::park_timeout(WATCH_STEP.min(deadline - now));
            }
        });
        let out = integrator.render_pass(scene, info, &stop);
        done.store(true, Ordering::Release);
        watchdog.thread().unpark();
        out
    })
}
