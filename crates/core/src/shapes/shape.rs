//! The geometry an entity carries, in its local frame: what scene files describe and the BuildAccel stage flattens
//! into primitives.

use crate::mesh::MeshHandle;
use glam::{Vec2, Vec3};

/// Geometry of an entity, in its local frame.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A sphere (an ellipsoid once a non-uniform transform applies).
    Sphere {
        /// Centre, local frame.
        center: Vec3,
        /// Radius, local units (positive).
        radius: f32,
    },
    /// The plane `{x : normal . x = offset}`; unbounded, so accelerators keep it aside.
    Plane {
        /// Normal (need not be unit; the front side).
        normal: Vec3,
        /// Distance of the plane from the origin along the unit normal.
        offset: f32,
    },
    /// One triangle.
    Triangle {
        /// Vertices, local frame; counter-clockwise seen from the front.
        p: [Vec3; 3],
        /// Vertex normals, local frame (`None`: flat shading).
        n: Option<[Vec3; 3]>,
        /// Vertex texture coordinates (`None`: `(0,0), (1,0), (0,1)`).
        uv: Option<[Vec2; 3]>,
    },
    /// A triangle mesh of the scene's [`crate::mesh::MeshStore`].
    Mesh(MeshHandle),
    /// The surface of revolution of a profile curve in the xy-plane (z = 0) about the y axis.
    Revolution {
        /// The profile curve, in the xy-plane.
        profile: super::Curve,
    },
    /// A bicubic Bézier patch: 16 control points, four rows of four (u along a row).
    BezierPatch {
        /// Control points, local frame, four rows of four: `points[4 i + j]`, row `i` along v, column `j` along u.
        points: [Vec3; 16],
    },
}
