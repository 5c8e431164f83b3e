//! Samplers: where the random numbers of one camera sample (or one photon path) come from, dimension by dimension.
//!
//! An estimator asks for its numbers in a fixed order — the pixel position (dimensions 0-1), the lens (2-3), then
//! at every path vertex the light choice, the light point, the BSDF lobe, the BSDF direction and Russian roulette —
//! and the sampler answers:
//! - `independent`: every number from the pixel's PCG32 stream (plain Monte Carlo, as Mitsuba's `independent`);
//! - `stratified`: pixel positions jittered on an n x n grid over the pixel's samples, the first two integrator 2D
//!   dimensions (the first vertex's light and BSDF samples) from Owen-scrambled Sobol points, everything else
//!   independent;
//! - `sobol` (the default): **every** dimension from Owen-scrambled Sobol points (Burley 2020, "Practical Hash-based
//!   Owen Scrambling"): 2D requests use the first two Sobol dimensions, a (0,2)-sequence, 1D requests the first
//!   (van der Corput); each dimension (pair) gets its own index shuffle and its own nested uniform scramble, hashed
//!   from (pixel, dimension), which decorrelates dimensions ("padding" in pbrt's terms) and makes every single point
//!   uniformly distributed. So the estimate is unbiased for any sample count; every prefix of 2^k samples of a pixel
//!   is stratified in every 2D projection used (one point in each of the 2^k elementary intervals of any shape),
//!   and in between powers of two the extra samples are a stratified subset of the next power's set.
//!   The sequence is progressive: sample `i` of a pixel is the same point whatever the total, so passes and time
//!   budgets continue one sequence. One exception to the shuffle: a thin lens's point (dimensions 2-3) is taken
//!   from another sample of the pixel's block through a random permutation ([`Sampler::next_2d_of`], `PerPixel`),
//!   which pairs it with the pixel point better than the nested shuffle does. So with a lens, sample `i`'s lens
//!   point depends on its block (the pixel's total samples): the same for threads, shards and resumes, which share
//!   the block, but not progressive across totals.
//!
//! Everything is a pure function of (seed, pixel, sample index, dimension), so images do not depend on threads.

use super::Rng;
use super::batch::MAX_BATCH_DIMS;
use super::sobol::{hash32, scramble_keys_2d, sobol_owen_1d_point, sobol_owen_2d_keyed};
use glam::{Vec2, Vec3A};
use multiversion::multiversion;

/// Which sampler fills the dimensions of a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SamplerKind {
    /// Every number from the pixel's PCG32 stream.
    Independent,
    /// Jittered pixel positions, Sobol points for the first vertex's light and BSDF samples, the rest independent.
    Stratified,
    /// Owen-scrambled Sobol points for every dimension (the default).
    #[default]
    Sobol,
}

impl SamplerKind {
    /// The sampler of a name: `independent` (or `random`), `stratified`, `sobol` (or `ldsampler`,
    /// `low_discrepancy`); `None` for any other.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "independent" | "random" => Some(Self::Independent),
            "stratified" => Some(Self::Stratified),
            "sobol" | "ldsampler" | "low_discrepancy" => Some(Self::Sobol),
            _ => None,
        }
    }

    /// The sampler's canonical name (what [`SamplerKind::parse`] reads back).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Independent => "independent",
            Self::Stratified => "stratified",
            Self::Sobol => "sobol",
        }
    }

    /// The canonical names, as error messages list them.
    pub const NAMES: &'static str = "independent, stratified or sobol";
}

/// A dimension reserved by [`Sampler::defer_1d`]: its number is computed on demand.
#[derive(Clone, Copy, Debug)]
pub struct Deferred1d(DeferredValue);

#[derive(Clone, Copy, Debug)]
enum DeferredValue {
    /// A Sobol dimension, computed when asked.
    Dim(u32),
    /// A number drawn when the dimension was reserved.
    Value(f32),
}

/// Dimensions PerPixel uses before the integrator's: the pixel position (0-1) and the lens (2-3).
pub const CAMERA_DIMENSIONS: u32 = 4;

