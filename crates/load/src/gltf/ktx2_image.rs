//! KTX2 textures (`KHR_texture_basisu` and plain KTX2 images in glTF files), through the `ktx2` crate's container
//! reader and `ruzstd` for Zstandard supercompression.
//!
//! Decoded: level 0 of a 2D texture (one layer, one face) in an uncompressed 8-bit UNORM/SRGB format (R, RG, RGB,
//! RGBA, BGR, BGRA) or a 16-/32-bit float RGBA one, stored plain or Zstandard-supercompressed. The colour space
//! of the texels follows the glTF use (base colour sRGB, the rest linear), as for PNG and JPEG.
//! Not decoded ([`Ktx2::Unsupported`], the caller keeps the material's factor with one warning): Basis Universal
//! (BasisLZ/ETC1S or UASTC, `VK_FORMAT_UNDEFINED`), block-compressed formats, ZLIB supercompression, arrays, cube
//! maps and 3D textures. The size is checked against Prism's texture limit before anything is decompressed, and
//! decompression stops at the level's stated length.

use image::DynamicImage;
use ktx2::{Format, SupercompressionScheme};
use std::io::Read;

/// What a KTX2 file decodes to.
pub enum Ktx2 {
    /// The texels of level 0.
    Image(DynamicImage),
    /// A valid file in an encoding Prism does not decode; the reason names it.
    Unsupported(String),
}

/// Channel layout and bytes per texel of the formats decoded.
#[derive(Clone, Copy)]
enum Layout {
    U8 { channels: usize, bgr: bool },
    F16x4,
    F32x4,
}

fn layout(f: Format) -> Option<Layout> {
    let u8s = |channels, bgr| Some(Layout::U8 { channels, bgr });
    match f {
        Format::R8_UNORM | Format::R8_SRGB => u8s(1, false),
        Format::R8G8_UNORM | Format::R8G8_SRGB => u8s(2, false),
        Format::R8G8B8_UNORM | Format::R8G8B8_SRGB => u8s(3, false),
        Format::B8G8R8_UNORM | Format::B8G8R8_SRGB => u8s(3, true),
        Format::R8G8B8A8_UNORM | Format::R8G8B8A8_SRGB => u8s(4, false),
        Format::B8G8R8A8_UNORM | Format::B8G8R8A8_SRGB => u8s(4, true),
        Format::R16G16B16A16_SFLOAT => Some(Layout::F16x4),
        Format::R32G32B32A32_SFLOAT => Some(Layout::F32x4),
        _ => None,
    }
}

/// Decode a KTX2 file's bytes; `Err` for a malformed file (the message says what is wrong).
pub fn decode(bytes: &[u8]) -> Result<Ktx2, String> {
    let reader = ktx2::Reader::new(bytes).map_err(|e| format!("malformed KTX2 file: {e:?}"))?;
    let h = reader.header();
    let Some(format) = h.format else {
        return Ok(Ktx2::Unsupported("Basis Universal (ETC1S/UASTC) compressed".into()));
    };
    let Some(lay) = layout(format) else {
        return Ok(Ktx2::Unsupported(format!("in the GPU format {format:?}")));
    };
    if h.pixel_depth > 1 || h.layer_count > 1 || h.face_count != 1 {
        return Ok(Ktx2::Unsupported("a 3D, array or cube-map texture".into()));
    }
    let (w, ht) = (h.pixel_width, h.pixel_height.max(1));
    let side = prism_core::texture::MAX_TEXTURE_SIZE;
    if w == 0 || w > side || ht > side {
        return Err(format!("a {w} x {ht} texture (at most {side} texels a side)"));
    }
    let texel = match lay {
        Layout::U8 { channels, .. } => channels,
        Layout::F16x4 => 8,
        Layout::F32x4 => 16,
    };
    let need = w as usize * ht as usize * texel;
    let level = reader.levels().next().ok_or("the file has no mip level")?;
    let data: Vec<u8> = match h.supercompression_scheme {
        None => level.data.to_vec(),
        Some(SupercompressionScheme::Zstandard) => {
            let mut out = Vec::with_capacity(need);
            let dec = ruzstd::decoding::StreamingDecoder::new(level.data)
                .map_err(|e| format!("bad Zstandard level data: {e}"))?;
            // One byte past what the texels need tells a longer stream from an exact one.
            dec.take(need as u64 + 1).read_to_end(&mut out).map_err(|e| format!("bad Zstandard level data: {e}"))?;
            out
        }
        Some(s) => return Ok(Ktx2::Unsupported(format!("{s:?}-supercompressed"))),
    };
    // Rows are tightly packed for these texel sizes (KTX2 aligns rows to lcm(texel, 4) only for block formats).
    if data.len() < need {
        return Err(format!("level 0 holds {} bytes, a {w} x {ht} {format:?} image needs {need}", data.len()));
    }
    let data = &data[..need];
    let img = match lay {
        Layout::U8 { channels, bgr } => {
            let mut px = data.to_vec();
            if bgr {
                px.chunks_exact_mut(channels).for_each(|c| c.swap(0, 2));
            }
            let bad = || "texel buffer size".to_string();
            match channels {
                1 => DynamicImage::ImageLuma8(image::GrayImage::from_raw(w, ht, px).ok_or_else(bad)?),
                2 => DynamicImage::ImageLumaA8(image::GrayAlphaImage::from_raw(w, ht, px).ok_or_else(bad)?),
                3 => DynamicImage::ImageRgb8(image::RgbImage::from_raw(w, ht, px).ok_or_else(bad)?),
                _ => DynamicImage::ImageRgba8(image::RgbaImage::from_raw(w, ht, px).ok_or_else(bad)?),
            }
        }
        Layout::F16x4 | Layout::F32x4 => {
            let f: Vec<f32> = match lay {
                Layout::F16x4 => data.chunks_exact(2).map(|b| half_to_f32(u16::from_le_bytes([b[0], b[1]]))).collect(),
                _ => data.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect(),
            };
            DynamicImage::ImageRgba32F(image::Rgba32FImage::from_raw(w, ht, f).ok_or("texel buffer size")?)
        }
    };
    Ok(Ktx2::Image(img))
}

/// IEEE 754 half to single precision (subnormals, infinities and NaN included).
fn half_to_f32(h: u16) -> f32 {
    let sign = ((h >> 15) as u32) << 31;
    let exp = ((h >> 10) & 0x1f) as u32;
    let man = (h & 0x3ff) as u32;
    let bits = match (exp, man) {
        (0, 0) => sign,
        (0, m) => {
            // Subnormal: m * 2^-24.
            let v = m as f32 * (1.0 / 16_777_216.0);
            return if sign != 0 { -v } else { v };
        }
        (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 112) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}
