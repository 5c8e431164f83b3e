//! The stability atlas: each known failure mode as captioned pictures with its measured effect. Three kinds of case
//! (`suite::StabilityCase`): renders of variants (parameters, scenes, inputs that must be rejected) measured
//! against a reference, over a region, and for non-finite samples; accelerators on one view (`traversal.rs`);
//! shadow rays with several ray-origin offsets (`acne.rs`).

use super::html::{self, esc, num};
use super::images::{self, fit_reference};
use super::suite::{Reference, RendersCase, StabilityCase, TraversalCase};
use super::{Ctx, RenderJob, field, traversal};
use crate::compare::compare;
use crate::converge::{Budget, BudgetRender};
use prism_core::io::{Image, read_image};
use std::fmt::Write as _;

pub(super) fn section(ctx: &mut Ctx, cases: &[StabilityCase]) -> String {
    let mut s = String::from(
        r#"<section id="stability"><h2>Stability atlas</h2><p class="caption">Where methods fail: each known failure mode, pictured, with what it does to the measurements.</p><div class="cases">"#,
    );
    for case in cases {
        ctx.log(format!("stability: {}", case.name()));
        s += &match case {
            StabilityCase::Renders(c) => renders(ctx, c),
            StabilityCase::Traversal(c) => traversal_case(ctx, c),
            StabilityCase::ShadowAcne(c) => super::acne::case(ctx, c),
        };
    }
    s + "</div></section>"
}

