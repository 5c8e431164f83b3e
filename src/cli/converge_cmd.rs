//! `prism converge SCENE --reference REF.exr --integrator A [--integrator B ...] (--spp 1,4,16 | --times 1,2,4)
//! -o DIR [--peer curves.csv --peer-scene cornell --peer-variant llvm_ad_rgb]`: error-vs-budget curves.

use clap::Args;
use prism_core::error::PrismError;
use prism_core::io::read_image;
use prism_core::settings::Overrides;
use prism_lab::converge::{Budget, PeerCurve, measure, read_peer, time_to_error, write_results};
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct ConvergeArgs {
    /// Scene file.
    pub scene: PathBuf,
    /// Reference image (.exr).
    #[arg(long)]
    pub reference: PathBuf,
    /// Integrator spec, `name` or `name(param: value, ...)`; repeat for several curves.
    #[arg(long = "integrator", required = true)]
    pub integrators: Vec<String>,
    /// Sample counts, comma-separated (e.g. 1,4,16,64).
    #[arg(long, value_delimiter = ',', conflicts_with = "times")]
    pub spp: Vec<u32>,
    /// Time budgets in seconds, comma-separated (e.g. 0.5,1,2,4).
    #[arg(long, value_delimiter = ',')]
    pub times: Vec<f64>,
    /// Output directory for convergence.csv and the charts.
    #[arg(short, long = "output")]
    pub output: PathBuf,
    /// A peer's curves (CSV with scene,spp,seconds,rmse,variant columns), drawn alongside.
    #[arg(long)]
    pub peer: Option<PathBuf>,
    #[arg(long, default_value = "cornell")]
    pub peer_scene: String,
    #[arg(long, default_value = "llvm_ad_rgb")]
    pub peer_variant: String,
    /// Only the peer rows of this sampler (for CSVs with a `sampler` column, e.g. `independent`, `ldsampler`).
    #[arg(long)]
    pub peer_sampler: Option<String>,
    /// Measure the error over a pixel rectangle `X,Y,W,H` only (e.g. the caustic: `95,195,70,35`).
    #[arg(long, value_delimiter = ',')]
    pub crop: Option<Vec<u32>>,
    #[arg(long, value_parser = super::render_cmd::parse_size)]
    pub size: Option<(u32, u32)>,
    #[arg(long)]
    pub seed: Option<u64>,
    #[arg(long)]
    pub threads: Option<usize>,
}

