//! Accelerators on one view: for each, the build (`accel::bench::timed_build`), the traversal work of the camera
//! ray through every pixel (`debug` plugin's `heat_rows`: nodes or cells visited, primitives tested) drawn as heat
//! maps on one colour scale, the mean work per ray, and optionally the camera rays' throughput measured
//! interleaved (`accel::bench::interleaved_best`). Used by the accelerator section and the stability atlas.

use super::html::{self, esc, num};
use super::images;
use super::{Ctx, RenderJob, field};
use crate::accel_bench::{interleaved_best, timed_build};
use crate::ray_sets::camera_rays;
use prism_core::accel::TraversalWork;
use prism_core::error::{PrismError, Result};
use prism_core::settings::AccelKind;
use prism_debug::{HeatCount, heat_rows};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// One accelerator's numbers on the view.
pub(super) struct Row {
    pub build_ms: f64,
    pub memory_bytes: usize,
    pub detail: String,
    pub mean_nodes: f64,
    pub mean_prims: f64,
    pub camera_mrays: Option<f64>,
    /// Work per pixel, row-major `size x size`.
    pub work: Vec<TraversalWork>,
}

/// Measure every accelerator of `specs` on the view of `scene` at `size x size` (camera throughput too when
/// `seconds` is given). A spec that fails gives its error in place of its row.
pub(super) fn measure(
    ctx: &Ctx,
    scene: &Path,
    specs: &[String],
    size: u32,
    seconds: Option<f64>,
) -> Result<(u32, Vec<std::result::Result<Row, String>>)> {
    if !scene.is_file() {
        return Err(PrismError::io(scene, std::io::Error::new(std::io::ErrorKind::NotFound, "scene file not found")));
    }
    let job = RenderJob { scene, accel: Some(AccelKind::Brute), size: Some((size, size)), ..Default::default() };
    let mut app = job.app(ctx);
    ctx.pool.install(|| app.setup())?;
    let mut scene = app.resources.scene.take().ok_or_else(|| PrismError::invalid("no scene"))?;
    let prims_count = scene.prims.num_bounded();
    let min = Duration::from_secs_f64(seconds.unwrap_or(0.0));
    let (mut rows, mut accels) = (vec![], vec![]);
    for spec in specs {
        let built = super::parse_accel(spec, Some(&scene.prims))
            .and_then(|kind| ctx.pool.install(|| timed_build(kind, &scene.prims, min)));
        let (accel, build) = match built {
            Ok(b) => b,
            Err(e) => {
                rows.push(Err(e.to_string()));
                continue;
            }
        };
        let stats = accel.stats();
        let previous = std::mem::replace(&mut scene.accel, accel);
        let never = AtomicBool::new(false);
        let work: Vec<TraversalWork> =
            ctx.pool.install(|| heat_rows(&scene, size, size, &never)).into_iter().flatten().flatten().collect();
        let accel = std::mem::replace(&mut scene.accel, previous);
        let n = work.len().max(1) as f64;
        rows.push(Ok(Row {
            build_ms: build.as_secs_f64() * 1e3,
            memory_bytes: stats.memory_bytes,
            detail: stats.detail,
            mean_nodes: work.iter().map(|w| w.nodes as f64).sum::<f64>() / n,
            mean_prims: work.iter().map(|w| w.prims as f64).sum::<f64>() / n,
            camera_mrays: None,
            work,
        }));
        accels.push(accel);
    }
    if seconds.is_some() && !accels.is_empty() {
        let rays = camera_rays(&scene, size, size);
        let speeds = ctx.pool.install(|| interleaved_best(&accels, &scene.prims, [&rays, &[], &[]], min));
        for (row, speed) in rows.iter_mut().filter_map(|r| r.as_mut().ok()).zip(speeds) {
            row.camera_mrays = Some(speed[0]);
        }
    }
    Ok((prims_count, rows))
}

/// Heat maps (one colour scale: `max`, or the largest of the maps' 99th percentiles) and a table of the rows;
/// pictures are named `NAME-SPEC.png`; rows go to `traversal.csv` under `case`.
pub(super) fn figures(
    ctx: &mut Ctx,
    case: &str,
    rows: &[std::result::Result<Row, String>],
    specs: &[String],
    size: u32,
    count: HeatCount,
    max: Option<f32>,
) -> String {
    let ok: Vec<&Row> = rows.iter().filter_map(|r| r.as_ref().ok()).collect();
    let max = max.unwrap_or_else(|| {
        ok.iter().map(|r| images::quantile(r.work.iter().map(|&w| count.of(w)), 0.99)).fold(1.0, f32::max)
    });
    let what = match count {
        HeatCount::Nodes => "nodes or cells visited per ray",
        HeatCount::Prims => "primitive tests per ray",
        HeatCount::Total => "nodes/cells visited + primitive tests per ray",
    };
    let width = html::shown_width(size, 220);
    let (mut strip, mut table) = (String::new(), vec![]);
    for (r, spec) in rows.iter().zip(specs) {
        let r = match r {
            Ok(r) => r,
            Err(e) => {
                strip += &html::failed_figure(width, spec, e);
                ctx.problem("traversal", &format!("{case} / {spec}"), e);
                continue;
            }
        };
        // Logarithmic: ln(1 + count) / ln(1 + max), so a few tests and thousands both show.
        let values: Vec<f32> = r.work.iter().map(|&w| count.of(w).ln_1p()).collect();
        let slug: String = spec.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
        let (path, rel) = ctx.picture(&format!("{case}-{slug}"));
        if let Err(e) = images::write_false_colour(&path, &values, size, size, max.ln_1p(), images::heat) {
            strip += &ctx.problem("traversal", &format!("{case} / {spec}"), e);
            continue;
        }
        let speed = r.camera_mrays.map_or(String::new(), |m| format!(", {} Mrays/s", num(m)));
        let caption = format!(
            "<b>{}</b><br>{} nodes/cells, {} primitive tests per ray{speed}",
            esc(spec),
            num(r.mean_nodes),
            num(r.mean_prims)
        );
        strip += &html::figure(&rel, &format!("{spec} heat map"), width, &caption, "map");
        table.push(vec![
            esc(spec),
            num(r.build_ms),
            format!("{} MiB", num(r.memory_bytes as f64 / (1 << 20) as f64)),
            num(r.mean_nodes),
            num(r.mean_prims),
            r.camera_mrays.map_or("-".into(), num),
            esc(&r.detail),
        ]);
        ctx.csv(
            "traversal.csv",
            "case,accel,build_ms,memory_bytes,nodes_per_ray,prims_per_ray,camera_mrays,structure",
            format!(
                "{},{},{:.4},{},{:.4},{:.4},{},{}",
                field(case),
                field(spec),
                r.build_ms,
                r.memory_bytes,
                r.mean_nodes,
                r.mean_prims,
                r.camera_mrays.map_or(String::new(), |m| format!("{m:.4}")),
                field(&r.detail)
            ),
        );
    }
    let mut s = format!(r#"<div class="strip">{strip}</div>"#);
    s += &html::colour_bar(images::heat, max as f64, true, what, &format!("bar-{case}"));
    s += &html::table(
        &[
            "accelerator",
            "build ms",
            "memory",
            "nodes/cells per ray",
            "prim tests per ray",
            "camera Mrays/s",
            "structure",
        ],
        "lrrrrrl",
        &table,
        "traversal",
    );
    s
}
