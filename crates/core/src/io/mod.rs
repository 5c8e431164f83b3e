//! Image files: linear RGB f32 OpenEXR (exr crate) and 8-bit sRGB PNG with an exposure (image crate). Writes go to
//! a temporary file renamed into place, so an interrupted write never leaves a half-written image behind.

mod files;
mod image_read;
mod output_check;
mod pfm;

pub use files::{file_kind, open_regular, read_regular, read_regular_text, restrict_reads};
pub use image_read::{read_exr_bytes, read_exr_file, read_exr_from, read_hdr_bytes, read_hdr_file, read_hdr_from};
pub use output_check::{check_outputs, check_writable_dir, same_file};
pub use pfm::{read_pfm_bytes, read_pfm_file};

use crate::error::{PrismError, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGB values, row-major from the top-left.
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// An image of `pixels`, which must hold `width * height` values (checked in debug builds only).
    pub fn new(width: u32, height: u32, pixels: Vec<Vec3>) -> Self {
        debug_assert_eq!(pixels.len(), width as usize * height as usize);
        Image { width, height, pixels }
    }

    /// The pixel in column `x < width` and row `y < height`, counted from the top-left.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The rectangle of `w x h` pixels from `(x, y)`, clipped to the image.
    pub fn crop(&self, x: u32, y: u32, w: u32, h: u32) -> Image {
        let (x1, y1) = ((x.saturating_add(w)).min(self.width), (y.saturating_add(h)).min(self.height));
        let (x0, y0) = (x.min(x1), y.min(y1));
        let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
        for yy in y0..y1 {
            for xx in x0..x1 {
                pixels.push(self.get(xx, yy));
            }
        }
        Image::new(x1 - x0, y1 - y0, pixels)
    }

    /// Mean of every pixel.
    pub fn mean(&self) -> Vec3 {
        let s = self.pixels.iter().fold(glam::DVec3::ZERO, |a, p| a + p.as_dvec3());
        (s / self.pixels.len().max(1) as f64).as_vec3()
    }
}

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".partial");
    let tmp = path.with_file_name(name);
    // Keep the real extension last so encoders that look at it still work.
    match path.extension() {
        Some(ext) => tmp.with_extension(format!("partial.{}", ext.to_string_lossy())),
        None => tmp,
    }
}

/// Write `path` through its temporary file: `write` fills the temporary file, which is then renamed into place. On
/// any failure (a full disk, a file too large, an encoder's error, the rename) the temporary file is removed, so a
/// failed write leaves neither a half-written output nor a `.partial` file beside it.
fn write_via_temp(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temp_path(path);
    let done = write(&tmp).and_then(|()| std::fs::rename(&tmp, path).map_err(|e| PrismError::io(path, e)));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// True for `.prism-film` paths (film files, not images).
pub fn is_film_path(path: &Path) -> bool {
    path.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.to_ascii_lowercase().ends_with(".prism-film"))
}

/// Write bytes to `path` through a temporary file renamed into place (never a half-written file).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_via_temp(path, |tmp| std::fs::write(tmp, bytes).map_err(|e| PrismError::io(path, e)))
}

/// Write `img` to `path`; the format follows the extension (`.exr` linear, `.png` sRGB after `exposure` stops,
/// `.tga` the 6.837 course's linear 8-bit values).
pub fn write_image(path: &Path, img: &Image, exposure: f32) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "exr" => write_exr(path, img),
        "png" => write_png(path, img, exposure),
        "tga" => write_tga(path, img),
        _ => {
            Err(PrismError::invalid(format!("{}: unsupported output format (use .png, .exr or .tga)", path.display())))
        }
    }
}

/// The 6.837 course's quantisation of a linear value: `int(255 c)` clamped to [0, 255] (no sRGB, no rounding).
#[inline]
pub fn course_byte(c: f32) -> u8 {
    if c.is_nan() { 0 } else { (255.0 * c).clamp(0.0, 255.0) as u8 }
}

