//! Per scene: every method rendered once per budget (`converge::render_budget`) and measured against the
//! reference; log-log RMSE and relMSE against seconds with the peers' curves (dashed) and the reference's own noise
//! (dotted); the images of one budget side by side with their false-colour error maps on one scale; the hardest
//! region enlarged (the suite's, or the quarter-size window with the largest squared error); the equal-error
//! times (`converge::time_to_error`, log-log interpolation) as ratios.

use super::html::{self, esc, num};
use super::images::{self, fit_reference};
use super::suite::{Budgets, Method, Reference, SceneCase};
use super::{Ctx, RenderJob, field};
use crate::chart::{Chart, Decor, Series};
use crate::compare::compare;
use crate::converge::{Budget, BudgetRender, PeerCurve, read_peer, time_to_error};
use prism_core::error::Result;
use prism_core::io::{Image, read_image};
use std::fmt::Write as _;
use std::path::Path;

struct Point {
    budget: Budget,
    spp: u64,
    seconds: f64,
    rmse: f64,
    relmse: f64,
}

struct Curve<'a> {
    label: String,
    method: &'a Method,
    points: Vec<Point>,
    /// The render at the compared budget.
    shown: Option<BudgetRender>,
}

/// The reference at the render's size, its own noise (RMSE against the converged image, when known), and a line
/// saying where it came from.
fn reference(ctx: &Ctx, case: &SceneCase, w: u32, h: u32) -> Result<(Image, Option<f64>, String), String> {
    match &case.reference {
        Reference::File(path) => {
            let img = read_image(path).map_err(|e| e.to_string())?;
            let (full_w, full_h) = (img.width, img.height);
            let (img, factor) = fit_reference(img, w, h).map_err(|m| format!("{}: {m}", path.display()))?;
            let noise = noise_estimate(path).map(|n| n / factor as f64);
            let mut d = format!("reference <code>{}</code> ({full_w}x{full_h}", esc(&path.display().to_string()));
            if factor > 1 {
                let _ = write!(d, ", box-filtered {factor}x down to {w}x{h}");
            }
            d += ")";
            if let Some(n) = noise {
                let _ = write!(d, "; its own noise: RMSE {} (dotted line)", num(n));
            }
            Ok((img, noise, d))
        }
        Reference::Render(r) => {
            let job = RenderJob {
                scene: r.scene.as_ref().unwrap_or(&case.scene),
                integrator: Some(&r.integrator),
                sampler: r.sampler,
                size: Some((w, h)),
                seed: Some(r.seed.unwrap_or(1_000_003)),
                ..Default::default()
            };
            ctx.log(format!("{}: rendering the reference ({}, {} spp)", case.name, r.integrator, r.spp));
            let out = job.render(ctx, Budget::Spp(r.spp)).map_err(|e| format!("reference render: {e}"))?;
            let d = format!(
                "reference rendered here: <code>{}</code>, {} spp in {:.1} s (its noise is not subtracted)",
                esc(&r.integrator),
                out.spp,
                out.seconds
            );
            Ok((out.image, None, d))
        }
    }
}

/// `noise_rmse_estimate` from the `NAME.json` beside a reference `NAME.exr`, if there is one.
fn noise_estimate(reference: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(reference.with_extension("json")).ok()?;
    let at = text.find("\"noise_rmse_estimate\"")?;
    let rest = text[at..].split_once(':')?.1.trim_start();
    let end =
        rest.find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'))).unwrap_or(rest.len());
    rest[..end].parse().ok().filter(|v: &f64| v.is_finite() && *v >= 0.0)
}

fn budget_text(b: Budget) -> String {
    match b {
        Budget::Spp(n) => format!("{n} spp"),
        Budget::Seconds(t) => format!("{} s", num(t)),
    }
}

