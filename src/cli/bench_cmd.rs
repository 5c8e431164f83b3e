//! `prism bench SCENE... [--accel all|bvh,kdtree,...] [--grid NX NY NZ] [--size N] [--threads N] [--chart F.svg]
//! [--export-rays DIR]`:
//! for each scene and accelerator, the build time, the structure's memory and node/cell count, and closest-hit
//! throughput (Mrays/s) for camera rays and for secondary (diffuse bounce) rays, plus occlusion throughput for
//! shadow rays (`accel/ray_sets.rs`). Prints a Markdown table; `--chart` writes an SVG of Mrays/s against the
//! number of primitives, one curve per accelerator and ray kind (give several scenes, e.g. the bunny series, for
//! curves). Brute force is skipped above `--brute-limit` primitives. The build is the fastest of the builds done
//! in `--seconds / 2`. Traversal is timed interleaved: round after round, every accelerator traces every ray set
//! once, until each (accelerator, ray set) has had about `--seconds`; each number is the fastest pass. A machine
//! whose speed drifts (other jobs, frequency changes) then slows every accelerator alike, so the ratios between
//! accelerators of one scene are measured in the same run. `--export-rays DIR` also writes each scene's triangles,
//! ray sets and BVH answers to `DIR/STEM.prism-rays` (`accel/ray_file.rs`), for timing another engine on the same
//! rays (`benches/embree/`).

use crate::accel::Accel;
use crate::accel::ray_file::RaySetFile;
use crate::accel::ray_sets::{camera_rays, secondary_rays};
use crate::app::{App, SceneSource};
use crate::chart::{Chart, Series};
use crate::error::PrismError;
use crate::geometry::Ray;
use crate::primitives::Primitives;
use crate::settings::{AccelKind, Overrides};
use clap::Args;
use rayon::prelude::*;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Scene files (.ron, .obj, 6.837 .txt).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// `all`, or a comma-separated list of bvh, kdtree, grid, brute.
    #[arg(long, default_value = "all")]
    pub accel: String,
    /// Grid resolution NX NY NZ for the grid (default: automatic).
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"])]
    pub grid: Option<Vec<u32>>,
    /// Camera rays: one per pixel of an N x N image of the scene's camera.
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Worker threads for the traversal measurements.
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Minimum measuring time per number, in seconds.
    #[arg(long, default_value_t = 0.5)]
    pub seconds: f64,
    /// Skip brute force above this many primitives.
    #[arg(long, default_value_t = 20_000)]
    pub brute_limit: u32,
    /// Write an SVG chart of Mrays/s against primitive count.
    #[arg(long)]
    pub chart: Option<PathBuf>,
    /// Also write each scene's triangles, ray sets and BVH hits to DIR/STEM.prism-rays (triangle scenes only).
    #[arg(long, value_name = "DIR")]
    pub export_rays: Option<PathBuf>,
}

/// One row of the table.
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

fn parse_kinds(s: &str, grid: Option<&[u32]>) -> Result<Vec<AccelKind>, PrismError> {
    let mut kinds = if s == "all" {
        AccelKind::ALL.to_vec()
    } else {
        s.split(',')
            .map(|n| {
                AccelKind::parse(n.trim()).ok_or_else(|| {
                    PrismError::invalid(format!("unknown accelerator '{n}' (expected all or {})", AccelKind::NAMES))
                })
            })
            .collect::<Result<Vec<_>, _>>()?
    };
    if let Some(g) = grid {
        for k in kinds.iter_mut() {
            if let AccelKind::Grid(_) = k {
                *k = super::render_cmd::accel_override(Some(*k), Some(g))?.unwrap_or(*k);
            }
        }
    }
    Ok(kinds)
}

