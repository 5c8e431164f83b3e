//! Shadow acne, measured: from the surface point seen through each pixel centre, one shadow ray towards the scene's
//! first light (a point light), leaving the surface with one of several origin offsets (`suite::Offset`): none, a
//! fixed epsilon along the normal, or Prism's error-bounded offset (`geometry::spawn_ray_to`). The scenes are
//! convex objects that cannot shadow each other from the light, so a surface that faces the light is lit: every
//! shadow ray that reports an occluder there is a false shadow (the surface re-hitting itself). Pictures: lit
//! surfaces grey by their cosine, false shadows red, surfaces facing away dark.

use super::html::{self, esc};
use super::images;
use super::stability::card;
use super::suite::{AcneCase, Offset};
use super::{Ctx, RenderJob, field};
use glam::Vec2;
use prism_core::error::{PrismError, Result};
use prism_core::geometry::{Ray, spawn_ray_to};
use prism_core::scene::Scene;
use prism_core::settings::AccelKind;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// What one pixel shows.
#[derive(Clone, Copy, PartialEq)]
enum Seen {
    Nothing,
    FacingAway,
    Lit(f32),
    FalseShadow,
}

fn shadow_ray(scene: &Scene, ray: &Ray, offset: Offset) -> Seen {
    let Some(s) = scene.trace(ray) else {
        return Seen::Nothing;
    };
    let Some(l) = scene.lights.sample_li(0, &scene.prims, s.p, Vec2::splat(0.5)) else {
        return Seen::FacingAway;
    };
    // The side of the surface the camera sees.
    let n = if s.ng.dot(-ray.dir) >= 0.0 { s.ng } else { -s.ng };
    let cos = n.dot(l.wi);
    if cos <= 0.0 {
        return Seen::FacingAway;
    }
    let shadow = match offset {
        Offset::None => Ray::with_tmax(s.p, l.wi, l.dist * (1.0 - 1e-4)),
        Offset::Fixed(eps) => {
            let o = s.p + n * eps;
            let to = l.p - o;
            let d = to.length();
            Ray::with_tmax(o, to / d, d * (1.0 - 1e-4))
        }
        Offset::ErrorBounded => spawn_ray_to(s.p, s.p_err, s.ng, l.p, l.p_err, l.n),
    };
    if scene.occluded(&shadow) { Seen::FalseShadow } else { Seen::Lit(cos) }
}

/// The view of `path` at `size x size` under each offset: pictures (sRGB bytes) and `(false, lit-facing)` counts.
fn measure(ctx: &Ctx, path: &Path, offsets: &[Offset], size: u32) -> Result<Vec<(Vec<u8>, usize, usize)>> {
    if !path.is_file() {
        return Err(PrismError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, "scene file not found")));
    }
    let job = RenderJob { scene: path, accel: Some(AccelKind::Bvh), size: Some((size, size)), ..Default::default() };
    let mut app = job.app(ctx);
    ctx.pool.install(|| app.setup())?;
    let scene = app.resources.scene()?;
    if scene.lights.is_empty() || !scene.lights.is_delta(0) {
        return Err(PrismError::invalid(format!("{}: the first light must be a point light", path.display())));
    }
    let mut out = vec![];
    for &offset in offsets {
        let seen: Vec<Seen> = ctx.pool.install(|| {
            (0..size * size)
                .into_par_iter()
                .map(|i| {
                    let px = Vec2::new((i % size) as f32 + 0.5, (i / size) as f32 + 0.5);
                    shadow_ray(scene, &scene.camera.generate_ray(px), offset)
                })
                .collect()
        });
        let lit_facing = seen.iter().filter(|s| matches!(s, Seen::Lit(_) | Seen::FalseShadow)).count();
        let false_shadows = seen.iter().filter(|s| **s == Seen::FalseShadow).count();
        let bytes = seen
            .iter()
            .flat_map(|s| match *s {
                Seen::Nothing => [18, 22, 30],
                Seen::FacingAway => [52, 56, 66],
                Seen::Lit(c) => {
                    let v = 90.0 + 160.0 * c;
                    [v as u8, v as u8, (v + 5.0).min(255.0) as u8]
                }
                Seen::FalseShadow => [230, 40, 40],
            })
            .collect();
        out.push((bytes, false_shadows, lit_facing));
    }
    Ok(out)
}

pub(super) fn case(ctx: &mut Ctx, c: &AcneCase) -> String {
    let mut s = card(&c.name, &c.title, &c.caption);
    let width = html::shown_width(c.size, 160);
    let mut rows = vec![];
    for (si, (label, path)) in c.scenes.iter().enumerate() {
        ctx.log(format!("stability: {} / {label}", c.name));
        let measured = match measure(ctx, path, &c.offsets, c.size) {
            Ok(m) => m,
            Err(e) => {
                s += &ctx.problem("stability", &format!("{} / {label}", c.name), e);
                continue;
            }
        };
        let mut strip = String::new();
        for (oi, (offset, (bytes, bad, lit))) in c.offsets.iter().zip(&measured).enumerate() {
            let share = 100.0 * *bad as f64 / (*lit).max(1) as f64;
            let (p, rel) = ctx.picture(&format!("{}-s{si}-o{oi}", c.name));
            if let Err(e) = images::write_rgb8(&p, bytes, c.size, c.size) {
                strip += &ctx.problem("stability", &format!("{} / {label}", c.name), e);
                continue;
            }
            let caption = format!("<b>{}</b><br>{share:.1}% false shadows", esc(&offset.label()));
            strip += &html::figure(&rel, &format!("{label}, {}", offset.label()), width, &caption, "shot");
            rows.push(vec![esc(label), esc(&offset.label()), format!("{share:.2}%"), format!("{bad} of {lit}")]);
            ctx.csv(
                "stability.csv",
                "case,variant,metric,value",
                format!(
                    "{},{},false_shadow_percent,{share:.4}",
                    field(&c.name),
                    field(&format!("{label} / {}", offset.label()))
                ),
            );
        }
        let _ = write!(s, r#"<p class="note"><b>{}</b></p><div class="strip">{strip}</div>"#, esc(label));
    }
    s += &html::table(&["scene", "shadow-ray origin", "false shadows", "lit-facing pixels"], "llrr", &rows, "measured");
    s + "</article>"
}
