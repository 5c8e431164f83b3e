//! `prism watch SCENE [render flags] [--port N]`: render progressively into a viewer page served on 127.0.0.1, and
//! start again whenever the scene or a file it reads changes.
//!
//! The render loop (this thread): load the scene and set it up, then run passes, publishing the image after each
//! (`view.rs`) with the film's noise estimate (`prism_core::film::noise`), until the render's limits end it
//! (samples, time, noise target, as `prism render`) or a file changes. A change cancels the pass in flight (the
//! watcher raises the render's cancel flag: `files.rs`); after `DEBOUNCE` without another change the scene is
//! loaded again from scratch but for what `prism_engine::reload_cache` keeps: mesh files that did not change are
//! not read again, and the accelerator is not built again when the world-space geometry is the same (a camera,
//! material or light edit). Passes hold 4 samples unless `--passes` says otherwise, for a first image soon after
//! the save (the image does not depend on the passes). A scene that fails to load leaves the last good image on the
//! page with the error line over it (and on the terminal), and the files it read so far stay watched. Outputs are
//! written only when `-o` asks for them, when a render ends undisturbed: the same bytes `prism render` writes with
//! the same flags.
//!
//! Parameters: `--port` (default 8917; 0 picks a free one). The page's address is printed on stderr.

mod files;
mod server;
mod view;

use super::render_cmd::{RenderArgs, overrides};
use clap::Args;
use prism_core::error::PrismError;
use prism_engine::reload_cache::ReloadCache;
use prism_engine::{App, SceneSource, Stage};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};
use view::{Frame, Shared};

/// How long the files must stay unchanged after a change before the scene is loaded again (editors write a file
/// in several steps).
const DEBOUNCE: Duration = Duration::from_millis(30);

/// Samples per pixel of a watch render's passes when `--passes` is not given.
const WATCH_PASS_SPP: u32 = 4;

#[derive(Args, Debug, Clone)]
pub struct WatchArgs {
    #[command(flatten)]
    pub render: RenderArgs,
    /// Port of the viewer page on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8917)]
    pub port: u16,
}

pub fn run(args: WatchArgs) -> anyhow::Result<()> {
    let r = &args.render;
    if r.shard.is_some() || r.resume.is_some() {
        return Err(PrismError::invalid("prism watch: --shard and --resume are for `prism render`").into());
    }
    if !r.allow_read.is_empty() {
        prism_core::io::restrict_reads(&r.allow_read)?;
    }
    if let Some(t) = r.threads {
        prism_core::limits::threads(t)?;
    }
    let o = overrides(r)?;
    let shared = Arc::new(Shared::default());
    shared.update(|v| {
        v.status = "loading";
        v.scene = r.scene.display().to_string();
    });
    let (srv, addr) = server::bind(args.port)?;
    eprintln!("prism watch: {} at http://{addr}/ (Ctrl-C stops)", r.scene.display());
    let s = shared.clone();
    std::thread::spawn(move || server::serve(srv, s));
    ctrlc::set_handler(|| std::process::exit(130)).map_err(|e| anyhow::anyhow!("prism watch: {e}"))?;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = r.threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build().map_err(|e| PrismError::invalid(format!("cannot start the threads: {e}")))?;
    let mut watcher = files::FileWatcher::new()?;
    watcher.watch(std::slice::from_ref(&r.scene));
    let mut since: Option<Instant> = None;
    let mut cache = ReloadCache::default();
    pool.install(|| {
        loop {
            let restarted = since.take();
            cache = render_once(r, &o, &shared, &mut watcher, cache, restarted);
            // Wait for a change, then for the files to settle.
            let first = loop {
                if let Some(first) = settled(&watcher.changes) {
                    break first;
                }
                std::thread::sleep(Duration::from_millis(5));
            };
            since = Some(first);
        }
    })
}

/// The first change of a burst once `DEBOUNCE` has passed since its last one (taking it); `None` before.
fn settled(changes: &files::Changes) -> Option<Instant> {
    let last = changes.last()?;
    if last.elapsed() < DEBOUNCE {
        return None;
    }
    changes.take().map(|(first, _)| first)
}

/// Load the scene and render it until its limits or a change end the render; what the next load can reuse.
fn render_once(
    args: &RenderArgs,
    o: &prism_core::settings::Overrides,
    shared: &Shared,
    watcher: &mut files::FileWatcher,
    cache: ReloadCache,
    restarted: Option<Instant>,
) -> ReloadCache {
    let mut app = App::with(crate::DefaultPlugins);
    app.resources.insert(cache);
    let loaded = render_app(&mut app, args, o, shared, watcher, restarted);
    let accel = app.resources.scene.take().map(|s| s.accel);
    let mut cache = app.resources.remove::<ReloadCache>().unwrap_or_default();
    cache.finish(accel, loaded);
    cache
}

