//! What a 6.837 scene file says, as parsed (course units and conventions, before conversion): camera, background,
//! ambient light, lights, materials and the object tree. Every object remembers its line; leaf objects carry the
//! material index that was current when they were read (`MaterialIndex` applies in file order, ignoring the
//! tree, as in the course parser).

use glam::Vec3;
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
pub enum CameraTxt {
    /// `size` is the width and height of the view in world units.
    Orthographic { center: Vec3, direction: Vec3, up: Vec3, size: f32 },
    /// `angle` is the full field of view in degrees.
    Perspective { center: Vec3, direction: Vec3, up: Vec3, angle: f32 },
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightTxt {
    /// `direction` is where the light travels; `color` is the course's light colour.
    Directional { direction: Vec3, color: Vec3 },
    /// The colour at distance d is `color / (a0 + a1 d + a2 d^2)`.
    Point { position: Vec3, color: Vec3, attenuation: [f32; 3] },
}

/// A material of the `Materials` block.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialTxt {
    Phong(PhongTxt),
    /// `Checkerboard`, `Noise`, `Marble`, `Wood` (assignment 6): two materials mixed by a solid texture.
    Solid(SolidTxt),
}

/// Which solid texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidTxtKind {
    Checkerboard,
    Noise,
    Marble,
    Wood,
}

/// `Checkerboard { Transform { ops } materialIndex a materialIndex b }`, and `Noise`/`Marble`/`Wood` with
/// `octaves`, `frequency`, `amplitude` (course defaults 1, 1, 1 where a file omits them).
#[derive(Clone, Debug, PartialEq)]
pub struct SolidTxt {
    pub kind: SolidTxtKind,
    /// World point to texture space, composed like an object `Transform`.
    pub ops: Vec<OpTxt>,
    pub materials: [usize; 2],
    pub octaves: u32,
    pub frequency: f32,
    pub amplitude: f32,
}

/// `Material` / `PhongMaterial` with the course's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct PhongTxt {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub exponent: f32,
    pub reflective: Vec3,
    pub transparent: Vec3,
    pub ior: f32,
}

impl Default for PhongTxt {
    fn default() -> Self {
        PhongTxt {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            exponent: 1.0,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            ior: 1.0,
        }
    }
}

/// One operation of a `Transform` block; the list applies like the course's matrix product (first listed =
/// outermost), with `Matrix` already moved to the front where the course pre-multiplies it.
#[derive(Clone, Debug, PartialEq)]
pub enum OpTxt {
    Scale(Vec3),
    UniformScale(f32),
    Translate(Vec3),
    Rotate {
        axis: Vec3,
        degrees: f32,
    },
    /// Rows top to bottom.
    Matrix([[f32; 4]; 4]),
}

#[derive(Clone, Debug, PartialEq)]
pub enum ObjectTxt {
    Group {
        line: usize,
        children: Vec<ObjectTxt>,
    },
    Transform {
        line: usize,
        ops: Vec<OpTxt>,
        child: Box<ObjectTxt>,
    },
    Sphere {
        line: usize,
        center: Vec3,
        radius: f32,
        material: usize,
    },
    Plane {
        line: usize,
        normal: Vec3,
        offset: f32,
        material: usize,
    },
    Triangle {
        line: usize,
        vertices: [Vec3; 3],
        material: usize,
    },
    /// `path` resolved against the scene file's folder. `splines`: for a mesh assignment 8's curve editor made
    /// (`course_meshes.rs`), the spline file next to the scene and the resolutions it was made with (the mesh file
    /// itself may then be missing).
    Mesh {
        line: usize,
        path: PathBuf,
        material: usize,
        splines: Option<(PathBuf, super::spline::Tessellation)>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct SceneTxt {
    pub camera: CameraTxt,
    /// Course default (0.5, 0.5, 0.5).
    pub background: Vec3,
    /// Course default 0, or white when the scene has no lights.
    pub ambient: Vec3,
    pub lights: Vec<LightTxt>,
    pub materials: Vec<MaterialTxt>,
    pub root: Option<ObjectTxt>,
}
