//! PCG32 (O'Neill 2014, XSH-RR variant): small state, good statistical quality, cheap to seed per pixel.

/// A PCG32 random number generator.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const MULT: u64 = 6364136223846793005;

/// A 64-bit finaliser (SplitMix64) used to derive independent seeds from (seed, pixel, pass) tuples.
#[inline]
pub fn hash_u64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E3779B97F4A7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D049BB133111EB);
    x ^ (x >> 31)
}

impl Rng {
    /// A generator for one stream: `stream` selects the sequence, `seed` the starting point.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Rng { state: 0, inc: (stream << 1) | 1 };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    /// The generator for one pixel in one pass of a render with a given seed. Deterministic whatever the thread
    /// that renders the pixel.
    pub fn for_pixel(seed: u64, pixel: u64, pass: u64) -> Self {
        let a = hash_u64(seed ^ hash_u64(pixel.wrapping_mul(0x2545F4914F6CDD1D) ^ pass));
        let b = hash_u64(a ^ pass.wrapping_mul(0x9E3779B97F4A7C15) ^ pixel);
        Rng::new(a, b)
    }

    /// An independent generator for item `index` of this stream (a sample of a pixel): a pure function of the
    /// stream's state and `index`, whatever was drawn from the stream before.
    #[inline]
    pub fn sub_stream(&self, index: u32) -> Self {
        let a = hash_u64(self.state ^ hash_u64(index as u64 ^ 0x5375_6273_7472_6561));
        Rng::new(a, (self.inc >> 1) ^ hash_u64(a))
    }

    /// The next 32 uniformly distributed bits (one PCG32 step).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1), 24 bits of precision (never returns 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two successive [`Rng::next_f32`] values, as `(x, y)`: uniform in the unit square.
    #[inline]
    pub fn next_2d(&mut self) -> glam::Vec2 {
        glam::Vec2::new(self.next_f32(), self.next_f32())
    }

    /// Uniform integer in [0, n) (n > 0), by Lemire's multiply-shift (bias below 2^-32 * n).
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.next_u32() as u64 * n as u64) >> 32) as u32
    }
}
