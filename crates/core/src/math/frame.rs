//! An orthonormal frame around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"):
//! branchless, continuous except at one point, exact for unit input.

use glam::Vec3A;

/// A right-handed orthonormal basis `(s, t, n)`: local x, y and z axes in world space.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The first tangent (local x), unit.
    pub s: Vec3A,
    /// The second tangent (local y), unit, `n x s`.
    pub t: Vec3A,
    /// The normal (local z), unit.
    pub n: Vec3A,
}

impl Frame {
    /// A frame whose z axis is the unit vector `n`.
    #[inline]
    pub fn from_normal(n: Vec3A) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3A::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// World direction to local coordinates (z along the normal).
    #[inline]
    pub fn to_local(&self, v: Vec3A) -> Vec3A {
        Vec3A::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local coordinates to a world direction.
    #[inline]
    pub fn to_world(&self, v: Vec3A) -> Vec3A {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}
