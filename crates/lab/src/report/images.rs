//! The report's pictures: tone-mapped PNG thumbnails, false-colour maps (per-pixel error, traversal work) with a
//! perceptual colour scale, the box-filtered reduction of a reference to the render's size, and the search for
//! the hardest region (the window with the largest squared error, by a summed-area table).

use glam::{DVec3, Vec3};
use prism_core::error::{PrismError, Result};
use prism_core::io::Image;
use std::path::Path;

/// Viridis at 0, 0.1, ..., 1 (sRGB bytes): perceptually uniform, readable in grey and by colour-blind readers.
pub const VIRIDIS: [[u8; 3]; 11] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x24, 0x75],
    [0x41, 0x44, 0x87],
    [0x35, 0x5f, 0x8d],
    [0x2a, 0x78, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x22, 0xa8, 0x84],
    [0x44, 0xbf, 0x70],
    [0x7a, 0xd1, 0x51],
    [0xbd, 0xdf, 0x26],
    [0xfd, 0xe7, 0x25],
];

/// A colour scale: sRGB colour of `t` in [0, 1].
pub type Scale = fn(f32) -> [u8; 3];

/// Viridis, linearly interpolated between its stops.
pub fn viridis(t: f32) -> [u8; 3] {
    let x = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } * (VIRIDIS.len() - 1) as f32;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f32;
    std::array::from_fn(|c| (VIRIDIS[i][c] as f32 * (1.0 - f) + VIRIDIS[i + 1][c] as f32 * f + 0.5) as u8)
}

/// The heat maps' ramp of `debug(mode: heat)` (black, purple, red, orange, yellow, white).
pub fn heat(t: f32) -> [u8; 3] {
    let c = prism_debug::ramp(if t.is_nan() { 0.0 } else { t });
    [c.x, c.y, c.z].map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}

/// Write `values` (row-major, `w x h`) as a PNG coloured by `scale` from 0 to `max`: an indexed PNG whose palette
/// is the scale at 256 levels (a third of the bytes of the same colours as RGB).
pub fn write_false_colour(path: &Path, values: &[f32], w: u32, h: u32, max: f32, scale: Scale) -> Result<()> {
    let inv = if max > 0.0 { 1.0 / max } else { 0.0 };
    let index: Vec<u8> = values
        .iter()
        .map(|&v| {
            let t = v * inv;
            if t.is_nan() { 0 } else { (t.clamp(0.0, 1.0) * 255.0 + 0.5) as u8 }
        })
        .collect();
    let palette: Vec<u8> = (0..256).flat_map(|i| scale(i as f32 / 255.0)).collect();
    let mut png = Vec::new();
    let mut enc = png::Encoder::new(&mut png, w, h);
    enc.set_color(png::ColorType::Indexed);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_palette(palette);
    enc.set_compression(png::Compression::High);
    let mut writer = enc.write_header().map_err(|e| PrismError::format(path, format!("cannot write PNG: {e}")))?;
    writer.write_image_data(&index).map_err(|e| PrismError::format(path, format!("cannot write PNG: {e}")))?;
    writer.finish().map_err(|e| PrismError::format(path, format!("cannot write PNG: {e}")))?;
    prism_core::io::write_atomic(path, &png)
}

/// Write 8-bit sRGB pixels as a PNG (atomically).
pub fn write_rgb8(path: &Path, bytes: &[u8], w: u32, h: u32) -> Result<()> {
    let mut png = Vec::new();
    let enc = image::codecs::png::PngEncoder::new_with_quality(
        &mut png,
        image::codecs::png::CompressionType::Best,
        image::codecs::png::FilterType::Adaptive,
    );
    image::ImageEncoder::write_image(enc, bytes, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| PrismError::format(path, format!("cannot write PNG: {e}")))?;
    prism_core::io::write_atomic(path, &png)
}

/// A linear image as 8-bit sRGB after `exposure` stops (non-finite values black).
pub fn srgb_bytes(img: &Image, exposure: f32) -> Vec<u8> {
    let scale = 2f32.powf(exposure);
    img.pixels
        .iter()
        .flat_map(|p| {
            [p.x, p.y, p.z].map(|c| {
                let v = if c.is_finite() { (c * scale).clamp(0.0, 1.0) } else { 0.0 };
                (prism_core::io::linear_to_srgb(v) * 255.0 + 0.5) as u8
            })
        })
        .collect()
}

/// A linear image as an sRGB PNG after `exposure` stops (the thumbnails).
pub fn write_thumbnail(path: &Path, img: &Image, exposure: f32) -> Result<()> {
    write_thumbnail_boxed(path, img, exposure, None)
}