/// The section of one scene: `(anchor, title, html)`.
pub(super) fn section(ctx: &mut Ctx, case: &SceneCase) -> (String, String, String) {
    let anchor = format!("scene-{}", case.name);
    let title = case.title.clone().unwrap_or_else(|| case.name.clone());
    let mut s = format!(r#"<section id="{anchor}"><h2>{}</h2>"#, esc(&title));
    if !case.caption.is_empty() {
        let _ = write!(s, r#"<p class="caption">{}</p>"#, case.caption);
    }
    s += &body(ctx, case);
    s += "</section>";
    (anchor, title, s)
}

fn body(ctx: &mut Ctx, case: &SceneCase) -> String {
    let job = RenderJob { scene: &case.scene, size: case.size, ..Default::default() };
    let (w, h) = match case.size.map_or_else(|| job.size_of(ctx), Ok) {
        Ok(size) => size,
        Err(e) => return ctx.problem("scenes", &case.name, e),
    };
    let (reference, noise, ref_line) = match reference(ctx, case, w, h) {
        Ok(r) => r,
        Err(e) => return ctx.problem("scenes", &format!("{} reference", case.name), e),
    };
    let mut budgets: Vec<Budget> = match &case.budgets {
        Budgets::Times(t) => t.iter().map(|&t| Budget::Seconds(t)).collect(),
        Budgets::Spp(n) => n.iter().map(|&n| Budget::Spp(n)).collect(),
    };
    let value = |b: &Budget| match *b {
        Budget::Spp(n) => n as f64,
        Budget::Seconds(t) => t,
    };
    let shown_budget = match case.compare_at {
        Some(v) => {
            let b = match case.budgets {
                Budgets::Times(_) => Budget::Seconds(v),
                Budgets::Spp(_) => Budget::Spp(v.max(1.0) as u32),
            };
            if !budgets.contains(&b) {
                budgets.push(b);
            }
            b
        }
        None => *budgets.iter().max_by(|a, b| value(a).total_cmp(&value(b))).expect("budgets checked non-empty"),
    };
    budgets.sort_by(|a, b| value(a).total_cmp(&value(b)));
    budgets.dedup();
    let mut s = format!(r#"<p class="note">{w}x{h}; {ref_line}.</p>"#);
    let mut curves: Vec<Curve> = vec![];
    for method in &case.methods {
        let label = method.label();
        let mut curve = Curve { label: label.clone(), method, points: vec![], shown: None };
        let accel = match method.accel.as_deref().map(|a| super::parse_accel(a, None)).transpose() {
            Ok(a) => a,
            Err(e) => {
                s += &ctx.problem("scenes", &format!("{} / {label}", case.name), e);
                continue;
            }
        };
        let job = RenderJob {
            scene: &case.scene,
            integrator: Some(&method.integrator),
            sampler: method.sampler,
            accel,
            size: Some((w, h)),
            seed: None,
            adaptive: method.adaptive,
        };
        for &b in &budgets {
            ctx.log(format!("{}: {label}, {}", case.name, budget_text(b)));
            let r = match job.render(ctx, b) {
                Ok(r) => r,
                Err(e) => {
                    s += &ctx.problem("scenes", &format!("{} / {label}", case.name), e);
                    break;
                }
            };
            let m = match compare(&r.image, &reference) {
                Ok(m) => m,
                Err(e) => {
                    s += &ctx.problem("scenes", &format!("{} / {label}", case.name), e);
                    break;
                }
            };
            ctx.csv(
                "convergence.csv",
                "scene,method,integrator,sampler,budget,spp,seconds,cpu_seconds,rmse,relmse,mae",
                format!(
                    "{},{},{},{},{},{},{:.6},{},{:.6e},{:.6e},{:.6e}",
                    field(&case.name),
                    field(&label),
                    field(&method.integrator),
                    method.sampler.map_or("", |s| s.name()),
                    field(&budget_text(b)),
                    r.spp,
                    r.seconds,
                    r.cpu_seconds.map_or(String::new(), |c| format!("{c:.6}")),
                    m.rmse,
                    m.relmse,
                    m.mae
                ),
            );
            curve.points.push(Point { budget: b, spp: r.spp, seconds: r.seconds, rmse: m.rmse, relmse: m.relmse });
            if b == shown_budget {
                curve.shown = Some(r);
            }
        }
        if !curve.points.is_empty() {
            curves.push(curve);
        }
    }
    let mut peers: Vec<PeerCurve> = vec![];
    for p in &case.peers {
        match read_peer(&p.file, &p.scene, &p.variant, p.sampler.as_deref()) {
            Ok(mut c) => {
                if let Some(l) = &p.label {
                    c.name = l.clone();
                }
                for (spp, t, e) in &c.points {
                    ctx.csv(
                        "convergence.csv",
                        "scene,method,integrator,sampler,budget,spp,seconds,cpu_seconds,rmse,relmse,mae",
                        format!(
                            "{},{},,{},,{spp},{t:.6},,{e:.6e},,",
                            field(&case.name),
                            field(&c.name),
                            field(p.sampler.as_deref().unwrap_or(""))
                        ),
                    );
                }
                peers.push(c);
            }
            Err(e) => s += &ctx.problem("scenes", &format!("{} peer", case.name), e),
        }
    }
    if curves.is_empty() {
        return s + r#"<p class="note">No method could be measured on this scene.</p>"#;
    }
    s += &charts(case, &curves, &peers, noise);
    s += &shown_images(ctx, case, &curves, &reference, shown_budget);
    s += &equal_error(ctx, case, &curves, &peers, noise);
    s += &all_points(&curves);
    s
}

fn charts(case: &SceneCase, curves: &[Curve], peers: &[PeerCurve], noise: Option<f64>) -> String {
    let title = case.title.as_deref().unwrap_or(&case.name);
    let mut series: Vec<Series> = curves
        .iter()
        .map(|c| Series { name: c.label.clone(), points: c.points.iter().map(|p| (p.seconds, p.rmse)).collect() })
        .collect();
    let mut decor = Decor::default();
    for p in peers {
        decor.dashed.push(p.name.clone());
        series.push(Series { name: p.name.clone(), points: p.points.iter().map(|q| (q.1, q.2)).collect() });
    }
    if let Some(n) = noise {
        decor.hlines.push(("reference noise".into(), n));
    }
    let rmse = Chart {
        title: format!("{title}: RMSE against time"),
        x_label: "render time (s)".into(),
        y_label: "RMSE".into(),
        log_x: true,
        log_y: true,
        series,
    };
    let rel = Chart {
        title: format!("{title}: relMSE against time"),
        x_label: "render time (s)".into(),
        y_label: "relMSE".into(),
        log_x: true,
        log_y: true,
        series: curves
            .iter()
            .map(|c| Series { name: c.label.clone(), points: c.points.iter().map(|p| (p.seconds, p.relmse)).collect() })
            .collect(),
    };
    format!(r#"<div class="charts">{}{}</div>"#, rmse.to_svg_with(&decor), rel.to_svg())
}

/// Pixels whose centre sees an emitter or nothing (the background or environment) directly, and their neighbours.
fn direct_emission_mask(ctx: &Ctx, scene: &Path, w: u32, h: u32) -> Option<Vec<bool>> {
    let mut app = RenderJob { scene, size: Some((w, h)), ..Default::default() }.app(ctx);
    ctx.pool.install(|| app.setup()).ok()?;
    let scene = app.resources.scene().ok()?;
    let direct: Vec<bool> = (0..w * h)
        .map(|i| {
            let ray = scene.camera.generate_ray(glam::Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5));
            scene.trace(&ray).is_none_or(|s| s.light != prism_core::primitives::NO_LIGHT)
        })
        .collect();
    let at = |x: i64, y: i64| x >= 0 && y >= 0 && x < w as i64 && y < h as i64 && direct[(y * w as i64 + x) as usize];
    Some(
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as i64, (i / w) as i64);
                (-1..=1).any(|dy| (-1..=1).any(|dx| at(x + dx, y + dy)))
            })
            .collect(),
    )
}

