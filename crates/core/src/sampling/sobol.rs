//! Owen-scrambled Sobol points in 2D (Burley 2020, "Practical Hash-based Owen Scrambling"): the first two Sobol
//! dimensions form a (0,2)-sequence, so every prefix of 2^k points puts exactly one point in each of 2^k equal
//! elementary intervals in any aspect ratio, and the sequence is progressive: no total count is needed. A hash-based
//! nested uniform scramble per (pixel, dimension) randomises it, so each point alone is uniform (unbiased), and
//! shuffling the index decorrelates dimensions.
//!
//! The sampler's entry points ([`sobol_owen_1d_point`] here, and its cached 2D points) are compiled twice and chosen
//! at run time: where the CPU has GFNI (Intel Ice Lake and later, AMD Zen 4 and later) a bit reversal is one
//! `gf2p8affineqb` and a byte swap instead of a dozen shifts and masks. The integer arithmetic is the same, so the
//! points are the same bit for bit on every CPU.

use multiversion::multiversion;

#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50b47c);
    x ^= x.wrapping_mul(0xb82f1e52);
    x ^= x.wrapping_mul(0xc7afe638);
    x ^= x.wrapping_mul(0x8d22f6e6);
    x
}

/// Owen (nested uniform) scramble of a 32-bit fixed-point value.
#[inline]
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// Generator matrix columns of the second Sobol dimension: `v_0 = 2^31`, `v_(k+1) = v_k ^ (v_k >> 1)`.
const fn sobol_dim1_columns() -> [u32; 32] {
    let mut v = [0u32; 32];
    let mut c = 1u32 << 31;
    let mut k = 0;
    while k < 32 {
        v[k] = c;
        c ^= c >> 1;
        k += 1;
    }
    v
}

/// The matrix product split by bytes of the index: `TABLE[j][b]` is the XOR of the columns `8j + k` for the set
/// bits `k` of `b`, so a point costs four lookups instead of a loop over 32 bits.
const fn byte_tables(v: [u32; 32]) -> [[u32; 256]; 4] {
    let mut t = [[0u32; 256]; 4];
    let mut j = 0;
    while j < 4 {
        let mut b = 0;
        while b < 256 {
            let mut r = 0u32;
            let mut k = 0;
            while k < 8 {
                if b & (1 << k) != 0 {
                    r ^= v[8 * j + k];
                }
                k += 1;
            }
            t[j][b] = r;
            b += 1;
        }
        j += 1;
    }
    t
}

/// The columns of the second Sobol dimension conjugated by bit reversal: the map `r -> rev(sobol_dim1(rev(r)))`,
/// whose column `k` is `rev(v_(31-k))`. The scrambles work on bit-reversed values, so with this table the
/// sampler never reverses the index back and forth.
const fn sobol_dim1_reversed_columns() -> [u32; 32] {
    let v = sobol_dim1_columns();
    let mut w = [0u32; 32];
    let mut k = 0;
    while k < 32 {
        w[k] = v[31 - k].reverse_bits();
        k += 1;
    }
    w
}

static SOBOL_DIM1: [[u32; 256]; 4] = byte_tables(sobol_dim1_columns());
static SOBOL_DIM1_REVERSED: [[u32; 256]; 4] = byte_tables(sobol_dim1_reversed_columns());

#[inline]
fn apply(t: &[[u32; 256]; 4], i: u32) -> u32 {
    t[0][(i & 0xff) as usize]
        ^ t[1][((i >> 8) & 0xff) as usize]
        ^ t[2][((i >> 16) & 0xff) as usize]
        ^ t[3][(i >> 24) as usize]
}

/// The second Sobol dimension of `i` (as 32-bit fixed point).
#[inline]
fn sobol_dim1(i: u32) -> u32 {
    apply(&SOBOL_DIM1, i)
}

/// The reference bit loop for `sobol_dim1` (tests compare the two).
pub fn sobol_dim1_reference(mut i: u32) -> u32 {
    let mut v = 1u32 << 31;
    let mut r = 0;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// The second Sobol dimension of `i` by table (public for tests).
pub fn sobol_dim1_fast(i: u32) -> u32 {
    sobol_dim1(i)
}

/// The second Sobol dimension in the bit-reversed domain, without a table: `rev(sobol_dim1(i))` for any `i`. Bit
/// `j` of the result is the XOR of the bits `k` of `i` whose binomial coefficient `C(k, j)` is odd, which by Lucas's
/// theorem are the `k` that contain `j`'s bits: a superset XOR over five bit positions, five shift-and-XOR steps.
/// The same linear map as `apply(&SOBOL_DIM1_REVERSED, rev(i))` (tests check every basis vector); it needs no
/// memory lookup, so [`sobol_owen_2d_batch`] computes it for sixteen lanes at once.
#[inline(always)]
pub fn sobol_dim1_reversed(i: u32) -> u32 {
    let mut x = i;
    x ^= (x >> 1) & 0x5555_5555;
    x ^= (x >> 2) & 0x3333_3333;
    x ^= (x >> 4) & 0x0f0f_0f0f;
    x ^= (x >> 8) & 0x00ff_00ff;
    x ^= (x >> 16) & 0x0000_ffff;
    x
}

/// Lanes of [`sobol_owen_2d_batch`].
pub const SOBOL_BATCH: usize = 16;

/// Sixteen points of [`sobol_owen_2d_keyed`] at once, for each 2D dimension `d` given: lane `l` is the point of
/// the index whose bit reversal is `index_rev[l]` under the keys `keys[d][0][l]`, `keys[d][1][l]`,
/// `keys[d][2][l]`, written to `out[d][0][l]` (x) and `out[d][1][l]` (y) — the same bits as the one-point
/// function. Compiled for AVX-512 and AVX2 (with GFNI, whose `gf2p8affineqb` reverses the bits of a byte) and
/// chosen at run time, the lane loop is one vector computation: the 32-bit multiplies of the scrambles, the bit
/// reversals and the table-free second dimension ([`sobol_dim1_reversed`]) for all lanes per instruction.
#[multiversion(targets(
    "x86_64+avx512f+avx512vl+avx512bw+gfni",
    "x86_64+avx512f+avx512vl+avx512bw",
    "x86_64+avx2+gfni",
    "x86_64+avx2"
))]
pub fn sobol_owen_2d_batch(
    index_rev: &[u32; SOBOL_BATCH],
    keys: &[[[u32; SOBOL_BATCH]; 3]],
    out: &mut [[[f32; SOBOL_BATCH]; 2]],
) {
    const S: f32 = 1.0 / 16_777_216.0;
    for (keys, out) in keys.iter().zip(out.iter_mut()) {
        for l in 0..SOBOL_BATCH {
            // As `sobol_owen_2d_keyed`: the shuffled index (reversed), then both dimensions scrambled; here the
            // second dimension takes the shuffled index's reversal, which the first computes anyway.
            let r = laine_karras(index_rev[l], keys[0][l]).reverse_bits();
            let x = laine_karras(r, keys[1][l]).reverse_bits();
            let y = laine_karras(sobol_dim1_reversed(r), keys[2][l]).reverse_bits();
            // Below 2^24, so the signed conversion (one vector instruction on every target) is exact.
            out[0][l] = (x >> 8) as i32 as f32 * S;
            out[1][l] = (y >> 8) as i32 as f32 * S;
        }
    }
}

