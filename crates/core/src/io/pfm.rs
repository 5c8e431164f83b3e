//! Portable float maps (`.pfm`, the format of pbrt-v4's environment maps): a text header `PF` (RGB) or `Pf`
//! (grey), `width height`, and a scale whose sign gives the byte order (negative: little-endian), then
//! `width * height` pixels of 32-bit floats stored from the bottom row up. The claimed size is checked against the
//! input cap and against the bytes present before anything is allocated; the scale's magnitude is ignored, as
//! pbrt-v4 ignores it.

use super::Image;
use super::files::read_regular;
use crate::error::{PrismError, Result};
use crate::limits::check_input_image_size;
use glam::Vec3;
use std::path::Path;

/// A PFM file, linear RGB (grey maps repeated in all three channels), rows from the top.
pub fn read_pfm_file(path: &Path) -> Result<Image> {
    read_pfm_bytes(&read_regular(path, "image file")?, path)
}

/// A PFM image from bytes in memory (`path` only names it in errors).
pub fn read_pfm_bytes(bytes: &[u8], path: &Path) -> Result<Image> {
    let bad = |m: &str| PrismError::format(path, format!("PFM: {m}"));
    // Three whitespace-separated header fields after the magic, the last followed by one whitespace byte.
    let mut at = 0;
    let mut token = || -> Option<&[u8]> {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() && at - start < 64 {
            at += 1;
        }
        (at > start).then(|| &bytes[start..at])
    };
    let channels = match token() {
        Some(b"PF") => 3,
        Some(b"Pf") => 1,
        _ => return Err(bad("not a portable float map (expected `PF` or `Pf`)")),
    };
    let mut number = |what: &str| -> Result<f64> {
        token()
            .and_then(|t| std::str::from_utf8(t).ok())
            .and_then(|t| t.parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(&format!("bad {what} in the header")))
    };
    let (w, h, scale) = (number("width")?, number("height")?, number("scale")?);
    if w.fract() != 0.0 || h.fract() != 0.0 || w < 0.0 || h < 0.0 || w > u32::MAX as f64 || h > u32::MAX as f64 {
        return Err(bad("the width and height must be whole numbers"));
    }
    if scale == 0.0 {
        return Err(bad("the scale must not be 0 (its sign gives the byte order)"));
    }
    let (w, h) = (w as u64, h as u64);
    check_input_image_size(w, h).map_err(|m| bad(&m))?;
    let data_start = at + 1;
    let need = w * h * channels * 4;
    if (bytes.len() as u64) < data_start as u64 + need {
        return Err(bad(&format!("the file is truncated ({w}x{h} needs {need} bytes of pixels)")));
    }
    let little = scale < 0.0;
    let data = &bytes[data_start..data_start + need as usize];
    let value = |i: usize| {
        let b: [u8; 4] = data[4 * i..4 * i + 4].try_into().expect("4 bytes");
        if little { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) }
    };
    let (wu, hu, c) = (w as usize, h as usize, channels as usize);
    let mut pixels = Vec::with_capacity(wu * hu);
    for row in (0..hu).rev() {
        for x in 0..wu {
            let i = (row * wu + x) * c;
            pixels.push(if c == 3 { Vec3::new(value(i), value(i + 1), value(i + 2)) } else { Vec3::splat(value(i)) });
        }
    }
    Ok(Image::new(w as u32, h as u32, pixels))
}