fn shown_images(ctx: &mut Ctx, case: &SceneCase, curves: &[Curve], reference: &Image, at: Budget) -> String {
    let shown: Vec<(&Curve, &BudgetRender)> = curves.iter().filter_map(|c| c.shown.as_ref().map(|r| (c, r))).collect();
    if shown.is_empty() {
        return String::new();
    }
    let (w, h) = (reference.width, reference.height);
    let errors: Vec<Vec<f32>> = shown.iter().map(|(_, r)| images::abs_error(&r.image, reference)).collect();
    let max = images::quantile(errors.iter().flatten().copied(), 0.99).max(1e-6);
    let crop = case.crop.map(|(x, y, cw, ch)| (x.min(w - 1), y.min(h - 1), cw, ch)).unwrap_or_else(|| {
        let mut sq = vec![0f32; (w * h) as usize];
        for (_, r) in &shown {
            for (a, e) in sq.iter_mut().zip(images::squared_error(&r.image, reference)) {
                *a += e;
            }
        }
        // Emitters and the background seen directly differ only by their edges' aliasing: not where a method
        // struggles, so they are left out of the search.
        if let Some(mask) = direct_emission_mask(ctx, &case.scene, w, h)
            && mask.iter().any(|m| !m)
        {
            sq.iter_mut().zip(&mask).filter(|(_, m)| **m).for_each(|(v, _)| *v = 0.0);
        }
        images::hardest_region(&sq, w, h, (w / 4).max(8), (h / 4).max(8))
    });
    let crop = (crop.0, crop.1, crop.2.min(w - crop.0), crop.3.min(h - crop.1));
    let exposure = shown[0].1.exposure;
    let heading = match at {
        Budget::Seconds(t) => format!("At equal time: {} s each", num(t)),
        Budget::Spp(n) => format!("At equal samples: {n} spp each"),
    };
    let mut s = format!("<h3>{heading}</h3>");
    let width = html::shown_width(w, 256);
    let mut strip = String::new();
    let mut crops = String::new();
    let cw = html::shown_width(crop.2, 200).min(crop.2 * 8);
    let name = &case.name;
    let (path, rel) = ctx.picture(&format!("{name}-reference"));
    match images::write_thumbnail_boxed(&path, reference, exposure, Some(crop)) {
        Ok(()) => {
            strip += &format!(
                r#"<div class="pair">{}</div>"#,
                html::figure(&rel, "reference", width, "<b>reference</b><br>(box: the enlarged region)", "shot")
            )
        }
        Err(e) => strip += &ctx.problem("scenes", &format!("{name} picture"), e),
    }
    let (path, crel) = ctx.picture(&format!("{name}-reference-crop"));
    match images::write_thumbnail(&path, &reference.crop(crop.0, crop.1, crop.2, crop.3), exposure) {
        Ok(()) => crops += &html::figure(&crel, "reference region", cw, "<b>reference</b>", "crop"),
        Err(e) => crops += &ctx.problem("scenes", &format!("{name} picture"), e),
    }
    let ref_crop = reference.crop(crop.0, crop.1, crop.2, crop.3);
    for (i, ((c, r), err)) in shown.iter().zip(&errors).enumerate() {
        let m = compare(&r.image, reference).map(|m| m.rmse).unwrap_or(f64::NAN);
        let crop_img = r.image.crop(crop.0, crop.1, crop.2, crop.3);
        let crop_rmse = compare(&crop_img, &ref_crop).map(|m| m.rmse).unwrap_or(f64::NAN);
        let caption = format!("<b>{}</b><br>{} spp, {} s, RMSE {}", esc(&c.label), r.spp, num(r.seconds), num(m));
        let (p1, r1) = ctx.picture(&format!("{name}-m{i}"));
        let (p2, r2) = ctx.picture(&format!("{name}-m{i}-error"));
        let (p3, r3) = ctx.picture(&format!("{name}-m{i}-crop"));
        ctx.csv("maps.csv", MAPS_HEADER, format!("{r2},{},{},{},{max:.6e}", field(name), field(&c.label), r.spp));
        let written = images::write_thumbnail(&p1, &r.image, exposure)
            .and_then(|_| images::write_false_colour(&p2, err, w, h, max, images::viridis))
            .and_then(|_| images::write_thumbnail(&p3, &crop_img, exposure));
        if let Err(e) = written {
            strip += &ctx.problem("scenes", &format!("{name} picture"), e);
            continue;
        }
        strip += &format!(
            r#"<div class="pair">{}{}</div>"#,
            html::figure(&r1, &c.label, width, &caption, "shot"),
            html::figure(&r2, &format!("{} error", c.label), width, "error map", "map")
        );
        crops += &html::figure(
            &r3,
            &format!("{} region", c.label),
            cw,
            &format!("<b>{}</b><br>RMSE here {}", esc(&c.label), num(crop_rmse)),
            "crop",
        );
    }
    s += &format!(r#"<div class="strip">{strip}</div>"#);
    s += &html::colour_bar(
        images::viridis,
        max as f64,
        false,
        "|render - reference| (linear radiance, mean of RGB)",
        &format!("bar-{name}"),
    );
    let how = if case.crop.is_some() {
        "the suite's region"
    } else {
        "the window with the largest squared error (emitters and background seen directly left out)"
    };
    let _ = write!(
        s,
        r#"<h3>Hardest region: {} x {} pixels at ({}, {}), {how}, enlarged</h3><div class="strip">{crops}</div>"#,
        crop.2, crop.3, crop.0, crop.1
    );
    s
}

/// The columns of `maps.csv`: each error map, what it shows, and the error drawn at the top of its colour scale.
pub(super) const MAPS_HEADER: &str = "picture,case,method,spp,scale_max";

/// A curve's name, its (seconds, RMSE) points and its lowest RMSE.
type Timed = (String, Vec<(f64, f64)>, f64);

fn timed(name: &str, pts: Vec<(f64, f64)>) -> Timed {
    let low = pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    (name.to_string(), pts, low)
}

fn equal_error(ctx: &mut Ctx, case: &SceneCase, curves: &[Curve], peers: &[PeerCurve], noise: Option<f64>) -> String {
    let ours: Vec<Timed> =
        curves.iter().map(|c| timed(&c.label, c.points.iter().map(|p| (p.seconds, p.rmse)).collect())).collect();
    let theirs: Vec<Timed> =
        peers.iter().map(|p| timed(&p.name, p.points.iter().map(|q| (q.1, q.2)).collect())).collect();
    // The lowest error every one of our curves reaches: each one's time to it is interpolated, never extrapolated.
    let common = ours.iter().map(|c| c.2).fold(0.0, f64::max);
    let times: Vec<Option<f64>> = ours.iter().chain(&theirs).map(|c| time_to_error(&c.1, common)).collect();
    let fastest = times[..ours.len()].iter().flatten().copied().fold(f64::INFINITY, f64::min);
    let mut head =
        vec!["method".to_string(), "lowest RMSE".into(), format!("time to RMSE {}", num(common)), "relative".into()];
    head.extend(theirs.iter().map(|t| format!("speed-up over {}", t.0)));
    let mut rows = vec![];
    let header = "scene,target,target_rmse,method,seconds,ratio";
    for (i, (label, pts, low)) in ours.iter().chain(&theirs).enumerate() {
        let t = times[i];
        let mut row = vec![esc(label), num(*low)];
        row.push(t.map_or("-".into(), |t| format!("{} s", num(t))));
        row.push(t.map_or("-".into(), |t| {
            if i < ours.len() && t <= fastest * (1.0 + 1e-9) {
                "1 (fastest)".into()
            } else {
                format!("{}x", num(t / fastest))
            }
        }));
        ctx.csv(
            "equal_error.csv",
            header,
            format!(
                "{},common,{common:.6e},{},{},{}",
                field(&case.name),
                field(label),
                t.map_or(String::new(), |t| format!("{t:.6}")),
                t.map_or(String::new(), |t| format!("{:.4}", t / fastest))
            ),
        );
        for (pname, ppts, plow) in &theirs {
            if i >= ours.len() {
                row.push("-".into());
                continue;
            }
            // The lowest error both curves reach.
            let target = low.max(*plow);
            let ratio = time_to_error(pts, target).zip(time_to_error(ppts, target)).map(|(tm, tp)| (tm, tp / tm));
            row.push(ratio.map_or("-".into(), |(_, r)| format!("{}x at RMSE {}", num(r), num(target))));
            ctx.csv(
                "equal_error.csv",
                header,
                format!(
                    "{},{},{target:.6e},{},{},{}",
                    field(&case.name),
                    field(&format!("vs {pname}")),
                    field(label),
                    ratio.map_or(String::new(), |(tm, _)| format!("{tm:.6}")),
                    ratio.map_or(String::new(), |(_, r)| format!("{r:.4}"))
                ),
            );
        }
        rows.push(row);
    }
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut s = String::from("<h3>Equal-error time</h3>");
    s += r#"<p class="note">The time each curve needs to reach an error, interpolated in log-log between its measured points (never extrapolated). "Relative" divides by the fastest of Prism's methods at the lowest error all of them reach."#;
    if !theirs.is_empty() {
        s += " A speed-up over a peer is the peer's time divided by the method's at the lowest error both reach (above 1: Prism is faster; the peer's times are its own, from its CSV, measured on the same kind of machine).";
    }
    if let Some(n) = noise
        && common < 2.0 * n
    {
        let _ = write!(
            s,
            " The target is within twice the reference's own noise ({}), which flattens every curve there.",
            num(n)
        );
    }
    s += "</p>";
    s + &html::table(&head, &format!("lrrr{}", "r".repeat(theirs.len())), &rows, "ratios")
}

fn all_points(curves: &[Curve]) -> String {
    let rows: Vec<Vec<String>> = curves
        .iter()
        .flat_map(|c| {
            c.points.iter().map(|p| {
                vec![
                    esc(&c.label),
                    esc(&c.method.integrator),
                    c.method.sampler.map_or("scene's".into(), |s| s.name().to_string()),
                    budget_text(p.budget),
                    p.spp.to_string(),
                    num(p.seconds),
                    num(p.rmse),
                    num(p.relmse),
                ]
            })
        })
        .collect();
    format!(
        "<details><summary>All measurements ({} renders)</summary>{}</details>",
        rows.len(),
        html::table(
            &["method", "integrator", "sampler", "budget", "spp", "seconds", "RMSE", "relMSE"],
            "lllrrrrr",
            &rows,
            "points"
        )
    )
}
