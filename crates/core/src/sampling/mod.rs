//! Random numbers and sample distributions: a PCG32 generator seeded per (seed, pixel, pass) so images do not
//! depend on thread scheduling, samplers (independent, stratified, Owen-scrambled Sobol over every dimension), pixel
//! sample patterns (RGSS, stratified jitter, uniform grid, independent), pixel filters, MIS weights, and warps from the
//! unit square to the domains integrators need, each with its exact pdf (tested by chi-square in `tests/sampling`).

mod batch;
mod filter;
mod mis;
mod pattern;
mod permute;
mod rng;
mod sampler;
mod sobol;
pub mod warp;

pub use batch::{MAX_BATCH_DIMS, SobolBatch};
pub use filter::{MAX_FILTER_RADIUS, PixelFilter};
pub use mis::power_heuristic;
pub use pattern::PixelPattern;
pub use permute::permute;
pub use rng::{Rng, hash_u64};
pub use sampler::{CAMERA_DIMENSIONS, Deferred1d, DirectionPoint, Sampler, SamplerKind};
pub use sobol::{
    SOBOL_BATCH, nested_uniform_scramble, sobol_dim1_fast, sobol_dim1_reference, sobol_dim1_reversed,
    sobol_owen_1d_point, sobol_owen_1d_reversed, sobol_owen_2d, sobol_owen_2d_batch, sobol_owen_2d_keyed,
    sobol_owen_2d_reference,
};

/// Stratified 2D points for `count` samples: the unit square is cut into `n x n` strata with `n = ceil(sqrt(count))`,
/// sample `i` takes the `i`-th stratum of a random permutation and jitters inside it. Every sample is uniform on the
/// square on its own (so any `count` is unbiased), and a perfect square `count` gives full n x n stratification.
#[inline]
pub fn stratified_2d(i: u32, count: u32, scramble: u32, rng: &mut Rng) -> glam::Vec2 {
    // At most 65535^2 cells (a count near u32::MAX would overflow n * n); beyond them samples reuse strata.
    let n = ((count as f32).sqrt().ceil().max(1.0) as u32).min(65535);
    let cells = n * n;
    let cell = permute(i % cells, cells, scramble);
    let (cx, cy) = (cell % n, cell / n);
    glam::Vec2::new((cx as f32 + rng.next_f32()) / n as f32, (cy as f32 + rng.next_f32()) / n as f32)
}
