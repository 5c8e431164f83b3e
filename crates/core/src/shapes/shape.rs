//! The geometry an entity carries, in its local frame: what scene files describe and the BuildAccel stage flattens
//! into primitives.

use crate::mesh::MeshHandle;
use glam::{Vec2, Vec3};

/// Geometry of an entity, in its local frame.
#[derive(Clone, Debug)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// The plane `{x : normal . x = offset}`; unbounded, so accelerators keep it aside.
    Plane {
        normal: Vec3,
        offset: f32,
    },
    Triangle {
        p: [Vec3; 3],
        n: Option<[Vec3; 3]>,
        uv: Option<[Vec2; 3]>,
    },
    Mesh(MeshHandle),
    /// The surface of revolution of a profile curve in the xy-plane (z = 0) about the y axis.
    Revolution {
        profile: super::Curve,
    },
    /// A bicubic Bézier patch: 16 control points, four rows of four (u along a row).
    BezierPatch {
        points: [Vec3; 16],
    },
}