/// The random numbers of one sample: call [`Sampler::start`] for each sample index, then draw with `next_1d` /
/// `next_2d` in a fixed order. `rng()` gives the raw stream for decisions that need no stratification.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    /// Scramble key of the pixel (or photon batch).
    key: u32,
    /// Index of the current sample in the pixel's sequence.
    index: u32,
    /// `index` bit-reversed (the Sobol scrambles work on reversed indices; reversed once per sample).
    index_rev: u32,
    /// Next dimension.
    dim: u32,
    /// 2D requests so far in this sample (for `stratified`).
    requests_2d: u32,
    /// The stream the samples' independent numbers derive from (the pixel's, or the photon's).
    stream: Rng,
    /// The current sample's independent numbers: `stream`'s sub-stream for the sample's index, made when first
    /// asked for (`rng_fresh`), so that they depend on the sample's index alone, never on which samples the same
    /// sampler ran before it (a render's image does not depend on how its samples are grouped into passes).
    rng: Rng,
    rng_fresh: bool,
    /// The Sobol scramble keys of 2D dimensions, which depend on (pixel key, dimension) only: computed by the
    /// pixel's first sample and reused by the rest. Slot `(dim / 2) % KEY_SLOTS` holds the three keys and `dim + 1`
    /// (0: empty); a dimension whose slot holds another recomputes its keys.
    keys_2d: [[u32; 4]; KEY_SLOTS],
    /// 2D points of the current sample computed ahead by a [`SobolBatch`](super::SobolBatch), indexed as the
    /// batch's dimensions: `pre_dims[k]`'s point is `pre[k]`, for `pre_next <= k < pre_len`, in the order the
    /// estimator asks for them; `pre_next` is the next one `next_2d` may answer from here. Emptied by `start`.
    pre_dims: [u32; MAX_BATCH_DIMS],
    pre: [Vec2; MAX_BATCH_DIMS],
    /// Bit `k`: `pre_dir[k]` is `pre[k]`'s cosine-weighted hemisphere direction, computed ahead too.
    pre_dir_mask: u16,
    pre_dir: [Vec3A; MAX_BATCH_DIMS],
    pre_len: u8,
    pre_next: u8,
}

/// A 2D point for a BSDF direction, with its cosine-weighted hemisphere direction where a
/// [`SobolBatch`](super::SobolBatch) computed it ahead ([`Sampler::next_direction_2d`]).
#[derive(Clone, Copy, Debug)]
pub struct DirectionPoint {
    /// The point in [0, 1)^2.
    pub u: Vec2,
    /// `warp::cosine_hemisphere(u)`, if known.
    cosine: Option<Vec3A>,
}

impl DirectionPoint {
    /// A point whose direction is computed when asked for.
    #[inline(always)]
    pub fn new(u: Vec2) -> Self {
        DirectionPoint { u, cosine: None }
    }

    /// `warp::cosine_hemisphere(self.u)`: computed ahead or now (the same bits).
    #[inline(always)]
    pub fn cosine_hemisphere(&self) -> Vec3A {
        match self.cosine {
            Some(d) => d,
            None => super::warp::cosine_hemisphere(self.u),
        }
    }
}

/// The scramble seed of dimension `dim` of the pixel (or photon batch) whose key is `key`.
#[inline]
fn dim_key(key: u32, dim: u32) -> u32 {
    hash32(key ^ dim.wrapping_mul(0x9E37_79B9).wrapping_add(0x632B_E5AB))
}

/// The Sobol point at dimensions `dim, dim + 1` for the index whose reversal is `index_rev`, its scramble keys
/// (from [`dim_key`] of the pixel's `key` and the dimension) cached in `keys_2d`. Compiled twice and chosen at run
/// time, so that its bit reversals use GFNI where the CPU has it (see `sobol.rs`): fewer instructions per point, the
/// same points bit for bit (see `docs/decisions/0011-sobol-gfni-bit-reversal.md`).
#[multiversion(targets("x86_64+gfni"))]
fn sobol_2d_cached(keys_2d: &mut [[u32; 4]; KEY_SLOTS], index_rev: u32, dim: u32, key: u32) -> Vec2 {
    sobol_owen_2d_keyed(index_rev, cached_keys_2d(keys_2d, dim, key))
}

/// The scramble keys of 2D dimension `dim` of the pixel whose key is `key`, from slot `(dim / 2) % KEY_SLOTS` of the
/// cache, computed into it if the slot holds another dimension.
#[inline(always)]
fn cached_keys_2d(keys_2d: &mut [[u32; 4]; KEY_SLOTS], dim: u32, key: u32) -> [u32; 3] {
    let slot = (dim as usize >> 1) % KEY_SLOTS;
    let tag = dim.wrapping_add(1);
    if tag == 0 {
        // The last dimension there is (tag 0 would read an empty slot as cached).
        return scramble_keys_2d(dim_key(key, dim));
    }
    if keys_2d[slot][3] != tag {
        let [a, b, c] = scramble_keys_2d(dim_key(key, dim));
        keys_2d[slot] = [a, b, c, tag];
    }
    let [a, b, c, _] = keys_2d[slot];
    [a, b, c]
}

