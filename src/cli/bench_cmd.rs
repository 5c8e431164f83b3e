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

use clap::Args;
use prism_core::error::PrismError;
use prism_core::settings::AccelKind;
use prism_lab::accel_bench::{BenchOptions, bench_scene, chart_of, table};
use std::path::PathBuf;

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

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    prism_core::limits::threads(args.threads)?;
    if args.size == 0 || args.size > prism_core::limits::MAX_BENCH_SIZE {
        return Err(PrismError::invalid(format!(
            "--size must be between 1 and {}, got {}",
            prism_core::limits::MAX_BENCH_SIZE,
            args.size
        ))
        .into());
    }
    let min = prism_core::limits::seconds(args.seconds, "--seconds")?;
    if min.is_zero() {
        return Err(PrismError::invalid("--seconds must be positive").into());
    }
    let kinds = parse_kinds(&args.accel, args.grid.as_deref())?;
    // Outputs are checked before the (long) measurements: the chart's directory is writable and no output is a scene.
    if let Some(chart) = &args.chart {
        prism_core::io::check_outputs(std::slice::from_ref(chart), &args.scenes)?;
    }
    if let Some(dir) = &args.export_rays {
        std::fs::create_dir_all(dir).map_err(|e| PrismError::io(dir, e))?;
        prism_core::io::check_writable_dir(&dir.join("rays.prism-rays"))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .map_err(|e| PrismError::invalid(format!("cannot start {} threads: {e}", args.threads)))?;
    let opts = BenchOptions {
        kinds,
        size: args.size,
        min,
        brute_limit: args.brute_limit,
        export_rays: args.export_rays.clone(),
    };
    let mut rows = Vec::new();
    for path in &args.scenes {
        rows.extend(bench_scene(path, &opts, &pool, &crate::DefaultPlugins)?);
    }
    super::print_stdout(&format!("{}\n", table(&rows, args.threads, args.size)))?;
    if let Some(chart) = &args.chart {
        chart_of(&rows, args.threads).write_svg(chart)?;
        eprintln!("wrote {}", chart.display());
    }
    Ok(())
}
