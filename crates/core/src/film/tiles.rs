//! What a pass hands the film: the image cut into tiles, and per tile the radiance sums and sample counts of its
//! pixels (or, for methods whose estimate is not a mean of samples, a whole image).

use super::FixedRgb;
use glam::Vec3;

/// Side of the square tiles passes render (the last row and column of tiles may be smaller).
pub const TILE_SIZE: u32 = 16;

/// The image cut into `TILE_SIZE` tiles, row by row.
pub fn tiles(width: u32, height: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(TILE_SIZE as usize) {
        for x0 in (0..width).step_by(TILE_SIZE as usize) {
            out.push(Tile { x0, y0, w: TILE_SIZE.min(width - x0), h: TILE_SIZE.min(height - y0) });
        }
    }
    out
}

/// A rectangle of pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Column of the tile's left pixels.
    pub x0: u32,
    /// Row of the tile's top pixels.
    pub y0: u32,
    /// Width in pixels (at most [`TILE_SIZE`] for the tiles of [`tiles`]).
    pub w: u32,
    /// Height in pixels (at most [`TILE_SIZE`] for the tiles of [`tiles`]).
    pub h: u32,
}

/// Radiance sums of one tile for one pass: `sums[y * w + x]` holds the sum of `counts[y * w + x]` samples (the
/// same count everywhere unless the render is adaptive).
#[derive(Clone, Debug)]
pub struct TileSamples {
    /// The pixels covered.
    pub tile: Tile,
    /// Samples taken per pixel, row-major within the tile (`w * h` entries).
    pub counts: Vec<u32>,
    /// Linear RGB radiance summed over each pixel's samples, each sample converted to fixed point before it is added
    /// (so the sums do not depend on how samples are grouped into passes), row-major within the tile (`w * h`
    /// entries).
    pub sums: Vec<FixedRgb>,
    /// Samples that came out NaN or infinite and were replaced by 0 (reported in the render summary).
    pub nonfinite: u32,
}

impl TileSamples {
    /// Whether the tile lies inside a `width` x `height` image and holds one sum and one count per pixel (a
    /// plugin's tiles are checked before they reach the film).
    pub fn fits(&self, width: u32, height: u32) -> bool {
        let t = self.tile;
        let n = t.w as u64 * t.h as u64;
        t.x0 as u64 + t.w as u64 <= width as u64
            && t.y0 as u64 + t.h as u64 <= height as u64
            && self.sums.len() as u64 == n
            && self.counts.len() as u64 == n
    }
}

/// The result of one pass.
#[derive(Clone, Debug)]
pub enum PassOutput {
    /// Sample sums to add to the film (tiles not rendered because of cancellation are simply absent).
    Samples(Vec<TileSamples>),
    /// A complete image estimate that replaces the film's content (for methods whose estimate is not a mean of
    /// independent samples, such as progressive photon mapping). `complete` is false if the pass was cut short.
    Estimate {
        /// Linear RGB radiance per pixel of the whole image, row-major (`width * height` entries).
        image: Vec<Vec3>,
        /// False when the pass was cut short: `image` is then the last complete pass's estimate, and the pass does
        /// not count as done.
        complete: bool,
    },
}