/// Seconds of the fastest pass of each accelerator over each ray set (camera and bounce rays: closest hit; shadow
/// rays: occlusion), passes interleaved round by round (see the module doc); at least three rounds.
fn interleaved_best(accels: &[Accel], prims: &Primitives, sets: [&[Ray]; 3], min: Duration) -> Vec<[f64; 3]> {
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

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    crate::limits::threads(args.threads)?;
    if args.size == 0 || args.size > crate::limits::MAX_BENCH_SIZE {
        return Err(PrismError::invalid(format!(
            "--size must be between 1 and {}, got {}",
            crate::limits::MAX_BENCH_SIZE,
            args.size
        ))
        .into());
    }
    let min = crate::limits::seconds(args.seconds, "--seconds")?;
    if min.is_zero() {
        return Err(PrismError::invalid("--seconds must be positive").into());
    }
    let kinds = parse_kinds(&args.accel, args.grid.as_deref())?;
    // Outputs are checked before the (long) measurements: the chart's directory is writable and no output is a scene.
    if let Some(chart) = &args.chart {
        crate::io::check_outputs(std::slice::from_ref(chart), &args.scenes)?;
    }
    if let Some(dir) = &args.export_rays {
        std::fs::create_dir_all(dir).map_err(|e| PrismError::io(dir, e))?;
        crate::io::check_writable_dir(&dir.join("rays.prism-rays"))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .map_err(|e| PrismError::invalid(format!("cannot start {} threads: {e}", args.threads)))?;
    let mut rows = Vec::new();
    for path in &args.scenes {
        let mut app = App::with_default_plugins();
        app.resources.source = SceneSource::File(path.clone());
        app.resources.overrides = Overrides { accel: Some(AccelKind::Brute), ..Default::default() };
        app.setup()?;
        let scene = app.resources.scene()?;
        let prims = &scene.prims;
        let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into());
        let camera = camera_rays(scene, args.size, args.size);
        // Secondary rays from the hits of a BVH-traced camera pass (the same rays for every accelerator).
        let reference = Accel::build(AccelKind::Bvh, prims)?;
        let scene_for_rays = crate::scene::Scene {
            camera: scene.camera,
            prims: prims.clone(),
            accel: reference,
            lights: Default::default(),
            materials: vec![],
            textures: Default::default(),
            globals: scene.globals,
            cancel: Default::default(),
        };
        let (bounce, shadow) = secondary_rays(&scene_for_rays, &camera, 1);
        if let Some(dir) = &args.export_rays {
            let file = RaySetFile::trace(prims, &scene_for_rays.accel, [&camera, &bounce, &shadow])?;
            std::fs::create_dir_all(dir).map_err(|e| PrismError::io(dir, e))?;
            let stem = path.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
            let out = dir.join(format!("{stem}.prism-rays"));
            file.write(&out)?;
            eprintln!("{name}: wrote {}", out.display());
        }
        drop(scene_for_rays);
        let (mut accels, mut builds) = (Vec::new(), Vec::new());
        for &kind in &kinds {
            if kind == AccelKind::Brute && prims.num_bounded() > args.brute_limit {
                eprintln!("{name}: brute force skipped ({} primitives > --brute-limit)", prims.num_bounded());
                continue;
            }
            eprintln!("{name}: building {} ...", kind.name());
            let (accel, build) = pool.install(|| -> anyhow::Result<(Accel, Duration)> {
                let t0 = Instant::now();
                let mut accel = Accel::build(kind, prims)?;
                let mut best = t0.elapsed();
                while t0.elapsed() < min / 2 {
                    let t = Instant::now();
                    accel = Accel::build(kind, prims)?;
                    best = best.min(t.elapsed());
                }
                Ok((accel, best))
            })?;
            accels.push(accel);
            builds.push((kind, build));
        }
        eprintln!("{name}: tracing ...");
        let mrays = pool.install(|| interleaved_best(&accels, prims, [&camera, &bounce, &shadow], min));
        for (((kind, build), accel), [camera_mrays, secondary_mrays, shadow_mrays]) in
            builds.iter().zip(&accels).zip(mrays)
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
    }
    super::print_stdout(&format!("{}\n", table(&rows, args.threads, args.size)))?;
    if let Some(chart) = &args.chart {
        chart_of(&rows, args.threads).write_svg(chart)?;
        eprintln!("wrote {}", chart.display());
    }
    Ok(())
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

/// Mrays/s against primitive count, per accelerator and ray kind.
pub fn chart_of(rows: &[BenchRow], threads: usize) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    let mut add = |name: String, x: f64, y: f64| match series.iter_mut().find(|s| s.name == name) {
        Some(s) => s.points.push((x, y)),
        None => series.push(Series { name, points: vec![(x, y)] }),
    };
    for r in rows {
        add(format!("{} camera", r.accel), r.prims as f64, r.camera_mrays);
        add(format!("{} secondary", r.accel), r.prims as f64, r.secondary_mrays);
    }
    for s in series.iter_mut() {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    Chart {
        title: format!("Closest-hit throughput ({threads} thread(s))"),
        x_label: "primitives".into(),
        y_label: "Mrays/s".into(),
        log_x: true,
        log_y: true,
        series,
    }
}
