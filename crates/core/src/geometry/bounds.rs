//! Axis-aligned bounding boxes.

use glam::{Affine3A, Vec3A};

/// An axis-aligned box, `min` to `max` inclusive; empty when `min > max` on any axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The corner of smallest coordinates.
    pub min: Vec3A,
    /// The corner of largest coordinates.
    pub max: Vec3A,
}

impl Default for Bounds {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Bounds {
    /// The empty box (`min` = +inf, `max` = -inf): the identity of [`Bounds::union`] and [`Bounds::with_point`].
    pub const EMPTY: Bounds = Bounds { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };

    /// The box from `min` to `max` as given (not reordered).
    #[inline]
    pub fn new(min: Vec3A, max: Vec3A) -> Self {
        Bounds { min, max }
    }

    /// The smallest box holding `points` ([`Bounds::EMPTY`] for none).
    #[inline]
    pub fn from_points(points: &[Vec3A]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.with_point(p))
    }

    /// The smallest box holding this one and `p`.
    #[inline]
    pub fn with_point(self, p: Vec3A) -> Self {
        Bounds { min: self.min.min(p), max: self.max.max(p) }
    }

    /// The smallest box holding both boxes.
    #[inline]
    pub fn union(self, o: Bounds) -> Self {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// True when `min > max` on some axis (NaN corners count as not empty).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// `max - min`: the box's extent per axis (negative for an empty box).
    #[inline]
    pub fn diagonal(&self) -> Vec3A {
        self.max - self.min
    }

    /// The midpoint of `min` and `max`.
    #[inline]
    pub fn center(&self) -> Vec3A {
        0.5 * (self.min + self.max)
    }

    /// Surface area (0 for an empty box).
    #[inline]
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.diagonal();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// The box of the 8 transformed corners: a conservative bound of any shape inside `self` under `m`.
    pub fn transformed(&self, m: &Affine3A) -> Bounds {
        let mut out = Bounds::EMPTY;
        for i in 0..8 {
            let c = Vec3A::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            out = out.with_point(m.transform_point3a(c));
        }
        out
    }

    /// Slab test: the parametric interval `(t0, t1)` of the ray inside the box, if any, clipped to `[0, tmax]`.
    #[inline]
    pub fn intersect_ray(&self, origin: Vec3A, inv_dir: Vec3A, tmax: f32) -> Option<(f32, f32)> {
        let ta = (self.min - origin) * inv_dir;
        let tb = (self.max - origin) * inv_dir;
        let tnear = ta.min(tb).max_element().max(0.0);
        let tfar = ta.max(tb).min_element().min(tmax);
        (tnear <= tfar).then_some((tnear, tfar))
    }
}
