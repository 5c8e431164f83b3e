//! Solid (procedural 3D) textures of the 6.837 course (assignment 6), evaluated at the world-space hit point `p`
//! mapped into texture space by the texture's `transform` (`q = transform(p)`). Each is a scalar in [0, 1], used
//! as the `weight` of a `Blend` of two materials (weight 0: the blend's `a`, 1: its `b`):
//!
//! | texture | value |
//! |---|---|
//! | `Checker3d` | `(floor(q.x) + floor(q.y) + floor(q.z)) mod 2` (0 on the cell containing the origin) |
//! | `Noise(octaves)` | `clamp((N(q) + 1) / 2, 0, 1)` with `N(q) = sum_{i < octaves} noise(2^i q) / 2^i` |
//! | `Marble(octaves, frequency, amplitude)` | `(sin(frequency q.x + amplitude N(q)) + 1) / 2` |
//! | `Wood(octaves, frequency, amplitude)` | `(sin(frequency sqrt(q.x^2 + q.z^2) + amplitude N(q)) + 1) / 2`: rings around the texture-space y axis |
//!
//! `noise` is Perlin's improved noise ([`super::perlin`]), as the course's `PerlinNoise::noise`.

use super::perlin::octave_sum;
use glam::{Affine3A, Vec3A};

/// Which solid pattern.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolidKind {
    /// Alternating unit cubes, 0 on the cell containing the origin.
    Checker3d,
    /// Perlin noise summed over octaves, mapped to `[0, 1]`.
    Noise,
    /// Sine bands along texture-space x, perturbed by the noise.
    Marble,
    /// Sine rings around texture-space y, perturbed by the noise.
    Wood,
}

/// A solid texture with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solid {
    /// Checker, noise, marble or wood.
    pub kind: SolidKind,
    /// World point to texture space.
    pub transform: Affine3A,
    /// Number of noise octaves summed (`Noise`, `Marble`, `Wood`); octave `i` at frequency `2^i`, weight `2^-i`.
    pub octaves: u32,
    /// Angular frequency of the sine bands or rings, radians per texture-space unit (`Marble`, `Wood`).
    pub frequency: f32,
    /// Phase perturbation of the bands or rings per unit of noise, radians (`Marble`, `Wood`).
    pub amplitude: f32,
}

impl Solid {
    /// The texture's value in [0, 1] at world point `p`.
    pub fn eval(&self, p: Vec3A) -> f32 {
        let q = self.transform.transform_point3a(p);
        let q = [q.x as f64, q.y as f64, q.z as f64];
        let v = match self.kind {
            SolidKind::Checker3d => {
                let s = q[0].floor() + q[1].floor() + q[2].floor();
                return if s.rem_euclid(2.0) == 0.0 { 0.0 } else { 1.0 };
            }
            SolidKind::Noise => (octave_sum(q, self.octaves) + 1.0) * 0.5,
            SolidKind::Marble => {
                let n = octave_sum(q, self.octaves);
                ((self.frequency as f64 * q[0] + self.amplitude as f64 * n).sin() + 1.0) * 0.5
            }
            SolidKind::Wood => {
                let n = octave_sum(q, self.octaves);
                let r = (q[0] * q[0] + q[2] * q[2]).sqrt();
                ((self.frequency as f64 * r + self.amplitude as f64 * n).sin() + 1.0) * 0.5
            }
        };
        if v.is_finite() { v.clamp(0.0, 1.0) as f32 } else { 0.0 }
    }
}