/// Uncompressed 24-bit true-colour TGA (type 2, top-left origin) with the course's linear quantisation
/// [`course_byte`], as the 6.837 ray tracer writes its images.
pub fn write_tga(path: &Path, img: &Image) -> Result<()> {
    let (w, h) = (img.width, img.height);
    if w > u16::MAX as u32 || h > u16::MAX as u32 {
        return Err(PrismError::invalid(format!("{}: TGA images are at most 65535 pixels wide", path.display())));
    }
    let mut buf = Vec::with_capacity(18 + img.pixels.len() * 3);
    buf.extend_from_slice(&[0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    buf.extend_from_slice(&(w as u16).to_le_bytes());
    buf.extend_from_slice(&(h as u16).to_le_bytes());
    // 24 bits per pixel; descriptor bit 5: rows stored from the top.
    buf.extend_from_slice(&[24, 0x20]);
    for p in &img.pixels {
        buf.extend_from_slice(&[course_byte(p.z), course_byte(p.y), course_byte(p.x)]);
    }
    write_via_temp(path, |tmp| std::fs::write(tmp, &buf).map_err(|e| PrismError::io(path, e)))
}

/// Write `img` as a 32-bit float RGB OpenEXR file (written to a temporary file and renamed). The blocks are
/// compressed in parallel but stored in increasing-y order, so the same image gives the same bytes whatever the
/// thread count and timing (with the exr crate's default, unspecified order, blocks land in the order their
/// compression finishes).
pub fn write_exr(path: &Path, img: &Image) -> Result<()> {
    let bytes = exr_bytes(img).map_err(|e| PrismError::format(path, e))?;
    write_atomic(path, &bytes)
}

/// The bytes [`write_exr`] writes (for downloads: `prism watch`).
pub fn exr_bytes(img: &Image) -> std::result::Result<Vec<u8>, String> {
    use exr::prelude::{Encoding, LineOrder, SpecificChannels, WritableImage};
    let w = img.width as usize;
    let channels = SpecificChannels::rgb(|exr::math::Vec2(x, y): exr::math::Vec2<usize>| {
        let p = img.pixels[y * w + x];
        (p.x, p.y, p.z)
    });
    let encoding = Encoding { line_order: LineOrder::Increasing, ..Encoding::default() };
    let mut out = std::io::Cursor::new(Vec::new());
    exr::image::Image::from_encoded_channels((w, img.height as usize), encoding, channels)
        .write()
        .to_buffered(&mut out)
        .map_err(|e| format!("cannot write EXR: {e}"))?;
    Ok(out.into_inner())
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
#[inline]
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// The inverse of [`linear_to_srgb`]: the linear value of an sRGB-encoded value in `[0, 1]`.
#[inline]
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// Write `img` as an 8-bit sRGB PNG (through a temporary file): each channel scaled by `2^exposure`, clamped to
/// `[0, 1]` (non-finite values to 0), sRGB-encoded and rounded.
pub fn write_png(path: &Path, img: &Image, exposure: f32) -> Result<()> {
    let bytes = png_bytes(img, exposure).map_err(|e| PrismError::format(path, e))?;
    write_atomic(path, &bytes)
}

/// The bytes [`write_png`] writes (for downloads: `prism watch`).
pub fn png_bytes(img: &Image, exposure: f32) -> std::result::Result<Vec<u8>, String> {
    let scale = 2f32.powf(exposure);
    let mut buf = Vec::with_capacity(img.pixels.len() * 3);
    for p in &img.pixels {
        for c in [p.x, p.y, p.z] {
            let v = if c.is_finite() { (c * scale).clamp(0.0, 1.0) } else { 0.0 };
            buf.push((linear_to_srgb(v) * 255.0 + 0.5) as u8);
        }
    }
    let mut out = std::io::Cursor::new(Vec::new());
    image::write_buffer_with_format(
        &mut out,
        &buf,
        img.width,
        img.height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot write PNG: {e}"))?;
    Ok(out.into_inner())
}

/// Decode an image through the image crate after checking the size its header claims against Prism's input cap
/// ([`crate::limits::check_input_image_size`]): a small file claiming a huge image is refused before any pixel is
/// allocated. The error is the message alone (the caller names the file).
pub fn decode_checked<R: std::io::BufRead + std::io::Seek>(
    reader: image::ImageReader<R>,
) -> std::result::Result<image::DynamicImage, String> {
    use image::ImageDecoder;
    let decoder = reader.into_decoder().map_err(|e| e.to_string())?;
    let (w, h) = decoder.dimensions();
    crate::limits::check_input_image_size(w as u64, h as u64)?;
    image::DynamicImage::from_decoder(decoder).map_err(|e| e.to_string())
}

/// Read an EXR (linear), Radiance HDR (linear), PFM (linear) or PNG (sRGB, converted to linear) image. Sizes claimed by a
/// file's header are checked before anything is allocated (see `image_read.rs`).
pub fn read_image(path: &Path) -> Result<Image> {
    open_regular(path, "image file")?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "exr" => read_exr_file(path),
        "hdr" => read_hdr_file(path),
        "pfm" => read_pfm_file(path),
        "png" => {
            let (file, _) = open_regular(path, "image file")?;
            let mut reader = image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Png);
            let mut limits = image::Limits::default();
            limits.max_image_width = Some(crate::limits::MAX_INPUT_IMAGE_SIDE);
            limits.max_image_height = Some(crate::limits::MAX_INPUT_IMAGE_SIDE);
            reader.limits(limits);
            let img = decode_checked(reader)
                .map_err(|e| PrismError::format(path, format!("cannot read PNG: {e}")))?
                .to_rgb8();
            let (w, h) = img.dimensions();
            let pixels = img
                .pixels()
                .map(|p| {
                    Vec3::new(
                        srgb_to_linear(p[0] as f32 / 255.0),
                        srgb_to_linear(p[1] as f32 / 255.0),
                        srgb_to_linear(p[2] as f32 / 255.0),
                    )
                })
                .collect();
            Ok(Image::new(w, h, pixels))
        }
        _ => Err(PrismError::invalid(format!(
            "{}: unsupported image format (use .exr, .hdr, .pfm or .png)",
            path.display()
        ))),
    }
}

/// Read an OpenEXR file (its first RGB(A) layer), linear.
pub fn read_exr(path: &Path) -> Result<Image> {
    read_exr_file(path)
}
