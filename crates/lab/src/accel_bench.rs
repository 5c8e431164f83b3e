//! Measuring accelerators (`prism bench`, `prism report`): for one scene and a list of accelerator kinds, the
//! build time (the fastest of the builds done in `min / 2`), the structure's memory and node/cell count, and
//! throughput in Mrays/s for camera rays and diffuse bounce rays (closest hit) and shadow rays (occlusion), from the
//! ray sets of `ray_sets.rs`. Traversal is timed interleaved: round after round, every accelerator traces every ray
//! set once, until each (accelerator, ray set) has had about `min`; each number is the fastest pass. A machine whose
//! speed drifts (other jobs, frequency changes) then slows every accelerator alike, so the ratios between the
//! accelerators of one scene are measured in the same run. Brute force is skipped above `brute_limit` primitives.

use crate::chart::{Chart, Series};
use crate::ray_file::RaySetFile;
use crate::ray_sets::{camera_rays, secondary_rays};
use prism_core::accel::Accel;
use prism_core::error::{PrismError, Result};
use prism_core::geometry::Ray;
use prism_core::primitives::Primitives;
use prism_core::settings::{AccelKind, Overrides};
use prism_engine::{App, Plugin, SceneSource};
use rayon::prelude::*;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// One accelerator on one scene.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub scene: String,
    pub prims: u32,
    pub accel: &'static str,
    pub build_ms: f64,
    pub memory_bytes: usize,
    pub nodes: usize,
    pub camera_mrays: f64,
    pub secondary_mrays: f64,
    pub shadow_mrays: f64,
    pub detail: String,
}

/// What to measure on each scene.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub kinds: Vec<AccelKind>,
    /// Camera rays: one per pixel of a `size x size` image of the scene's camera.
    pub size: u32,
    /// Minimum measuring time per number.
    pub min: Duration,
    /// Skip brute force above this many primitives.
    pub brute_limit: u32,
    /// Also write the scene's triangles, ray sets and BVH hits to `DIR/STEM.prism-rays`.
    pub export_rays: Option<PathBuf>,
}

/// Seconds of the fastest pass of each accelerator over each ray set (camera and bounce rays: closest hit; shadow
/// rays: occlusion), passes interleaved round by round (see the module doc); at least three rounds. Returns Mrays/s
/// per accelerator and ray set (0 for an empty set).
pub fn interleaved_best(accels: &[Accel], prims: &Primitives, sets: [&[Ray]; 3], min: Duration) -> Vec<[f64; 3]> {
    let pass = |accel: &Accel, set: usize| {
        let rays = sets[set];
        let t = Instant::now();
        let hits: usize = rays
            .par_chunks(256)
            .map(|c| {
                c.iter()
                    .filter(|r| if set == 2 { accel.occluded(prims, r) } else { accel.intersect(prims, r).is_some() })
                    .count()
            })
            .sum();
        black_box(hits);
        t.elapsed()
    };
    let mut best = vec![[Duration::MAX; 3]; accels.len()];
    let mut spent = vec![[Duration::ZERO; 3]; accels.len()];
    let mut rounds = 0;
    // Empty ray sets (a camera that sees nothing has no bounce or shadow rays) are never timed, so they must not
    // keep the loop going.
    let wanting =
        |spent: &[[Duration; 3]]| spent.iter().any(|s| (0..3).any(|set| !sets[set].is_empty() && s[set] < min));
    while rounds < 3 || wanting(&spent) {
        for (a, accel) in accels.iter().enumerate() {
            for set in 0..3 {
                if sets[set].is_empty() || (rounds >= 3 && spent[a][set] >= min) {
                    continue;
                }
                let t = pass(accel, set);
                best[a][set] = best[a][set].min(t);
                spent[a][set] += t;
            }
        }
        rounds += 1;
        if sets.iter().all(|s| s.is_empty()) {
            break;
        }
    }
    best.iter()
        .map(|b| {
            std::array::from_fn(|set| {
                if sets[set].is_empty() { 0.0 } else { sets[set].len() as f64 / b[set].as_secs_f64() / 1e6 }
            })
        })
        .collect()
}

/// Build `kind` over `prims` repeatedly for about `min / 2` (at least once); the structure and the fastest build.
pub fn timed_build(kind: AccelKind, prims: &Primitives, min: Duration) -> Result<(Accel, Duration)> {
    let t0 = Instant::now();
    let mut accel = Accel::build(kind, prims)?;
    let mut best = t0.elapsed();
    while t0.elapsed() < min / 2 {
        let t = Instant::now();
        accel = Accel::build(kind, prims)?;
        best = best.min(t.elapsed());
    }
    Ok((accel, best))
}