/// [`render_once`] with the app made: false when the scene did not load.
fn render_app(
    app: &mut App,
    args: &RenderArgs,
    o: &prism_core::settings::Overrides,
    shared: &Shared,
    watcher: &mut files::FileWatcher,
    restarted: Option<Instant>,
) -> bool {
    let quiet = args.quiet;
    let hits = |app: &App| app.resources.get::<ReloadCache>().map(|c| c.hits).unwrap_or_default();
    let before = hits(app);
    let cancel = Arc::new(AtomicBool::new(false));
    watcher.changes.set_cancel(cancel.clone());
    let res = &mut app.resources;
    res.source = SceneSource::File(args.scene.clone());
    res.overrides = o.clone();
    res.outputs = args.output.clone();
    res.cancel = cancel;
    shared.update(|v| v.status = "loading");
    let setup = app.run_stage(Stage::Load).and_then(|()| {
        // Small passes, for a first image soon after a save: the image does not depend on how the samples are
        // split into passes (adaptive sampling's pilot excepted).
        let s = &mut app.resources.settings;
        if let (None, Some(spp), false) = (o.passes, s.spp, s.adaptive) {
            s.passes = s.passes.max(spp / WATCH_PASS_SPP).max(1);
        }
        [Stage::Propagate, Stage::BuildAccel, Stage::Prepare].into_iter().try_for_each(|st| app.run_stage(st))
    });
    // Watch what this load read; after a failure, also what the last loads read (the failed one stopped part way).
    let mut files: Vec<PathBuf> = vec![args.scene.clone()];
    files.extend(app.resources.inputs.iter().cloned());
    if setup.is_ok() {
        watcher.watch(&files);
    } else {
        watcher.watch_more(&files);
    }
    if let Err(e) = setup {
        let line = prism_core::error::printable(&format!("{}", in_scene(&args.scene, e)));
        eprintln!("error: {line}");
        shared.update(|v| {
            v.error = Some(line);
            v.status = "error";
        });
        return false;
    }
    // The viewer shows the noise estimate whether or not the render has a target.
    if let Some(f) = app.resources.film.as_mut()
        && f.noise_halves().is_none()
    {
        f.track_noise(None);
    }
    shared.update(|v| {
        v.error = None;
        v.status = "rendering";
    });
    let mut first_pass = true;
    while !app.resources.progress.finished {
        let step = app.run_stage(Stage::Render).and_then(|()| app.run_stage(Stage::Accumulate));
        if let Err(e) = step {
            let line = prism_core::error::printable(&e.to_string());
            eprintln!("error: {line}");
            shared.update(|v| {
                v.error = Some(line);
                v.status = "error";
            });
            return true;
        }
        let p = &app.resources.progress;
        if p.interrupted {
            return true;
        }
        publish(app, shared);
        if first_pass {
            first_pass = false;
            if let Some(t) = restarted
                && !quiet
            {
                let now = hits(app);
                eprintln!(
                    "prism watch: reloaded; first pass {:.3} s after the change (mesh files reused: {}, accelerator {})",
                    t.elapsed().as_secs_f64(),
                    now.mesh_files - before.mesh_files,
                    if now.accels > before.accels { "reused" } else { "built" }
                );
            }
        }
    }
    if !app.resources.outputs.is_empty()
        && let Err(e) = app.run_stage(Stage::Output)
    {
        eprintln!("error: {}", prism_core::error::printable(&e.to_string()));
    }
    shared.update(|v| v.status = "done");
    if !quiet {
        let p = &app.resources.progress;
        eprintln!("prism watch: done, {} spp in {:.3} s", p.spp_done, p.elapsed.as_secs_f64());
    }
    true
}

/// An error raised after Load names an entity but not the file: prefix the scene file's name.
fn in_scene(scene: &std::path::Path, e: PrismError) -> PrismError {
    match e {
        PrismError::Scene { context, message } if !context.contains(&scene.display().to_string()) => {
            PrismError::Scene { context: format!("{}: {context}", scene.display()), message }
        }
        other => other,
    }
}

/// The film after a pass, to the viewer.
fn publish(app: &App, shared: &Shared) {
    let res = &app.resources;
    let Some(film) = res.film.as_ref() else { return };
    let image = film.image();
    let frame = Frame {
        width: film.width,
        height: film.height,
        rgb: image.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
        counts: film.parts().1.iter().map(|&c| c.min(u32::MAX as u64) as u32).collect(),
        pass: res.progress.passes_done,
        spp: res.progress.spp_done,
        seconds: res.progress.elapsed.as_secs_f64(),
        noise: res.progress.noise.or_else(|| film.relative_error()),
        exposure: res.settings.exposure,
    };
    shared.update(|v| v.frame = Some(Arc::new(frame)));
}