/// The opening of a case's card.
pub(super) fn card(name: &str, title: &str, caption: &str) -> String {
    let mut s = format!(r#"<article class="case" id="stab-{}"><h3>{}</h3>"#, esc(name), esc(title));
    if !caption.is_empty() {
        let _ = write!(s, r#"<p class="caption">{caption}</p>"#);
    }
    s
}

fn traversal_case(ctx: &mut Ctx, c: &TraversalCase) -> String {
    let mut s = card(&c.name, &c.title, &c.caption);
    match traversal::measure(ctx, &c.scene, &c.accels, c.size, Some(c.seconds)) {
        Ok((prims, rows)) => {
            let _ = write!(s, r#"<p class="note">{prims} primitives, {0}x{0} camera rays.</p>"#, c.size);
            s += &traversal::figures(ctx, &c.name, &rows, &c.accels, c.size, c.count, None);
        }
        Err(e) => s += &ctx.problem("stability", &c.name, e),
    }
    s + "</article>"
}

fn renders(ctx: &mut Ctx, c: &RendersCase) -> String {
    let mut s = card(&c.name, &c.title, &c.caption);
    let first_scene = c.scene.clone().or_else(|| c.variants[0].scene.clone()).expect("suite checked: a scene");
    let size = match c.size {
        Some(size) => Some(size),
        None if c.reference.is_some() => match (RenderJob { scene: &first_scene, ..Default::default() }).size_of(ctx) {
            Ok(size) => Some(size),
            Err(e) => return s + &ctx.problem("stability", &c.name, e) + "</article>",
        },
        None => None,
    };
    let reference: Option<Image> = match (&c.reference, size) {
        (Some(Reference::File(path)), Some((w, h))) => {
            match read_image(path).map_err(|e| e.to_string()).and_then(|img| fit_reference(img, w, h)) {
                Ok((img, _)) => Some(img),
                Err(e) => return s + &ctx.problem("stability", &format!("{} reference", c.name), e) + "</article>",
            }
        }
        (Some(Reference::Render(r)), Some(size)) => {
            let job = RenderJob {
                scene: r.scene.as_ref().unwrap_or(&first_scene),
                integrator: Some(&r.integrator),
                sampler: r.sampler,
                size: Some(size),
                seed: Some(r.seed.unwrap_or(1_000_003)),
                ..Default::default()
            };
            match job.render(ctx, Budget::Spp(r.spp)) {
                Ok(out) => Some(out.image),
                Err(e) => return s + &ctx.problem("stability", &format!("{} reference", c.name), e) + "</article>",
            }
        }
        _ => None,
    };
    let mut results: Vec<(usize, std::result::Result<BudgetRender, String>)> = vec![];
    for (i, v) in c.variants.iter().enumerate() {
        let scene = v.scene.as_ref().unwrap_or(&first_scene);
        let accel = match v.accel.as_deref().map(|a| super::parse_accel(a, None)).transpose() {
            Ok(a) => a,
            Err(e) => {
                results.push((i, Err(e.to_string())));
                continue;
            }
        };
        let job = RenderJob {
            scene,
            integrator: v.integrator.as_deref(),
            sampler: v.sampler,
            accel,
            size,
            ..Default::default()
        };
        let budget = match (v.time, v.spp) {
            (Some(t), _) => Budget::Seconds(t),
            (None, n) => Budget::Spp(n.unwrap_or(16)),
        };
        ctx.log(format!("stability: {} / {}", c.name, v.label));
        results.push((i, job.render(ctx, budget).map_err(|e| e.to_string())));
    }
    let max_err = reference.as_ref().map(|r| {
        let errs = results
            .iter()
            .filter_map(|(_, o)| o.as_ref().ok())
            .filter(|o| (o.image.width, o.image.height) == (r.width, r.height))
            .flat_map(|o| images::abs_error(&o.image, r));
        images::quantile(errs, 0.99).max(1e-6)
    });
    let (mut strip, mut rows) = (String::new(), vec![]);
    let mut exposure = None;
    for (i, out) in &results {
        let v = &c.variants[*i];
        let item = format!("{} / {}", c.name, v.label);
        match (out, v.expect_error) {
            (Err(e), true) => {
                strip += &format!(
                    r#"<figure class="shot"><div class="rejected"><b>rejected, as it should be</b><code>error: {}</code></div><figcaption><b>{}</b>{}</figcaption></figure>"#,
                    esc(e),
                    esc(&v.label),
                    note(&v.note)
                );
                rows.push(vec![
                    esc(&v.label),
                    "rejected".into(),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                ]);
                ctx.csv(
                    "stability.csv",
                    "case,variant,metric,value",
                    format!("{},{},error,{}", field(&c.name), field(&v.label), field(e)),
                );
            }
            (Err(e), false) => {
                strip += &html::failed_figure(220, &v.label, e);
                ctx.problem("stability", &item, e);
            }
            (Ok(_), true) => {
                strip += &html::failed_figure(220, &v.label, "expected an error, but the render succeeded");
                ctx.problem("stability", &item, "expected an error, but the render succeeded");
            }
            (Ok(o), false) => {
                let exposure = *exposure.get_or_insert(o.exposure);
                let (path, rel) = ctx.picture(&format!("{}-v{i}", c.name));
                let shown = html::shown_width(o.image.width, 200);
                let metrics = reference.as_ref().and_then(|r| compare(&o.image, r).ok());
                let mut caption = format!("<b>{}</b><br>{} spp, {} s", esc(&v.label), o.spp, num(o.seconds));
                if let Some(m) = &metrics {
                    let _ = write!(caption, ", RMSE {}", num(m.rmse));
                }
                caption += &note(&v.note);
                let mut pair = match images::write_thumbnail_boxed(&path, &o.image, exposure, c.region) {
                    Ok(()) => html::figure(&rel, &v.label, shown, &caption, "shot"),
                    Err(e) => ctx.problem("stability", &item, e),
                };
                if let (Some(r), Some(max)) = (&reference, max_err)
                    && metrics.is_some()
                {
                    let (p2, r2) = ctx.picture(&format!("{}-v{i}-error", c.name));
                    let err = images::abs_error(&o.image, r);
                    ctx.csv(
                        "maps.csv",
                        super::convergence::MAPS_HEADER,
                        format!("{r2},{},{},{},{max:.6e}", field(&c.name), field(&v.label), o.spp),
                    );
                    pair += &match images::write_false_colour(&p2, &err, r.width, r.height, max, images::viridis) {
                        Ok(()) => html::figure(&r2, &format!("{} error", v.label), shown, "error map", "map"),
                        Err(e) => ctx.problem("stability", &item, e),
                    };
                }
                strip += &format!(r#"<div class="pair">{pair}</div>"#);
                let mean_vs = metrics.as_ref().map(|m| {
                    let (a, b): (f64, f64) = (m.mean_test.iter().sum(), m.mean_reference.iter().sum());
                    100.0 * (a - b) / b.abs().max(1e-12)
                });
                let region = c.region.map(|r| images::region_mean(&o.image, r));
                let nan_pixels = images::nonfinite_pixels(&o.image);
                rows.push(vec![
                    esc(&v.label),
                    format!("{} spp, {} s", o.spp, num(o.seconds)),
                    metrics.as_ref().map_or("-".into(), |m| num(m.rmse)),
                    mean_vs.map_or("-".into(), |d| format!("{d:+.2}%")),
                    region.map_or("-".into(), |m| if m == 0.0 { "0 (exactly)".into() } else { num(m) }),
                    o.nonfinite.to_string(),
                    nan_pixels.to_string(),
                ]);
                let mut put = |metric: &str, value: String| {
                    ctx.csv(
                        "stability.csv",
                        "case,variant,metric,value",
                        format!("{},{},{metric},{value}", field(&c.name), field(&v.label)),
                    )
                };
                put("spp", o.spp.to_string());
                put("seconds", format!("{:.6}", o.seconds));
                if let Some(m) = &metrics {
                    put("rmse", format!("{:.6e}", m.rmse));
                    put("relmse", format!("{:.6e}", m.relmse));
                }
                if let Some(d) = mean_vs {
                    put("mean_vs_reference_percent", format!("{d:.4}"));
                }
                if let Some(m) = region {
                    put("region_mean", format!("{m:.6e}"));
                }
                put("nonfinite_samples", o.nonfinite.to_string());
                put("nonfinite_pixels", nan_pixels.to_string());
            }
        }
    }
    s += &format!(r#"<div class="strip">{strip}</div>"#);
    if let Some(max) = max_err {
        s += &html::colour_bar(images::viridis, max as f64, false, "|render - reference|", &format!("bar-{}", c.name));
    }
    let region_head = c.region_label.clone().unwrap_or_else(|| "region mean".into());
    s += &html::table(
        &["variant", "budget", "RMSE", "mean vs reference", &region_head, "NaN/Inf samples dropped", "NaN pixels"],
        "lrrrrrr",
        &rows,
        "measured",
    );
    s + "</article>"
}

fn note(n: &str) -> String {
    if n.is_empty() { String::new() } else { format!("<br>{n}") }
}