pub fn run(a: ConvergeArgs) -> anyhow::Result<()> {
    let budgets: Vec<Budget> = if !a.spp.is_empty() {
        a.spp.iter().map(|&n| Budget::Spp(n)).collect()
    } else if !a.times.is_empty() {
        if a.times.iter().any(|t| !(t.is_finite() && *t > 0.0 && *t <= prism_core::limits::MAX_SECONDS)) {
            return Err(PrismError::invalid(format!(
                "--times must be positive numbers of seconds (at most {})",
                prism_core::limits::MAX_SECONDS
            ))
            .into());
        }
        a.times.iter().map(|&t| Budget::Seconds(t)).collect()
    } else {
        return Err(PrismError::invalid("give the budgets with --spp N,N,... or --times S,S,...").into());
    };
    if let Some(t) = a.threads {
        prism_core::limits::threads(t)?;
    }
    // The output directory and every file written into it are checked before the first render: it exists (or is
    // created) and is writable, and no result would overwrite an input (scene, its meshes and maps, reference, peer).
    std::fs::create_dir_all(&a.output).map_err(|e| PrismError::io(&a.output, e))?;
    let results = prism_lab::converge::RESULT_FILES.map(|f| a.output.join(f));
    let mut inputs = scene_inputs(&a.scene)?;
    inputs.push(a.reference.clone());
    inputs.extend(a.peer.iter().cloned());
    prism_core::io::check_outputs(&results, &inputs)?;
    let reference = read_image(&a.reference)?;
    let peer: Option<PeerCurve> =
        a.peer.as_ref().map(|p| read_peer(p, &a.peer_scene, &a.peer_variant, a.peer_sampler.as_deref())).transpose()?;
    let crop = match a.crop.as_deref() {
        None => None,
        Some([x, y, w, h]) if *w > 0 && *h > 0 && x + w <= reference.width && y + h <= reference.height => {
            Some([*x, *y, *w, *h])
        }
        Some(c) => {
            return Err(PrismError::invalid(format!(
                "--crop {c:?} is not a non-empty rectangle inside the {}x{} reference",
                reference.width, reference.height
            ))
            .into());
        }
    };
    if crop.is_some() && peer.is_some() {
        return Err(PrismError::invalid("--crop measures a region; a peer's curve is over the whole image").into());
    }
    let base = Overrides { size: a.size, seed: a.seed, ..Default::default() };
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = a.threads {
        builder = builder.num_threads(n);
    }
    let pool = builder.build().map_err(|e| PrismError::invalid(format!("cannot start threads: {e}")))?;
    eprintln!("{:<40} {:>6} {:>9} {:>9} {:>10}", "integrator", "spp", "seconds", "cpu s", "RMSE");
    let title = a.scene.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    // Ctrl-C stops the render in progress; the points measured so far are written (they are rewritten after
    // every point anyway, so even a killed run leaves its results).
    let cancel = super::render_cmd::cancel_flag();
    let points = pool.install(|| {
        measure(
            &a.scene,
            &reference,
            &a.integrators,
            &budgets,
            &base,
            crop,
            &cancel,
            &crate::DefaultPlugins,
            |p, so_far| {
                let cpu = p.cpu_seconds.map_or("-".into(), |c| format!("{c:.3}"));
                eprintln!("{:<40} {:>6} {:>9.3} {:>9} {:>10.5}", p.integrator, p.spp, p.seconds, cpu, p.rmse);
                write_results(&a.output, so_far, peer.as_ref(), &title).map(|_| ())
            },
        )
    })?;
    let files = write_results(&a.output, &points, peer.as_ref(), &title)?;
    if cancel.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(anyhow::anyhow!(
            "interrupted: wrote the {} of {} points measured so far to {}",
            points.len(),
            a.integrators.len() * budgets.len(),
            a.output.display()
        ));
    }
    if let Some(peer) = &peer {
        // Equal-error time: when does each curve reach the peer's lowest error?
        let target = peer.points.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
        let peer_t = time_to_error(&peer.points.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>(), target);
        let peer_cpu: Option<Vec<(f64, f64)>> =
            peer.points.iter().zip(&peer.cpu_seconds).map(|(p, c)| c.map(|c| (c, p.2))).collect();
        let peer_cpu_t = peer_cpu.and_then(|c| time_to_error(&c, target));
        for spec in &a.integrators {
            let mine: Vec<_> = points.iter().filter(|p| &p.integrator == spec).collect();
            let wall: Vec<(f64, f64)> = mine.iter().map(|p| (p.seconds, p.rmse)).collect();
            match (time_to_error(&wall, target), peer_t) {
                (Some(t), Some(pt)) => eprintln!(
                    "equal error RMSE {target:.4}: {spec} {t:.2} s vs {} {pt:.2} s wall ({:.2}x)",
                    peer.name,
                    pt / t
                ),
                _ => eprintln!("equal error RMSE {target:.4}: {spec} did not reach it within the budgets"),
            }
            let cpu: Option<Vec<(f64, f64)>> = mine.iter().map(|p| p.cpu_seconds.map(|c| (c, p.rmse))).collect();
            if let (Some(t), Some(pt)) = (cpu.and_then(|c| time_to_error(&c, target)), peer_cpu_t) {
                eprintln!(
                    "equal error RMSE {target:.4}: {spec} {t:.2} s vs {} {pt:.2} s CPU ({:.2}x)",
                    peer.name,
                    pt / t
                );
            }
        }
    }
    eprintln!("wrote {}", files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>().join(", "));
    Ok(())
}

/// The files a scene reads (the scene itself, meshes, textures, environment maps): its Load stage alone.
fn scene_inputs(scene: &std::path::Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut app = prism_engine::App::with(crate::DefaultPlugins);
    app.resources.source = prism_engine::SceneSource::File(scene.to_path_buf());
    app.run_stage(prism_engine::Stage::Load)?;
    Ok(std::mem::take(&mut app.resources.inputs))
}
