//! Multiple importance sampling weights (Veach 1997): how two strategies that can produce the same sample share it.

/// The power heuristic (exponent 2) weight of a sample drawn with density `a` when another strategy would have drawn
/// it with density `b`: `a^2 / (a^2 + b^2)`, and 0 when both densities are 0.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 == 0.0 { 0.0 } else { a2 / (a2 + b2) }
}