/// [`write_thumbnail`] with the outline of the rectangle `(x, y, w, h)` drawn on it (white, dark inside edge).
pub fn write_thumbnail_boxed(
    path: &Path,
    img: &Image,
    exposure: f32,
    rect: Option<(u32, u32, u32, u32)>,
) -> Result<()> {
    let mut bytes = srgb_bytes(img, exposure);
    if let Some((x, y, w, h)) = rect {
        let (iw, ih) = (img.width as i64, img.height as i64);
        let mut put = |px: i64, py: i64, c: u8| {
            if (0..iw).contains(&px) && (0..ih).contains(&py) {
                let i = 3 * (py * iw + px) as usize;
                bytes[i..i + 3].copy_from_slice(&[c, c, c]);
            }
        };
        let (x0, y0, x1, y1) = (x as i64 - 1, y as i64 - 1, (x + w) as i64, (y + h) as i64);
        for (d, c) in [(0, 255u8), (1, 30)] {
            for px in x0 + d..=x1 - d {
                put(px, y0 + d, c);
                put(px, y1 - d, c);
            }
            for py in y0 + d..=y1 - d {
                put(x0 + d, py, c);
                put(x1 - d, py, c);
            }
        }
    }
    write_rgb8(path, &bytes, img.width, img.height)
}

/// Per-pixel absolute error `|a - r|`, mean over the three channels (linear radiance).
pub fn abs_error(test: &Image, reference: &Image) -> Vec<f32> {
    test.pixels.iter().zip(&reference.pixels).map(|(a, r)| (*a - *r).abs().element_sum() / 3.0).collect()
}

/// The `q` quantile (0..1) of the finite values (0 when there are none).
pub fn quantile(values: impl Iterator<Item = f32>, q: f64) -> f32 {
    let mut v: Vec<f32> = values.filter(|v| v.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f32::total_cmp);
    v[((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize]
}

/// `img` reduced by an integer `factor` with a box filter: each pixel the mean of its `factor x factor` block.
pub fn downsample(img: &Image, factor: u32) -> Image {
    let (w, h) = (img.width / factor, img.height / factor);
    let mut px = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut s = DVec3::ZERO;
            for dy in 0..factor {
                for dx in 0..factor {
                    s += img.get(x * factor + dx, y * factor + dy).as_dvec3();
                }
            }
            px.push((s / (factor * factor) as f64).as_vec3());
        }
    }
    Image::new(w, h, px)
}

/// A reference brought to the render's `w x h`: itself, or box-filtered down by the integer factor that relates
/// the sizes; an error naming both sizes otherwise.
pub fn fit_reference(reference: Image, w: u32, h: u32) -> std::result::Result<(Image, u32), String> {
    if (reference.width, reference.height) == (w, h) {
        return Ok((reference, 1));
    }
    let f = reference.width / w.max(1);
    if f >= 2 && reference.width == f * w && reference.height == f * h {
        return Ok((downsample(&reference, f), f));
    }
    Err(format!(
        "the reference is {}x{} but the render is {w}x{h} (neither the same size nor an integer multiple)",
        reference.width, reference.height
    ))
}

/// The `rw x rh` window (clipped to the image) with the largest sum of `values` (row-major, `w x h`): `(x, y, w, h)`.
pub fn hardest_region(values: &[f32], w: u32, h: u32, rw: u32, rh: u32) -> (u32, u32, u32, u32) {
    let (rw, rh) = (rw.clamp(1, w.max(1)), rh.clamp(1, h.max(1)));
    let (wu, hu) = (w as usize, h as usize);
    if values.len() != wu * hu || wu == 0 || hu == 0 {
        return (0, 0, rw, rh);
    }
    // Summed-area table with a zero first row and column, in f64 (exact enough for any image size).
    let mut sat = vec![0f64; (wu + 1) * (hu + 1)];
    for y in 0..hu {
        let mut row = 0f64;
        for x in 0..wu {
            let v = values[y * wu + x];
            row += if v.is_finite() { v as f64 } else { 0.0 };
            sat[(y + 1) * (wu + 1) + x + 1] = sat[y * (wu + 1) + x + 1] + row;
        }
    }
    let at = |x: usize, y: usize| sat[y * (wu + 1) + x];
    let (mut best, mut arg) = (f64::NEG_INFINITY, (0, 0));
    for y in 0..=hu - rh as usize {
        for x in 0..=wu - rw as usize {
            let (x1, y1) = (x + rw as usize, y + rh as usize);
            let s = at(x1, y1) - at(x, y1) - at(x1, y) + at(x, y);
            if s > best {
                best = s;
                arg = (x, y);
            }
        }
    }
    (arg.0 as u32, arg.1 as u32, rw, rh)
}

/// Per-pixel squared error summed over channels (for [`hardest_region`]).
pub fn squared_error(test: &Image, reference: &Image) -> Vec<f32> {
    test.pixels.iter().zip(&reference.pixels).map(|(a, r)| (*a - *r).length_squared()).collect()
}

/// Mean of `img` over the rectangle `(x, y, w, h)` (clipped), as the mean of the three channels.
pub fn region_mean(img: &Image, (x, y, w, h): (u32, u32, u32, u32)) -> f64 {
    let c = img.crop(x, y, w, h);
    let m: Vec3 = c.mean();
    (m.x as f64 + m.y as f64 + m.z as f64) / 3.0
}

/// Pixels of `img` with a NaN or infinite channel.
pub fn nonfinite_pixels(img: &Image) -> usize {
    img.pixels.iter().filter(|p| !p.is_finite()).count()
}
