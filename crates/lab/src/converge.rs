//! Convergence measurements: render a scene with several integrators at growing budgets (samples per pixel, or
//! seconds), compare each image with a reference, and collect (time, spp, error) points; write them as CSV and as
//! RMSE-vs-time and RMSE-vs-spp charts, optionally with a peer renderer's curve (`../shared/refs/curves.csv`)
//! and the equal-error time against it. Each point is a fresh render (no reuse between budgets), timed over the
//! render passes only (set-up excluded, like the peer's timings).

use crate::chart::{Chart, Series};
use crate::compare::compare;
use prism_core::error::{PrismError, Result};
use prism_core::io::Image;
use prism_core::settings::Overrides;
use prism_engine::{App, Plugin, SceneSource};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// What to spend per render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    Spp(u32),
    Seconds(f64),
}

#[derive(Clone, Debug, PartialEq)]
pub struct ConvergencePoint {
    pub integrator: String,
    pub spp: u64,
    /// Wall time of the render passes.
    pub seconds: f64,
    /// CPU time of the render passes (all threads), when the platform reports it.
    pub cpu_seconds: Option<f64>,
    pub rmse: f64,
    pub relmse: f64,
    pub mae: f64,
}

/// A peer's curve: (spp, seconds, rmse) points, and CPU seconds per point when the CSV has them.
#[derive(Clone, Debug, Default)]
pub struct PeerCurve {
    pub name: String,
    pub points: Vec<(u64, f64, f64)>,
    pub cpu_seconds: Vec<Option<f64>>,
}

/// A pixel rectangle `(x, y, width, height)` the error is measured over (e.g. a caustic).
pub type Crop = [u32; 4];

/// Render `scene` once per (integrator, budget) and measure against `reference` (over `crop` if given).
/// `on_point` sees each point as it is measured (the CLI writes the results so far). When `cancel` is set
/// (Ctrl-C) the render in progress stops, its point is dropped and the points measured so far are returned. Every
/// render is built with `plugins`.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    scene: &Path,
    reference: &Image,
    integrators: &[String],
    budgets: &[Budget],
    base: &Overrides,
    crop: Option<Crop>,
    cancel: &Arc<AtomicBool>,
    plugins: &dyn Plugin,
    mut on_point: impl FnMut(&ConvergencePoint, &[ConvergencePoint]) -> Result<()>,
) -> Result<Vec<ConvergencePoint>> {
    let cut = |img: &Image| match crop {
        Some([x, y, w, h]) => img.crop(x, y, w, h),
        None => img.clone(),
    };
    let reference = &cut(reference);
    let mut out = vec![];
    for spec in integrators {
        for b in budgets {
            let mut app = App::with(plugins);
            app.resources.source = SceneSource::File(scene.to_path_buf());
            let mut o = base.clone();
            o.integrator = Some(spec.clone());
            match *b {
                Budget::Spp(n) => {
                    o.spp = Some(n);
                    o.time_budget = None;
                }
                Budget::Seconds(t) => {
                    o.spp = None;
                    o.time_budget = Some(t);
                    o.spp_unlimited = true;
                }
            }
            app.resources.overrides = o;
            app.resources.cancel = cancel.clone();
            app.run()?;
            if app.resources.progress.interrupted || cancel.load(Ordering::Relaxed) {
                return Ok(out);
            }
            let img =
                prism_engine::stages::film_image(&app.resources).ok_or_else(|| PrismError::invalid("no image"))?;
            let m = compare(&cut(&img), reference)?;
            let p = ConvergencePoint {
                integrator: spec.clone(),
                spp: app.resources.progress.spp_done,
                seconds: app.resources.progress.elapsed.as_secs_f64(),
                cpu_seconds: app.resources.progress.cpu.map(|c| c.as_secs_f64()),
                rmse: m.rmse,
                relmse: m.relmse,
                mae: m.mae,
            };
            out.push(p);
            on_point(&out[out.len() - 1], &out)?;
        }
    }
    Ok(out)
}

/// Read a peer curve from a CSV with a header containing `scene,spp,seconds,rmse,variant` columns (and, if the CSV
/// has a `sampler` column and `sampler` is given, only that sampler's rows).
pub fn read_peer(path: &Path, scene: &str, variant: &str, sampler: Option<&str>) -> Result<PeerCurve> {
    let text = prism_core::io::read_regular_text(path, "peer curves file")?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').map(str::trim).collect();
    let col = |name: &str| {
        header.iter().position(|h| *h == name).ok_or_else(|| PrismError::format(path, format!("no `{name}` column")))
    };
    let (cs, cn, ct, ce, cv) = (col("scene")?, col("spp")?, col("seconds")?, col("rmse")?, col("variant")?);
    let ccpu = header.iter().position(|h| *h == "cpu_seconds");
    let csampler = header.iter().position(|h| *h == "sampler");
    let mut points = vec![];
    for (i, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() <= cs.max(cn).max(ct).max(ce).max(cv) || f[cs] != scene || f[cv] != variant {
            continue;
        }
        if let (Some(want), Some(k)) = (sampler, csampler)
            && f.get(k) != Some(&want)
        {
            continue;
        }
        let num = |k: usize| {
            f[k].parse::<f64>().map_err(|_| PrismError::format(path, format!("line {}: bad number `{}`", i + 2, f[k])))
        };
        let cpu = ccpu.and_then(|k| f.get(k)).and_then(|v| v.parse::<f64>().ok());
        points.push(((num(cn)? as u64, num(ct)?, num(ce)?), cpu));
    }
    if points.is_empty() {
        return Err(PrismError::format(path, format!("no rows for scene `{scene}` and variant `{variant}`")));
    }
    points.sort_by(|a, b| a.0.1.total_cmp(&b.0.1));
    let (points, cpu_seconds) = points.into_iter().unzip();
    let name = match sampler {
        Some(s) => format!("peer {variant} {s}"),
        None => format!("peer {variant}"),
    };
    Ok(PeerCurve { name, points, cpu_seconds })
}

