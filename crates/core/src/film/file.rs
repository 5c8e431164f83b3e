//! `.prism-film` files: a film's committed sums and counts with the render's progress and the integrator's own state,
//! so a render resumes exactly (`prism render --resume F`) and shards merge exactly (`prism merge`).
//!
//! Layout (little-endian):
//!
//! | bytes | field |
//! |---|---|
//! | 8 | magic `PRISMFLM` |
//! | 4 | version (2; version 1 files, without the noise halves' flag, are read too) |
//! | 4 + 4 | width, height |
//! | 4 + 4 + 8 | passes done (the index of the next pass), passes in the whole render, samples per pixel done |
//! | 4 + 4 + 1 | shard k, shard n (1 for a whole render), shard axis (0 passes, 1 pixel rows) |
//! | 8 | fingerprint of the scene file and of every setting that changes the image |
//! | 8 | samples that were NaN or infinite |
//! | 4 + len | integrator spec, UTF-8 (at most 4096 bytes) |
//! | 56 per pixel | three `i128` fixed-point channel sums (see `fixed.rs`) and a `u64` sample count |
//! | 1 | 1 when the noise halves follow (a render with a noise target: `noise.rs`), else 0 |
//! | 16 + 64 per pixel | the halves (`NoiseHalves::to_bytes`) |
//! | 8 + len | the integrator's state (opaque to the film; e.g. `ppm`'s per-pixel statistics) |
//! | 8 | FNV-1a 64 checksum of everything before |
//!
//! Reading checks the magic, version, checksum and that the file's length is exactly what the header implies before
//! allocating anything sized by the header, so a truncated or forged file is a one-line error, never a huge
//! allocation. Writes go to a temporary file renamed into place.

use super::Film;
use super::fixed::FixedRgb;
use crate::error::{PrismError, Result};
use crate::settings::MAX_IMAGE_PIXELS;
use std::path::Path;

const MAGIC: &[u8; 8] = b"PRISMFLM";
const VERSION: u32 = 2;
const MAX_SPEC: usize = 4096;
/// Largest integrator state accepted (bytes).
pub const MAX_STATE: u64 = 1 << 34;

/// How a `--shard K/N` render splits the work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShardAxis {
    /// Shard k renders the passes `p` with `p % n == k` (sample sums add up).
    #[default]
    Passes,
    /// Shard k renders the pixel rows `y` with `y % n == k` (for methods whose passes depend on each other).
    Rows,
}

/// What a film file says about its render.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmHeader {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Index of the next pass to render.
    pub passes_done: u32,
    /// Passes of the whole render (a film is complete when `passes_done >= passes`).
    pub passes: u32,
    /// Samples per pixel of the passes this film holds (a pass shard's own passes only; the uniform rate, which
    /// adaptive pixels exceed or fall short of).
    pub spp_done: u64,
    /// `(k, n)`: the film is shard `k` (from 0) of `n`; `(0, 1)` for a whole render.
    pub shard: (u32, u32),
    /// How the shards split the render.
    pub axis: ShardAxis,
    /// Hash of the scene file and of every setting that changes the image: a film resumes or merges only with a
    /// render of the same fingerprint.
    pub fingerprint: u64,
    /// The integrator spec the film was rendered with, as given (at most 4096 bytes of UTF-8).
    pub integrator: String,
}

/// A film file's content.
pub struct FilmFile {
    /// The render's size, progress, shard and fingerprint.
    pub header: FilmHeader,
    /// The committed sums, counts and non-finite sample count.
    pub film: Film,
    /// The integrator's own state, opaque to the film (empty for integrators that keep none), at most
    /// [`MAX_STATE`] bytes.
    pub state: Vec<u8>,
    /// The noise halves of a render with a noise target.
    pub noise: Option<super::NoiseHalves>,
}

/// The FNV-1a 64 checksum a film file ends with, of everything before it.
pub fn checksum(bytes: &[u8]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Write a film file atomically.
pub fn write_film(path: &Path, header: &FilmHeader, film: &Film, state: &[u8]) -> Result<()> {
    let (sum, count) = film.parts();
    let spec = header.integrator.as_bytes();
    let mut b = Vec::with_capacity(64 + spec.len() + sum.len() * 56 + state.len() + 16);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&VERSION.to_le_bytes());
    b.extend_from_slice(&header.width.to_le_bytes());
    b.extend_from_slice(&header.height.to_le_bytes());
    b.extend_from_slice(&header.passes_done.to_le_bytes());
    b.extend_from_slice(&header.passes.to_le_bytes());
    b.extend_from_slice(&header.spp_done.to_le_bytes());
    b.extend_from_slice(&header.shard.0.to_le_bytes());
    b.extend_from_slice(&header.shard.1.to_le_bytes());
    b.push(match header.axis {
        ShardAxis::Passes => 0,
        ShardAxis::Rows => 1,
    });
    b.extend_from_slice(&header.fingerprint.to_le_bytes());
    b.extend_from_slice(&film.nonfinite.to_le_bytes());
    b.extend_from_slice(&(spec.len().min(MAX_SPEC) as u32).to_le_bytes());
    b.extend_from_slice(&spec[..spec.len().min(MAX_SPEC)]);
    for (s, c) in sum.iter().zip(count) {
        for v in s.0 {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&c.to_le_bytes());
    }
    match film.noise_halves() {
        Some(h) => {
            b.push(1);
            h.to_bytes(&mut b);
        }
        None => b.push(0),
    }
    b.extend_from_slice(&(state.len() as u64).to_le_bytes());
    b.extend_from_slice(state);
    let sum = checksum(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    crate::io::write_atomic(path, &b)
}

/// A cursor over untrusted bytes: every read checks the remaining length.
struct Reader<'a> {
    b: &'a [u8],
    at: usize,
    path: &'a Path,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8]> {
        if self.b.len() - self.at < n {
            return Err(PrismError::format(self.path, "film file is truncated"));
        }
        let s = &self.b[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap_or_default()))
    }
    fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap_or_default()))
    }
    fn i128(&mut self) -> Result<i128> {
        Ok(i128::from_le_bytes(self.take(16)?.try_into().unwrap_or_default()))
    }
}