/// A 32-bit integer hash (Wellons' "lowbias32"): keys of the scrambles, here and in the sampler.
#[inline]
pub(super) fn hash32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846ca68b);
    x ^ (x >> 16)
}

/// Point `index` of the scrambled 2D Sobol sequence selected by `seed`, in [0,1)^2.
#[inline]
pub fn sobol_owen_2d(index: u32, seed: u32) -> glam::Vec2 {
    sobol_owen_2d_keyed(index.reverse_bits(), scramble_keys_2d(seed))
}

/// The three scramble keys of a 2D point set selected by `seed`: the index shuffle, the x and the y scramble. A
/// sampler computes them once per pixel and dimension and reuses them for every sample of the pixel.
#[inline]
pub fn scramble_keys_2d(seed: u32) -> [u32; 3] {
    [hash32(seed), hash32(seed ^ 0x9e37_79b9), hash32(seed ^ 0x85eb_ca6b)]
}

/// [`sobol_owen_2d`] from its `scramble_keys_2d`, for the index whose bit reversal is `index_rev` (a sampler
/// reverses its index once per sample). The same point as [`sobol_owen_2d_reference`], computed in the
/// bit-reversed domain where Laine-Karras scrambles act: three bit reversals instead of seven (two of them paired
/// into one 64-bit reversal).
#[inline]
pub fn sobol_owen_2d_keyed(index_rev: u32, keys: [u32; 3]) -> glam::Vec2 {
    // The shuffled index, reversed (the nested scramble of the index without its final reversal).
    let r = laine_karras(index_rev, keys[0]);
    let x = laine_karras(r.reverse_bits(), keys[1]);
    let y = laine_karras(apply(&SOBOL_DIM1_REVERSED, r), keys[2]);
    // Both final bit reversals as one 64-bit reversal: rev64(x : y) = rev32(y) : rev32(x).
    let both = ((x as u64) << 32 | y as u64).reverse_bits();
    let (x, y) = (both as u32, (both >> 32) as u32);
    const S: f32 = 1.0 / 16_777_216.0;
    glam::Vec2::new((x >> 8) as f32 * S, (y >> 8) as f32 * S)
}

/// [`sobol_owen_1d_reversed`], with its bit reversals in GFNI where the CPU has it (see the module's header).
#[multiversion(targets("x86_64+gfni"))]
pub fn sobol_owen_1d_point(index_rev: u32, shuffle: u32, scramble: u32) -> u32 {
    sobol_owen_1d_reversed(index_rev, shuffle, scramble)
}

/// The definition [`sobol_owen_2d`] implements (tests compare the two): shuffle the index by a nested uniform
/// scramble, take the first two Sobol dimensions of the shuffled index, and scramble each.
pub fn sobol_owen_2d_reference(index: u32, seed: u32) -> glam::Vec2 {
    let i = nested_uniform_scramble(index, hash32(seed));
    let x = nested_uniform_scramble(i.reverse_bits(), hash32(seed ^ 0x9e37_79b9));
    let y = nested_uniform_scramble(sobol_dim1_reference(i), hash32(seed ^ 0x85eb_ca6b));
    const S: f32 = 1.0 / 4_294_967_296.0;
    glam::Vec2::new((x >> 8) as f32 * (S * 256.0), (y >> 8) as f32 * (S * 256.0))
}

/// One scrambled van der Corput number (the first Sobol dimension) for the index whose bit reversal is
/// `index_rev`: the index shuffled by the nested scramble keyed `shuffle`, then scrambled by `scramble`, as 32-bit
/// fixed point. Equal to `nested_uniform_scramble(nested_uniform_scramble(index, shuffle).reverse_bits(),
/// scramble)`.
#[inline]
pub fn sobol_owen_1d_reversed(index_rev: u32, shuffle: u32, scramble: u32) -> u32 {
    laine_karras(laine_karras(index_rev, shuffle).reverse_bits(), scramble).reverse_bits()
}
