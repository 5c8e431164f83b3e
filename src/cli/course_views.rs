//! The 6.837 assignment 7 visualisations that are images, not renders:
//! - `-render_samples FILE ZOOM`: each pixel drawn as a `ZOOM x ZOOM` block (alternating dark greys, so pixel
//!   borders show) with the positions of its samples as white dots — the pattern the render uses (`random`,
//!   `uniform`, `jittered` = stratified), one block per pixel;
//! - `-render_filter FILE ZOOM`: the filter's weight around the centre pixel, `ZOOM` texels per pixel, white = the
//!   largest weight (the filter as the render samples it: Prism draws each sample's offset from this weight).

use glam::{Vec2, Vec3};
use prism_core::io::{Image, write_image};
use prism_core::sampling::{PixelFilter, PixelPattern, Rng, hash_u64};
use std::path::Path;

/// Largest visualisation accepted (pixels per side).
const MAX_SIDE: u64 = 8192;

fn checked_size(w: u32, h: u32, zoom: u32) -> Result<(u32, u32), prism_core::error::PrismError> {
    let (zw, zh) = (w as u64 * zoom as u64, h as u64 * zoom as u64);
    if zoom == 0 || zw > MAX_SIDE || zh > MAX_SIDE {
        return Err(prism_core::error::PrismError::invalid(format!(
            "zoom {zoom} for a {w}x{h} image is out of range (1 to {MAX_SIDE} pixels per side)"
        )));
    }
    Ok((zw as u32, zh as u32))
}

/// The sample positions of every pixel (`n` samples, `pattern`, seed 0 as the render).
pub fn render_samples(
    path: &Path,
    (w, h): (u32, u32),
    zoom: u32,
    pattern: PixelPattern,
    filter: PixelFilter,
    n: u32,
) -> prism_core::error::Result<()> {
    let (zw, zh) = checked_size(w, h, zoom)?;
    let mut px = vec![Vec3::ZERO; (zw * zh) as usize];
    for y in 0..zh {
        for x in 0..zw {
            let shade = if (x / zoom + y / zoom).is_multiple_of(2) { 0.15 } else { 0.25 };
            px[(y * zw + x) as usize] = Vec3::splat(shade);
        }
    }
    for py in 0..h {
        for pxl in 0..w {
            let pixel = py as u64 * w as u64 + pxl as u64;
            let key = hash_u64(hash_u64(pixel)) as u32;
            let mut rng = Rng::for_pixel(0, pixel, 0);
            for i in 0..n {
                let u = pattern.offset(i, n, key, &mut rng);
                let p = Vec2::new(pxl as f32 + 0.5, py as f32 + 0.5) + filter.warp(u);
                let (sx, sy) = ((p.x * zoom as f32) as i64, (p.y * zoom as f32) as i64);
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (-1, 0), (0, -1)] {
                    let (x, y) = (sx + dx, sy + dy);
                    if x >= 0 && y >= 0 && x < zw as i64 && y < zh as i64 {
                        px[(y as u32 * zw + x as u32) as usize] = Vec3::ONE;
                    }
                }
            }
        }
    }
    write_image(path, &Image::new(zw, zh, px), 0.0)
}

/// The filter's weight over the image, centred on its centre pixel.
pub fn render_filter(path: &Path, (w, h): (u32, u32), zoom: u32, filter: PixelFilter) -> prism_core::error::Result<()> {
    let (zw, zh) = checked_size(w, h, zoom)?;
    let centre = Vec2::new((w / 2) as f32 + 0.5, (h / 2) as f32 + 0.5);
    let peak = filter.weight(Vec2::ZERO).max(1e-30);
    let mut px = Vec::with_capacity((zw * zh) as usize);
    for y in 0..zh {
        for x in 0..zw {
            let p = Vec2::new((x as f32 + 0.5) / zoom as f32, (y as f32 + 0.5) / zoom as f32);
            px.push(Vec3::splat(filter.weight(p - centre) / peak));
        }
    }
    write_image(path, &Image::new(zw, zh, px), 0.0)
}