/// Cached 2D dimensions: 64 dimensions, a path of about nine vertices.
const KEY_SLOTS: usize = 32;

impl Sampler {
    /// A sampler whose Sobol points are scrambled by `key` and whose independent numbers come from sub-streams of
    /// `stream`, one per sample index.
    pub fn new(kind: SamplerKind, key: u32, stream: Rng) -> Self {
        Sampler {
            kind,
            key,
            index: 0,
            index_rev: 0,
            dim: 0,
            requests_2d: 0,
            rng: stream.clone(),
            stream,
            rng_fresh: false,
            keys_2d: [[0; 4]; KEY_SLOTS],
            pre_dims: [0; MAX_BATCH_DIMS],
            pre: [Vec2::ZERO; MAX_BATCH_DIMS],
            pre_dir_mask: 0,
            pre_dir: [Vec3A::ZERO; MAX_BATCH_DIMS],
            pre_len: 0,
            pre_next: 0,
        }
    }

    /// Begin sample `index` of the sequence (dimension 0).
    #[inline]
    pub fn start(&mut self, index: u32) {
        self.start_reversed(index, index.reverse_bits());
    }

    /// [`Sampler::start`] with the index's bit reversal already known (`index_rev == index.reverse_bits()`: a
    /// [`SobolBatch`](super::SobolBatch) has it for its lanes), which costs about seventeen instructions on the
    /// baseline x86-64 target.
    #[inline]
    pub fn start_reversed(&mut self, index: u32, index_rev: u32) {
        debug_assert_eq!(index_rev, index.reverse_bits());
        self.index = index;
        self.index_rev = index_rev;
        self.dim = 0;
        self.requests_2d = 0;
        self.pre_len = 0;
        self.pre_next = 0;
        self.rng_fresh = false;
    }

    /// The scramble keys of the Sobol points at dimensions `dim, dim + 1` (cached per pixel as `next_2d` caches
    /// them), for a [`SobolBatch`](super::SobolBatch).
    #[inline]
    pub(super) fn keys_2d(&mut self, dim: u32) -> [u32; 3] {
        cached_keys_2d(&mut self.keys_2d, dim, self.key)
    }

    /// Hand the current sample the 2D points computed ahead for dimensions `dims[first..len]` (ascending, in the
    /// order they will be asked for): `point(k)` is dimension `dims[k]`'s, and where bit `k` of `dir_mask` is set
    /// `dir(k)` is its cosine-weighted hemisphere direction (read for every `k`, used only there). `next_2d` and
    /// `next_direction_2d` answer a request for such a dimension from here, which is the number it would have
    /// computed (other samplers ignore them). Whole arrays and a loop without branches: this runs once per sample.
    #[inline(always)]
    pub(super) fn preload_2d(
        &mut self,
        dims: &[u32; MAX_BATCH_DIMS],
        (first, len): (usize, usize),
        point: impl Fn(usize) -> Vec2,
        dir_mask: u16,
        dir: impl Fn(usize) -> Vec3A,
    ) {
        // Only the Sobol sampler's numbers are these points; the others keep drawing their own.
        let len = if self.kind == SamplerKind::Sobol { len.min(MAX_BATCH_DIMS) } else { 0 };
        self.pre_dims = *dims;
        for k in first..len {
            self.pre[k] = point(k);
            self.pre_dir[k] = dir(k);
        }
        self.pre_dir_mask = dir_mask;
        self.pre_len = len as u8;
        self.pre_next = first.min(len) as u8;
    }

    /// Skip one 2D request (its dimensions are drawn elsewhere, e.g. pixel positions by an explicit pattern).
    #[inline]
    pub fn skip_2d(&mut self) {
        self.dim += 2;
        self.requests_2d += 1;
    }

    /// Which sampler this is.
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// The dimension the next request will use.
    pub fn dimension(&self) -> u32 {
        self.dim
    }

    /// The sample's index in its sequence.
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The current sample's independent stream: a pure function of the sampler's stream and the sample's index.
    #[inline]
    pub fn rng(&mut self) -> &mut Rng {
        if !self.rng_fresh {
            self.rng = self.stream.sub_stream(self.index);
            self.rng_fresh = true;
        }
        &mut self.rng
    }

