//! Decoding OpenEXR and Radiance HDR images from untrusted bytes. The header's claimed size is checked before
//! anything is allocated from it: against the documented cap ([`crate::limits::MAX_INPUT_IMAGE_PIXELS`]) and
//! against the bytes the file actually holds (at least what the format needs at its best compression: for EXR one
//! 8-byte offset-table entry and an 8-byte chunk header per chunk, plus every pixel byte when uncompressed; for
//! HDR 8 bytes per scanline, the shortest run-length encoding of a row). A forged header is a one-line error naming
//! the file, never an allocation failure.
//!
//! The `_from` functions read any `Read + Seek` source of known length (a file, or bytes in memory for fuzzing).

use super::Image;
use super::files::open_regular;
use crate::error::{PrismError, Result};
use crate::limits::check_input_image_size;
use glam::Vec3;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// An OpenEXR file's first RGB(A) layer, linear f32.
pub fn read_exr_file(path: &Path) -> Result<Image> {
    let (file, len) = open_regular(path, "image file")?;
    read_exr_from(BufReader::new(file), len, path)
}

/// An OpenEXR image from bytes in memory (`name` only names it in errors).
pub fn read_exr_bytes(bytes: &[u8], name: &Path) -> Result<Image> {
    read_exr_from(std::io::Cursor::new(bytes), bytes.len() as u64, name)
}

/// An OpenEXR image from `source` of `len` bytes: the header is checked before the pixels are allocated.
pub fn read_exr_from<R: Read + Seek>(mut source: R, len: u64, path: &Path) -> Result<Image> {
    let bad = |m: String| PrismError::format(path, m);
    let meta = exr::meta::MetaData::read_from_buffered(&mut source, false)
        .map_err(|e| bad(format!("cannot read EXR: {e}")))?;
    let mut needed: u64 = 0;
    let mut claimed = (0, 0);
    for h in &meta.headers {
        let (w, hh) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        check_input_image_size(w, hh).map_err(|m| bad(format!("EXR {m}")))?;
        claimed = (w, hh);
        // Every chunk has an 8-byte offset-table entry and at least an 8-byte header in the file.
        needed = needed.saturating_add((h.chunk_count as u64).saturating_mul(16));
        if !h.deep && h.compression == exr::compression::Compression::Uncompressed {
            needed = needed.saturating_add(h.total_pixel_bytes() as u64);
        }
    }
    if needed > len {
        return Err(bad(format!(
            "EXR header claims a {}x{} image that needs at least {needed} bytes, but the file holds {len}",
            claimed.0, claimed.1
        )));
    }
    source.seek(SeekFrom::Start(0)).map_err(|e| PrismError::io(path, e))?;
    use exr::prelude::{ReadChannels, ReadLayers};
    let img = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(create_pixels, set_pixel)
        .first_valid_layer()
        .all_attributes()
        .from_buffered(source)
        .map_err(|e| bad(format!("cannot read EXR: {e}")))?;
    let (w, px) = img.layer_data.channel_data.pixels;
    let h = px.len() / w.max(1);
    if w == 0 || h == 0 {
        return Err(bad("EXR image has no pixels".into()));
    }
    Ok(Image::new(w as u32, h as u32, px))
}

/// The pixel buffer of an EXR layer whose size has been checked.
fn create_pixels(res: exr::math::Vec2<usize>, _: &exr::image::RgbaChannels) -> (usize, Vec<Vec3>) {
    (res.width(), vec![Vec3::ZERO; res.width() * res.height()])
}

fn set_pixel(px: &mut (usize, Vec<Vec3>), pos: exr::math::Vec2<usize>, (r, g, b, _a): (f32, f32, f32, f32)) {
    let w = px.0;
    if let Some(p) = px.1.get_mut(pos.y() * w + pos.x()) {
        *p = Vec3::new(r, g, b);
    }
}

/// A Radiance HDR (RGBE) file, linear f32.
pub fn read_hdr_file(path: &Path) -> Result<Image> {
    let (file, len) = open_regular(path, "image file")?;
    read_hdr_from(BufReader::new(file), len, path)
}

/// A Radiance HDR image from bytes in memory (`name` only names it in errors).
pub fn read_hdr_bytes(bytes: &[u8], name: &Path) -> Result<Image> {
    read_hdr_from(std::io::Cursor::new(bytes), bytes.len() as u64, name)
}

/// A Radiance HDR image from `source` of `len` bytes: the header is checked before the pixels are allocated.
pub fn read_hdr_from<R: BufRead>(source: R, len: u64, path: &Path) -> Result<Image> {
    use image::ImageDecoder;
    let bad = |m: String| PrismError::format(path, m);
    let decoder = image::codecs::hdr::HdrDecoder::new(source)
        .map_err(|e| bad(format!("not a readable Radiance HDR file: {e}")))?;
    let (w, h) = decoder.dimensions();
    check_input_image_size(w as u64, h as u64).map_err(|m| bad(format!("HDR {m}")))?;
    // The shortest scanline: one pixel and one run-length marker (old RLE), 8 bytes; 4 for one-pixel rows.
    let needed = h as u64 * if w > 1 { 8 } else { 4 };
    if needed > len {
        return Err(bad(format!(
            "HDR header claims a {w}x{h} image that needs at least {needed} bytes, but the file holds {len}"
        )));
    }
    let img = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| bad(format!("cannot decode Radiance HDR data: {e}")))?
        .into_rgb32f();
    let pixels = img.pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    Ok(Image::new(w, h, pixels))
}
