//! Reading one environment image: Radiance `.hdr` (RGBE, through the image crate), OpenEXR (exr crate) or PFM, as
//! linear RGB f32. NaN and negative texels become 0 (and are counted); infinite texels are an error.

use super::EnvImage;
use crate::error::{PrismError, Result};
use std::path::Path;

/// The image and the number of texels that were clamped to 0.
pub fn read(path: &Path) -> Result<(EnvImage, usize)> {
    let (file, len) = crate::io::open_regular(path, "environment map")?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let img = match ext.as_str() {
        "hdr" | "pic" => crate::io::read_hdr_from(std::io::BufReader::new(file), len, path)?,
        "exr" => crate::io::read_exr_from(std::io::BufReader::new(file), len, path)?,
        "pfm" => {
            drop(file);
            crate::io::read_pfm_file(path)?
        }
        _ => {
            return Err(PrismError::format(path, "unsupported environment map format (expected .hdr, .exr or .pfm)"));
        }
    };
    from_image(img, path)
}

/// A decoded image as an environment image (`path` names it in errors): NaN and negative texels become 0,
/// infinite texels are an error.
pub fn from_image(img: crate::io::Image, path: &Path) -> Result<(EnvImage, usize)> {
    let (width, height, mut texels) = (img.width, img.height, img.pixels);
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
        crate::error::warn(&format!("{}: {clamped} NaN or negative texel values set to 0", path.display()));
    }
    Ok((EnvImage { width, height, texels }, clamped))
}