    /// The Sobol sampler's number at dimension `dim` of the current sample.
    #[inline]
    fn sobol_1d_at(&self, dim: u32) -> f32 {
        let k = dim_key(self.key, dim);
        // First Sobol dimension (van der Corput) of the shuffled index, Owen-scrambled.
        let x = sobol_owen_1d_point(self.index_rev, k, hash32(k ^ 0xa511_e9b3));
        (x >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// The Sobol sampler's point at dimensions `dim, dim + 1` of the current sample (scramble keys cached).
    #[inline]
    fn sobol_2d_at(&mut self, dim: u32) -> Vec2 {
        sobol_2d_cached(&mut self.keys_2d, self.index_rev, dim, self.key)
    }

    /// One number in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let dim = self.dim;
        self.dim += 1;
        match self.kind {
            SamplerKind::Sobol => self.sobol_1d_at(dim),
            _ => self.rng().next_f32(),
        }
    }

    /// Take the next dimension now and its number later, or never: [`Sampler::get_1d`] gives exactly what
    /// `next_1d` would have returned here. The Sobol sampler computes it only when asked (its numbers are pure
    /// functions of the dimension), so an estimator can reserve every dimension of a vertex in a fixed order and
    /// pay only for those it uses (the lobe number of a one-lobe BSDF, the light choice among one light, roulette
    /// before it starts); the other samplers draw it now, in order, as before.
    #[inline]
    pub fn defer_1d(&mut self) -> Deferred1d {
        match self.kind {
            SamplerKind::Sobol => {
                self.dim += 1;
                Deferred1d(DeferredValue::Dim(self.dim - 1))
            }
            _ => Deferred1d(DeferredValue::Value(self.next_1d())),
        }
    }

    /// The number of a deferred dimension (of the current sample).
    #[inline]
    pub fn get_1d(&self, d: Deferred1d) -> f32 {
        match d.0 {
            DeferredValue::Dim(dim) => self.sobol_1d_at(dim),
            DeferredValue::Value(v) => v,
        }
    }

    /// The next 2D request answered with sample `index`'s point of the pixel's sequence instead of the current
    /// sample's (the Sobol sampler; the others answer as [`Sampler::next_2d`]). A caller that draws it for every
    /// sample of a block through a permutation of the block's indices keeps the block's point set for these
    /// dimensions and pairs it with the other dimensions' points at random (the thin lens, `PerPixel`).
    #[inline]
    pub fn next_2d_of(&mut self, index: u32) -> Vec2 {
        match self.kind {
            SamplerKind::Sobol => {
                let dim = self.dim;
                self.dim += 2;
                self.requests_2d += 1;
                sobol_2d_cached(&mut self.keys_2d, index.reverse_bits(), dim, self.key)
            }
            _ => self.next_2d(),
        }
    }

    /// A point in [0, 1)^2.
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        // The direction part is never read here, so it compiles away.
        self.next_direction_2d().u
    }

    /// [`Sampler::next_2d`] for a BSDF direction: the point, and its cosine-weighted direction where it was computed
    /// ahead with it.
    #[inline(always)]
    pub fn next_direction_2d(&mut self) -> DirectionPoint {
        let dim = self.dim;
        let k = self.pre_next as usize;
        if k < self.pre_len as usize && self.pre_dims[k] == dim {
            // Computed ahead (a Sobol sampler handed a batch's points).
            self.dim += 2;
            self.requests_2d += 1;
            self.pre_next += 1;
            let cosine = (self.pre_dir_mask & (1 << k) != 0).then_some(self.pre_dir[k]);
            return DirectionPoint { u: self.pre[k], cosine };
        }
        DirectionPoint::new(self.next_2d_computed())
    }

    /// `next_2d` for a point not computed ahead.
    #[inline]
    fn next_2d_computed(&mut self) -> Vec2 {
        let dim = self.dim;
        self.dim += 2;
        let request = self.requests_2d;
        self.requests_2d += 1;
        match self.kind {
            SamplerKind::Sobol => self.sobol_2d_at(dim),
            // The first vertex's light and BSDF points (the first two 2D requests after the camera's).
            SamplerKind::Stratified if (2..4).contains(&request) => self.sobol_2d_at(dim),
            _ => self.rng().next_2d(),
        }
    }
}
