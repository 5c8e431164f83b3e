//! Reading one environment image: Radiance `.hdr` (RGBE, through the image crate) or OpenEXR (exr crate), as
//! linear RGB f32. NaN and negative texels become 0 (and are counted); infinite texels are an error.

use super::EnvImage;
use crate::error::{PrismError, Result};
use glam::Vec3;
use std::path::Path;

/// The image and the number of texels that were clamped to 0.
pub fn read(path: &Path) -> Result<(EnvImage, usize)> {
    if !path.is_file() {
        return Err(PrismError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::NotFound, "environment map not found"),
        ));
    }
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let (width, height, mut texels) = match ext.as_str() {
        "hdr" | "pic" => {
            let file = std::fs::File::open(path).map_err(|e| PrismError::io(path, e))?;
            let decoder = image::codecs::hdr::HdrDecoder::new(std::io::BufReader::new(file))
                .map_err(|e| PrismError::format(path, format!("not a readable Radiance HDR file: {e}")))?;
            let img = image::DynamicImage::from_decoder(decoder)
                .map_err(|e| PrismError::format(path, format!("cannot decode Radiance HDR data: {e}")))?
                .into_rgb32f();
            let (w, h) = img.dimensions();
            let texels = img.pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect::<Vec<_>>();
            (w, h, texels)
        }
        "exr" => {
            let img = crate::io::read_exr(path)?;
            (img.width, img.height, img.pixels)
        }
        _ => {
            return Err(PrismError::format(path, "unsupported environment map format (expected .hdr or .exr)"));
        }
    };
    if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
        return Err(PrismError::format(path, format!("environment map has no pixels ({width}x{height})")));
    }
    let mut clamped = 0;
    for (i, t) in texels.iter_mut().enumerate() {
        for c in 0..3 {
            let v = t[c];
            if v.is_infinite() && v > 0.0 {
                let (x, y) = (i as u32 % width, i as u32 / width);
                return Err(PrismError::format(path, format!("texel ({x}, {y}) is infinite")));
            }
            if v.is_nan() || v < 0.0 {
                t[c] = 0.0;
                clamped += 1;
            }
        }
    }
    if clamped > 0 {
        eprintln!("warning: {}: {clamped} NaN or negative texel values set to 0", path.display());
    }
    Ok((EnvImage { width, height, texels }, clamped))
}
