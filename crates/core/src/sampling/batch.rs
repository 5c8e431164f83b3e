//! Sobol points of a chunk of samples computed together: the 2D points an estimator will ask for at its first path
//! vertices, for up to sixteen samples at once (one lane each), with one vector instruction doing the scrambling of
//! all lanes ([`sobol_owen_2d_batch`]). The Sobol sampler's numbers are pure functions of (pixel, sample index,
//! dimension), so drawing them ahead changes no number: a sample's sampler is handed its lane's points and answers
//! those requests from them (`Sampler::next_2d`), every other request as before.
//!
//! `PerPixel` uses it where it already works a chunk at a time (the camera-ray packets): the estimator names the
//! dimensions ([`crate::integrator::PixelIntegrator::batched_2d_dims`]). A dimension computed for a path that ends
//! before asking for it is wasted work, so an estimator names those paths may reach, and each tile, once its first
//! samples show how far its paths go, keeps computing only the dimensions at least half of them reached
//! ([`SobolBatch::keep`]; short paths, such as an open scene's whose rays escape, keep three or five of thirteen).
//!
//! The dimensions the estimator asks for as BSDF directions
//! ([`crate::integrator::PixelIntegrator::batched_direction_dims`]) also get their cosine-weighted hemisphere
//! directions computed here, sixteen lanes at once (`warp::cosine_hemisphere_lanes`, the same bits as the one-point
//! map): a Lambertian vertex then takes its direction ready-made, and the concentric map's division and polynomial
//! leave the chain from one hit to the next ray (the Cornell box renders about 5% faster, the same image).

use super::sampler::Sampler;
use super::sobol::{SOBOL_BATCH, sobol_owen_2d_batch};
use glam::{Vec2, Vec3A};

/// The most 2D dimensions a batch computes per sample.
pub const MAX_BATCH_DIMS: usize = 16;

/// The 2D points of dimensions `dims` for the samples of one chunk (`SOBOL_BATCH` lanes).
pub struct SobolBatch {
    dims: [u32; MAX_BATCH_DIMS],
    n: usize,
    index_rev: [u32; SOBOL_BATCH],
    keys: [[[u32; SOBOL_BATCH]; 3]; MAX_BATCH_DIMS],
    points: [[[f32; SOBOL_BATCH]; 2]; MAX_BATCH_DIMS],
    /// Bit `k`: the `k`-th dimension's points are BSDF directions, whose cosine-weighted hemisphere directions
    /// (`warp::cosine_hemisphere`) the batch computes too, into `dirs[k]`.
    dir_mask: u16,
    dirs: [[[f32; SOBOL_BATCH]; 3]; MAX_BATCH_DIMS],
}

impl SobolBatch {
    /// A batch for the 2D requests at dimensions `dims` (ascending, the order an estimator asks for them; the first
    /// [`MAX_BATCH_DIMS`] are kept).
    pub fn new(dims: &[u32], direction_dims: &[u32]) -> Self {
        let n = dims.len().min(MAX_BATCH_DIMS);
        let mut d = [0; MAX_BATCH_DIMS];
        d[..n].copy_from_slice(&dims[..n]);
        let dir_mask = (0..n).filter(|&k| direction_dims.contains(&d[k])).fold(0u16, |m, k| m | 1 << k);
        SobolBatch {
            dims: d,
            n,
            index_rev: [0; SOBOL_BATCH],
            keys: [[[0; SOBOL_BATCH]; 3]; MAX_BATCH_DIMS],
            points: [[[0.0; SOBOL_BATCH]; 2]; MAX_BATCH_DIMS],
            dir_mask,
            dirs: [[[0.0; SOBOL_BATCH]; 3]; MAX_BATCH_DIMS],
        }
    }

    /// Whether the batch has no dimension to compute.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The dimensions the batch computes (ascending).
    pub fn dims(&self) -> &[u32] {
        &self.dims[..self.n]
    }

    /// Compute only the first `n` dimensions from now on (at least one is kept: a batch stays a batch).
    pub fn keep(&mut self, n: usize) {
        self.n = self.n.min(n.max(1));
    }

    /// Lanes `first..first + count` (within `SOBOL_BATCH`) are samples `index..index + count` of the pixel whose
    /// Sobol sampler is `sampler` (the scramble keys, one set per pixel and dimension, from the sampler's cache).
    #[inline]
    pub fn set_lanes(&mut self, first: usize, count: usize, sampler: &mut Sampler, index: u32) {
        let lanes = first..first + count;
        debug_assert!(lanes.end <= SOBOL_BATCH);
        for (k, l) in self.index_rev[lanes.clone()].iter_mut().enumerate() {
            // Wrapping, as the samplers' indices (`Sampler::start` takes the index modulo 2^32).
            *l = index.wrapping_add(k as u32).reverse_bits();
        }
        for (d, keys) in self.dims[..self.n].iter().zip(self.keys.iter_mut()) {
            let k = sampler.keys_2d(*d);
            if count == SOBOL_BATCH {
                // A whole chunk from one pixel (the common case, `spp >= 16`): whole-array stores, which compile to
                // a few vector stores instead of a fill over a range checked at run time.
                *keys = k.map(|kj| [kj; SOBOL_BATCH]);
            } else {
                for (j, key) in keys.iter_mut().enumerate() {
                    key[lanes.clone()].fill(k[j]);
                }
            }
        }
    }

    /// Compute every lane's points (lanes not set since the batch was made hold earlier or zero inputs, and their
    /// points are not used).
    #[inline]
    pub fn compute(&mut self) {
        sobol_owen_2d_batch(&self.index_rev, &self.keys[..self.n], &mut self.points[..self.n]);
        for k in 0..self.n {
            if self.dir_mask & (1 << k) != 0 {
                crate::sampling::warp::cosine_hemisphere_lanes(&self.points[k], &mut self.dirs[k]);
            }
        }
    }

    /// Lane `lane`'s sample index bit-reversed, as [`Sampler::start_reversed`] takes it (set by `set_lanes`).
    #[inline(always)]
    pub fn index_rev(&self, lane: usize) -> u32 {
        self.index_rev[lane]
    }

    /// Lane `lane`'s point of the batch's `k`-th dimension.
    #[inline(always)]
    pub fn point(&self, lane: usize, k: usize) -> Vec2 {
        Vec2::new(self.points[k][0][lane], self.points[k][1][lane])
    }

    /// Hand lane `lane`'s points of the dimensions from `sampler`'s current one on to `sampler`, which has started
    /// that lane's sample (`Sampler::start`) and drawn what it drew before them.
    #[inline(always)]
    pub fn load(&self, lane: usize, sampler: &mut Sampler) {
        let first = self.dims[..self.n].partition_point(|&d| d < sampler.dimension());
        let point = |k: usize| self.point(lane, k);
        let dir = |k: usize| {
            let d = &self.dirs[k];
            Vec3A::new(d[0][lane], d[1][lane], d[2][lane])
        };
        sampler.preload_2d(&self.dims, (first, self.n), point, self.dir_mask, dir);
    }
}