/// Measure every accelerator of `opts` on the scene at `path`, loaded with `plugins` (the builds and traversals run
/// on `pool`).
pub fn bench_scene(
    path: &Path,
    opts: &BenchOptions,
    pool: &rayon::ThreadPool,
    plugins: &dyn Plugin,
) -> Result<Vec<BenchRow>> {
    let mut app = App::with(plugins);
    app.resources.source = SceneSource::File(path.to_path_buf());
    app.resources.overrides = Overrides { accel: Some(AccelKind::Brute), ..Default::default() };
    app.setup()?;
    let scene = app.resources.scene()?;
    let prims = &scene.prims;
    let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into());
    let camera = camera_rays(scene, opts.size, opts.size);
    // Secondary rays from the hits of a BVH-traced camera pass (the same rays for every accelerator).
    let reference = Accel::build(AccelKind::Bvh, prims)?;
    let scene_for_rays = prism_core::scene::Scene {
        camera: scene.camera,
        prims: prims.clone(),
        accel: reference,
        lights: Default::default(),
        materials: Default::default(),
        textures: Default::default(),
        globals: scene.globals,
        cancel: Default::default(),
    };
    let (bounce, shadow) = secondary_rays(&scene_for_rays, &camera, 1);
    if let Some(dir) = &opts.export_rays {
        let file = RaySetFile::trace(prims, &scene_for_rays.accel, [&camera, &bounce, &shadow])?;
        std::fs::create_dir_all(dir).map_err(|e| PrismError::io(dir, e))?;
        let stem = path.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
        let out = dir.join(format!("{stem}.prism-rays"));
        file.write(&out)?;
        eprintln!("{name}: wrote {}", out.display());
    }
    drop(scene_for_rays);
    let (mut accels, mut builds) = (Vec::new(), Vec::new());
    for &kind in &opts.kinds {
        if kind == AccelKind::Brute && prims.num_bounded() > opts.brute_limit {
            eprintln!("{name}: brute force skipped ({} primitives > --brute-limit)", prims.num_bounded());
            continue;
        }
        eprintln!("{name}: building {} ...", kind.name());
        let (accel, build) = pool.install(|| timed_build(kind, prims, opts.min))?;
        accels.push(accel);
        builds.push((kind, build));
    }
    eprintln!("{name}: tracing ...");
    let mrays = pool.install(|| interleaved_best(&accels, prims, [&camera, &bounce, &shadow], opts.min));
    let mut rows = vec![];
    for (((kind, build), accel), [camera_mrays, secondary_mrays, shadow_mrays]) in builds.iter().zip(&accels).zip(mrays)
    {
        let stats = accel.stats();
        rows.push(BenchRow {
            scene: name.clone(),
            prims: prims.num_bounded(),
            accel: kind.name(),
            build_ms: build.as_secs_f64() * 1e3,
            memory_bytes: stats.memory_bytes,
            nodes: stats.nodes,
            camera_mrays,
            secondary_mrays,
            shadow_mrays,
            detail: stats.detail,
        });
    }
    Ok(rows)
}

/// The Markdown table of the rows.
pub fn table(rows: &[BenchRow], threads: usize, size: u32) -> String {
    let mut s = String::from(
        "| scene | primitives | accel | build ms | memory | nodes/cells | camera Mrays/s | secondary Mrays/s | shadow \
         Mrays/s | structure |\n|---|---:|---|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.1} | {:.1} MiB | {} | {:.2} | {:.2} | {:.2} | {} |\n",
            r.scene,
            r.prims,
            r.accel,
            r.build_ms,
            r.memory_bytes as f64 / (1 << 20) as f64,
            r.nodes,
            r.camera_mrays,
            r.secondary_mrays,
            r.shadow_mrays,
            r.detail
        );
    }
    s += &format!(
        "\n{threads} thread(s); camera rays: {size}x{size} pixel centres; secondary: one diffuse bounce per camera hit; \
         shadow: occlusion towards a random point of the scene bounds."
    );
    s
}

/// A named number of a bench row (e.g. `("camera", |r| r.camera_mrays)`).
pub type RowValue<'a> = (&'a str, fn(&BenchRow) -> f64);

/// One series per accelerator (and per ray kind when `kinds` names several) of `value(row)` against primitive
/// count, points sorted by primitive count.
pub fn series_by_accel(rows: &[BenchRow], kinds: &[RowValue]) -> Vec<Series> {
    let mut series: Vec<Series> = Vec::new();
    for r in rows {
        for (kind, value) in kinds {
            let name = if kinds.len() == 1 { r.accel.to_string() } else { format!("{} {kind}", r.accel) };
            let (x, y) = (r.prims as f64, value(r));
            match series.iter_mut().find(|s| s.name == name) {
                Some(s) => s.points.push((x, y)),
                None => series.push(Series { name, points: vec![(x, y)] }),
            }
        }
    }
    for s in series.iter_mut() {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    series
}

/// Mrays/s against primitive count, per accelerator and ray kind (camera and secondary).
pub fn chart_of(rows: &[BenchRow], threads: usize) -> Chart {
    Chart {
        title: format!("Closest-hit throughput ({threads} thread(s))"),
        x_label: "primitives".into(),
        y_label: "Mrays/s".into(),
        log_x: true,
        log_y: true,
        series: series_by_accel(rows, &[("camera", |r| r.camera_mrays), ("secondary", |r| r.secondary_mrays)]),
    }
}
