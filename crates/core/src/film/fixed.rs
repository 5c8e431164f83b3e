//! Fixed-point radiance sums: addition of integers is exact and order-independent, so a film merged from shards,
//! or resumed from a file, equals the one-process film bit for bit whatever order its parts were added in.
//!
//! A value `v` is stored as `round(v * 2^40)` in an `i128`: a resolution of 9.1e-13 (far below an f32's precision
//! for any radiance a pixel shows) and a range of 1.5e26, so no realistic sum of samples overflows (additions
//! saturate rather than wrap if one ever did). Conversion is a pure function of the f32/f64 value, so the same
//! sample sums give the same integers on every machine.

/// Scale of the fixed-point representation: 2^40.
pub const FIXED_ONE: f64 = 1_099_511_627_776.0;

/// The largest sum a channel holds, `(2^127 - 1) / 2^40` (about 1.5e26): sums that reach it stay there.
pub const MAX_SUM: f64 = i128::MAX as f64 / FIXED_ONE;

/// `v` in fixed point (non-finite values count as 0; the film reports them separately).
#[inline]
pub fn to_fixed(v: f64) -> i128 {
    if !v.is_finite() {
        return 0;
    }
    let y = (v * FIXED_ONE).round();
    // The common case fits an i64, whose conversion is one instruction; `as` saturates either way.
    if y.abs() < 9.0e18 { y as i64 as i128 } else { y as i128 }
}

/// A fixed-point value back as f64.
#[inline]
pub fn from_fixed(f: i128) -> f64 {
    f as f64 / FIXED_ONE
}

/// An RGB sum in fixed point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FixedRgb(pub [i128; 3]);

impl FixedRgb {
    /// `(r, g, b)` in fixed point, each by [`to_fixed`] (non-finite channels become 0).
    #[inline]
    pub fn from_rgb(r: f64, g: f64, b: f64) -> Self {
        FixedRgb([to_fixed(r), to_fixed(g), to_fixed(b)])
    }

    /// Add `o` channel by channel, saturating at the `i128` range instead of wrapping.
    #[inline]
    pub fn add(&mut self, o: FixedRgb) {
        for c in 0..3 {
            self.0[c] = self.0[c].saturating_add(o.0[c]);
        }
    }

    /// Add one sample's radiance, converted exactly as [`FixedRgb::from_rgb`] converts it: the sum of a pixel's
    /// samples is then the same integers whatever order or grouping they are added in.
    #[inline]
    pub fn add_sample(&mut self, v: glam::Vec3) {
        self.add(FixedRgb::from_rgb(v.x as f64, v.y as f64, v.z as f64));
    }

    /// Whether a channel sits at the range's end (a sum of radiance above [`MAX_SUM`], clipped).
    #[inline]
    pub fn saturated(&self) -> bool {
        self.0.iter().any(|&c| c == i128::MAX || c == i128::MIN)
    }

    /// The sums back as `f64` per channel ([`from_fixed`]).
    #[inline]
    pub fn to_dvec3(self) -> glam::DVec3 {
        glam::DVec3::new(from_fixed(self.0[0]), from_fixed(self.0[1]), from_fixed(self.0[2]))
    }
}
