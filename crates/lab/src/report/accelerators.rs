//! The accelerator section: `prism bench` (`accel::bench::bench_scene`) over the suite's scenes, charted against
//! primitive count (Mrays/s for camera, bounce and shadow rays; build time; memory), the table, and the heat maps
//! of each accelerator on one view (`traversal.rs`).

use super::html::{self, esc, num};
use super::suite::AccelCase;
use super::{Ctx, field, traversal};
use crate::accel_bench::{BenchOptions, BenchRow, bench_scene, series_by_accel};
use crate::chart::Chart;
use prism_core::settings::AccelKind;
use std::fmt::Write as _;
use std::time::Duration;

pub(super) fn section(ctx: &mut Ctx, case: &AccelCase) -> String {
    let mut s = String::from(r#"<section id="accelerators"><h2>Accelerators</h2>"#);
    if !case.caption.is_empty() {
        let _ = write!(s, r#"<p class="caption">{}</p>"#, case.caption);
    }
    let mut kinds: Vec<AccelKind> = vec![];
    for spec in &case.accels {
        match super::parse_accel(spec, None) {
            Ok(k) => kinds.push(k),
            Err(e) => s += &ctx.problem("accelerators", spec, e),
        }
    }
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(case.threads).build() {
        Ok(p) => p,
        Err(e) => return s + &ctx.problem("accelerators", "threads", e) + "</section>",
    };
    let opts = BenchOptions {
        kinds,
        size: case.rays,
        min: Duration::from_secs_f64(case.seconds),
        brute_limit: case.brute_limit,
        export_rays: None,
    };
    let mut rows: Vec<BenchRow> = vec![];
    for scene in &case.scenes {
        ctx.log(format!("accelerators: {}", scene.display()));
        let found = scene.is_file();
        let measured = if found {
            bench_scene(scene, &opts, &pool, ctx.plugins).map_err(|e| e.to_string())
        } else {
            Err(format!("{}: scene file not found", scene.display()))
        };
        match measured {
            Ok(r) => rows.extend(r),
            Err(e) => s += &ctx.problem("accelerators", &scene.display().to_string(), e),
        }
    }
    for r in &rows {
        ctx.csv(
            "accelerators.csv",
            "scene,primitives,accel,build_ms,memory_bytes,nodes,camera_mrays,bounce_mrays,shadow_mrays,structure",
            format!(
                "{},{},{},{:.4},{},{},{:.4},{:.4},{:.4},{}",
                field(&r.scene),
                r.prims,
                r.accel,
                r.build_ms,
                r.memory_bytes,
                r.nodes,
                r.camera_mrays,
                r.secondary_mrays,
                r.shadow_mrays,
                field(&r.detail)
            ),
        );
    }
    if !rows.is_empty() {
        let _ = write!(
            s,
            r#"<p class="note">{} thread{}; camera rays through the {r}x{r} pixel centres; bounce rays: one diffuse bounce per camera hit (closest hit); shadow rays: occlusion towards a random point of the scene bounds. Each number is the fastest of passes interleaved across the accelerators for about {} s each; builds are the fastest of repeated builds.</p>"#,
            case.threads,
            if case.threads == 1 { "" } else { "s" },
            num(case.seconds),
            r = case.rays
        );
        // Zero values (brute force builds nothing and holds no structure) have no place on a log axis.
        let chart = |title: &str, y: &str, value: fn(&BenchRow) -> f64| {
            let mut series = series_by_accel(&rows, &[("", value)]);
            series.iter_mut().for_each(|s| s.points.retain(|p| p.1 > 0.0));
            series.retain(|s| !s.points.is_empty());
            Chart {
                title: title.into(),
                x_label: "primitives".into(),
                y_label: y.into(),
                log_x: true,
                log_y: true,
                series,
            }
        };
        s += r#"<div class="charts">"#;
        s += &chart("Camera rays (closest hit)", "Mrays/s", |r| r.camera_mrays).to_svg();
        s += &chart("Bounce rays (closest hit)", "Mrays/s", |r| r.secondary_mrays).to_svg();
        s += &chart("Shadow rays (occlusion)", "Mrays/s", |r| r.shadow_mrays).to_svg();
        s += &chart("Build time", "milliseconds", |r| if r.accel == "brute" { 0.0 } else { r.build_ms }).to_svg();
        s += &chart("Memory of the structure", "MiB", |r| r.memory_bytes as f64 / (1 << 20) as f64).to_svg();
        s += "</div>";
        let table: Vec<Vec<String>> = rows
            .iter()
            .map(|r| {
                vec![
                    esc(&r.scene),
                    r.prims.to_string(),
                    r.accel.to_string(),
                    num(r.build_ms),
                    format!("{} MiB", num(r.memory_bytes as f64 / (1 << 20) as f64)),
                    r.nodes.to_string(),
                    num(r.camera_mrays),
                    num(r.secondary_mrays),
                    num(r.shadow_mrays),
                    esc(&r.detail),
                ]
            })
            .collect();
        s += &html::table(
            &[
                "scene",
                "primitives",
                "accel",
                "build ms",
                "memory",
                "nodes/cells",
                "camera Mrays/s",
                "bounce Mrays/s",
                "shadow Mrays/s",
                "structure",
            ],
            "lrlrrrrrrl",
            &table,
            "bench",
        );
    }
    if let Some(h) = &case.heat {
        let specs: Vec<String> =
            h.accels.clone().unwrap_or_else(|| case.accels.iter().filter(|a| a.as_str() != "brute").cloned().collect());
        let name = h.scene.file_stem().map_or("view".into(), |n| n.to_string_lossy().into_owned());
        let _ = write!(s, "<h3>Traversal heat maps: {}</h3>", esc(&name));
        s += r#"<p class="note">Per pixel, the work of the camera ray through the pixel centre in each accelerator, on one colour scale (<code>debug(mode: heat)</code>).</p>"#;
        ctx.log(format!("accelerators: heat maps of {}", h.scene.display()));
        match traversal::measure(ctx, &h.scene, &specs, h.size, None) {
            Ok((_, measured)) => s += &traversal::figures(ctx, "heat", &measured, &specs, h.size, h.count, h.max),
            Err(e) => s += &ctx.problem("accelerators", "heat maps", e),
        }
    }
    s + "</section>"
}
