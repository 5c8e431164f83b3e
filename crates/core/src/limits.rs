//! Prism's documented limits on untrusted input, in one place (`docs/guide/reliability.md`). Every file header, scene
//! value and command-line number that sizes an allocation, a recursion, a thread pool or a wait is checked
//! against one of these before it is used, so bad input is a one-line error instead of an abort, a stack overflow
//! or a hang.
//!
//! | limit | value | why |
//! |---|---|---|
//! | rendered image | 16384 per side, 2^25 pixels (8K UHD fits) | the film keeps 56 bytes per pixel (fixed-point sums and counts) |
//! | decoded input image (EXR, HDR; env maps, textures, `compare`) | 65536 per side, 2^26 pixels | 12 bytes per texel, decoded once |
//! | nesting depth of scene entities (RON `children`, 6.837 `Group`/`Transform`) | 10000 | the loader's stack |
//! | world-space coordinate magnitude | 1e18 | squares and products of coordinates stay finite in `f32` |
//! | world-space primitives (triangles after instancing, analytic shapes) | 2^26 | about 200 bytes each with the accelerator |
//! | worker threads (`--threads`) | 1024 | each thread reserves a stack |
//! | durations (`--time`, `--checkpoint`, `bench --seconds`) | 1e9 s (about 31 years) | `std::time::Duration` holds them exactly |
//! | `bench --size` | 4096 (16.7 M camera rays) | rays are kept in memory |

use crate::error::{PrismError, Result};
use std::time::Duration;

/// Largest rendered image side.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest rendered pixel count: 2^25 = 33.5 M pixels (7680 x 4320 fits); the film alone needs 1.9 GiB then.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 25;

/// Largest side of an image read from a file (EXR, Radiance HDR).
pub const MAX_INPUT_IMAGE_SIDE: u32 = 65536;
/// Largest pixel count of an image read from a file: 2^26 = 67 M texels (an 8192 x 4096 panorama is half of it).
pub const MAX_INPUT_IMAGE_PIXELS: u64 = 1 << 26;

/// Deepest nesting of scene entities (RON `children`, 6.837 `Group` and `Transform` blocks).
pub const MAX_NESTING_DEPTH: usize = 10_000;

/// Largest magnitude of a world-space coordinate (after transforms): products of two coordinates stay finite in
/// single precision, which ray–sphere and ray–triangle tests and the BVH's node quantisation rely on.
pub const MAX_COORDINATE: f32 = 1e18;

/// Most world-space primitives (triangles, after meshes are placed once per use, and analytic shapes) a scene may
/// flatten into: about 200 bytes each with the accelerator, so 2^26 = 67 M of them take about 13 GiB.
pub const MAX_PRIMITIVES: u64 = 1 << 26;

/// Most worker threads `--threads` may ask for.
pub const MAX_THREADS: usize = 1024;

/// Longest duration a command-line option may give, in seconds.
pub const MAX_SECONDS: f64 = 1e9;

/// Largest `prism bench --size` (camera rays per side).
pub const MAX_BENCH_SIZE: u32 = 4096;

/// Check a claimed image size (from a file header or the command line) against the input-image cap.
pub fn check_input_image_size(width: u64, height: u64) -> std::result::Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("image has no pixels ({width}x{height})"));
    }
    if width > MAX_INPUT_IMAGE_SIDE as u64
        || height > MAX_INPUT_IMAGE_SIDE as u64
        || width * height > MAX_INPUT_IMAGE_PIXELS
    {
        return Err(format!(
            "image is {width}x{height}, larger than Prism reads (at most {MAX_INPUT_IMAGE_SIDE} per side and \
             {MAX_INPUT_IMAGE_PIXELS} pixels)"
        ));
    }
    Ok(())
}

/// A number of seconds from the command line as a `Duration`: finite, non-negative and at most [`MAX_SECONDS`].
/// `what` names the option in the error.
pub fn seconds(value: f64, what: &str) -> Result<Duration> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(PrismError::invalid(format!("{what} must be a non-negative number of seconds, got {value}")));
    }
    if value > MAX_SECONDS {
        return Err(PrismError::invalid(format!("{what} is {value} seconds, more than the limit of {MAX_SECONDS}")));
    }
    Ok(Duration::from_secs_f64(value))
}

/// A `--threads` value: 1 to [`MAX_THREADS`].
pub fn threads(n: usize) -> Result<usize> {
    if n == 0 || n > MAX_THREADS {
        return Err(PrismError::invalid(format!("--threads must be between 1 and {MAX_THREADS}, got {n}")));
    }
    Ok(n)
}