/// Read and check a film file.
pub fn read_film(path: &Path) -> Result<FilmFile> {
    parse_film(&crate::io::read_regular(path, "film file")?, path)
}

/// Check and decode the bytes of a film file (`path` only names it in errors).
pub fn parse_film(bytes: &[u8], path: &Path) -> Result<FilmFile> {
    if bytes.len() < 8 + 4 || &bytes[..8] != MAGIC {
        return Err(PrismError::format(path, "not a Prism film file (bad magic)"));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    if checksum(body) != u64::from_le_bytes(tail.try_into().unwrap_or_default()) {
        return Err(PrismError::format(path, "film file is corrupt or truncated (checksum mismatch)"));
    }
    let mut r = Reader { b: body, at: 8, path };
    let version = r.u32()?;
    if version != VERSION && version != 1 {
        return Err(PrismError::format(
            path,
            format!("film file version {version} is not supported (expected {VERSION})"),
        ));
    }
    let (width, height) = (r.u32()?, r.u32()?);
    let pixels = width as u64 * height as u64;
    if width == 0 || height == 0 || pixels > MAX_IMAGE_PIXELS {
        return Err(PrismError::format(path, format!("film size {width}x{height} is out of range")));
    }
    let (passes_done, passes, spp_done) = (r.u32()?, r.u32()?, r.u64()?);
    let (k, n) = (r.u32()?, r.u32()?);
    let axis = match r.take(1)?[0] {
        0 => ShardAxis::Passes,
        1 => ShardAxis::Rows,
        a => return Err(PrismError::format(path, format!("unknown shard axis {a}"))),
    };
    if n == 0 || k >= n {
        return Err(PrismError::format(path, format!("bad shard {k}/{n}")));
    }
    let (fingerprint, nonfinite) = (r.u64()?, r.u64()?);
    let spec_len = r.u32()? as usize;
    if spec_len > MAX_SPEC {
        return Err(PrismError::format(path, "integrator spec too long"));
    }
    let integrator = String::from_utf8(r.take(spec_len)?.to_vec())
        .map_err(|_| PrismError::format(path, "integrator spec is not UTF-8"))?;
    // The pixel data must be there before it is allocated.
    let need = pixels as usize * 56;
    if body.len() - r.at < need + 8 {
        return Err(PrismError::format(path, format!("film file is truncated (needs {need} bytes of pixels)")));
    }
    let mut sum = Vec::with_capacity(pixels as usize);
    let mut count = Vec::with_capacity(pixels as usize);
    for i in 0..pixels {
        let s = FixedRgb([r.i128()?, r.i128()?, r.i128()?]);
        // Radiance is never negative, so neither is a sum of it: such a film is forged or corrupt.
        if s.0.iter().any(|&c| c < 0) {
            return Err(PrismError::format(
                path,
                format!(
                    "pixel ({}, {}) has a negative radiance sum (a corrupt or forged film)",
                    i % width as u64,
                    i / width as u64
                ),
            ));
        }
        sum.push(s);
        count.push(r.u64()?);
    }
    let noise = if version >= 2 { read_halves(&mut r, pixels as usize, body.len())? } else { None };
    let state_len = r.u64()?;
    if state_len > MAX_STATE || state_len as usize != body.len() - r.at {
        return Err(PrismError::format(path, "film file's integrator state has the wrong length"));
    }
    let state = r.take(state_len as usize)?.to_vec();
    Ok(FilmFile {
        header: FilmHeader {
            width,
            height,
            passes_done,
            passes,
            spp_done,
            shard: (k, n),
            axis,
            fingerprint,
            integrator,
        },
        film: Film::from_parts(width, height, sum, count, nonfinite),
        state,
        noise,
    })
}

/// The noise halves' section (after its flag byte), checked: present only when the bytes are there, every sum
/// finite and non-negative.
fn read_halves(r: &mut Reader, pixels: usize, body_len: usize) -> Result<Option<super::NoiseHalves>> {
    match r.take(1)?[0] {
        0 => return Ok(None),
        1 => {}
        f => return Err(PrismError::format(r.path, format!("unknown noise-halves flag {f}"))),
    }
    let need = super::NoiseHalves::byte_len(pixels);
    if body_len - r.at < need + 8 {
        return Err(PrismError::format(r.path, format!("film file is truncated (needs {need} bytes of noise halves)")));
    }
    let h = super::NoiseHalves::from_bytes(r.take(need)?, pixels)
        .ok_or_else(|| PrismError::format(r.path, "the film's noise halves hold invalid numbers"))?;
    Ok(Some(h))
}