/// Time at which a curve of (seconds, rmse) points reaches `target` RMSE, interpolating linearly in log-log
/// (RMSE ~ t^-1/2 is a straight line there). `None` when the curve never gets that low.
pub fn time_to_error(points: &[(f64, f64)], target: f64) -> Option<f64> {
    let mut pts: Vec<(f64, f64)> = points.iter().copied().filter(|(t, e)| *t > 0.0 && *e > 0.0).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in pts.windows(2) {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        if e0 >= target && e1 <= target {
            if e0 == e1 {
                return Some(t0);
            }
            let a = (target.ln() - e0.ln()) / (e1.ln() - e0.ln());
            return Some((t0.ln() + a * (t1.ln() - t0.ln())).exp());
        }
    }
    pts.first().filter(|(_, e)| *e <= target).map(|(t, _)| *t)
}

/// The files [`write_results`] writes into its directory.
pub const RESULT_FILES: [&str; 3] = ["convergence.csv", "rmse_vs_time.svg", "rmse_vs_spp.svg"];

/// Write `convergence.csv`, `rmse_vs_time.svg` and `rmse_vs_spp.svg` into `dir`; returns their paths.
pub fn write_results(
    dir: &Path,
    points: &[ConvergencePoint],
    peer: Option<&PeerCurve>,
    title: &str,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| PrismError::io(dir, e))?;
    let mut csv = String::from("integrator,spp,seconds,rmse,relmse,mae\n");
    for p in points {
        let _ = writeln!(
            csv,
            "\"{}\",{},{:.6},{:.6e},{:.6e},{:.6e}",
            p.integrator, p.spp, p.seconds, p.rmse, p.relmse, p.mae
        );
    }
    if let Some(peer) = peer {
        for (spp, t, e) in &peer.points {
            let _ = writeln!(csv, "\"{}\",{spp},{t:.6},{e:.6e},,", peer.name);
        }
    }
    let csv_path = dir.join("convergence.csv");
    std::fs::write(&csv_path, csv).map_err(|e| PrismError::io(&csv_path, e))?;
    let mut names: Vec<&str> = vec![];
    for p in points {
        if !names.contains(&p.integrator.as_str()) {
            names.push(&p.integrator);
        }
    }
    let series = |x: &dyn Fn(&ConvergencePoint) -> f64, peer_x: &dyn Fn(&(u64, f64, f64)) -> f64| {
        let mut s: Vec<Series> = names
            .iter()
            .map(|n| Series {
                name: n.to_string(),
                points: points.iter().filter(|p| p.integrator == *n).map(|p| (x(p), p.rmse)).collect(),
            })
            .collect();
        if let Some(peer) = peer {
            s.push(Series { name: peer.name.clone(), points: peer.points.iter().map(|p| (peer_x(p), p.2)).collect() });
        }
        s
    };
    let time_chart = Chart {
        title: format!("{title}: error vs time"),
        x_label: "render time (s)".into(),
        y_label: "RMSE".into(),
        log_x: true,
        log_y: true,
        series: series(&|p| p.seconds, &|p| p.1),
    };
    let spp_chart = Chart {
        title: format!("{title}: error vs samples"),
        x_label: "samples per pixel".into(),
        y_label: "RMSE".into(),
        log_x: true,
        log_y: true,
        series: series(&|p| p.spp as f64, &|p| p.0 as f64),
    };
    let (t, s) = (dir.join("rmse_vs_time.svg"), dir.join("rmse_vs_spp.svg"));
    time_chart.write_svg(&t)?;
    spp_chart.write_svg(&s)?;
    Ok(vec![csv_path, t, s])
}

/// One render spent on a budget: the image, how much it took, and what the film saw.
#[derive(Clone, Debug)]
pub struct BudgetRender {
    pub image: Image,
    /// Samples per pixel (iterations for multi-pass integrators) rendered.
    pub spp: u64,
    /// Wall time of the render passes (set-up excluded).
    pub seconds: f64,
    /// CPU time of the render passes (all threads), when the platform reports it.
    pub cpu_seconds: Option<f64>,
    /// Set-up time (load, accelerator, lights, integrator preparation).
    pub setup_seconds: f64,
    /// Samples the film replaced by 0 because they were NaN or infinite.
    pub nonfinite: u64,
    /// The scene's PNG exposure in stops.
    pub exposure: f32,
}

/// Run `app` (its scene source, plugins and overrides already set) once with `budget` replacing the overrides'
/// sample count and time budget: a fresh render whose passes alone are timed.
pub fn render_budget(app: &mut App, budget: Budget) -> Result<BudgetRender> {
    let o = &mut app.resources.overrides;
    match budget {
        Budget::Spp(n) => {
            o.spp = Some(n);
            o.time_budget = None;
            o.spp_unlimited = false;
        }
        Budget::Seconds(t) => {
            o.spp = None;
            o.time_budget = Some(t);
            o.spp_unlimited = true;
        }
    }
    app.run()?;
    let image = prism_engine::stages::film_image(&app.resources).ok_or_else(|| PrismError::invalid("no image"))?;
    let progress = &app.resources.progress;
    Ok(BudgetRender {
        image,
        spp: progress.spp_done,
        seconds: progress.elapsed.as_secs_f64(),
        cpu_seconds: progress.cpu.map(|c| c.as_secs_f64()),
        setup_seconds: progress.setup.as_secs_f64(),
        nonfinite: app.resources.film.as_ref().map_or(0, |f| f.nonfinite),
        exposure: app.resources.settings.exposure,
    })
}
