//! Environment maps: radiance from every direction, read from Radiance `.hdr` (RGBE), OpenEXR or PFM files in one
//! of four layouts, with bilinear lookup.
//!
//! **Direction convention** (env frame; the entity's transform rotates it into the world):
//! - equirectangular (2:1): `u = 0.5 + atan2(x, -z) / 2 pi`, `v = acos(y) / pi`: the image centre is straight ahead
//!   along -z (where a default camera looks), +x is at u = 0.75 (to the right, not mirrored), +y is the top row;
//! - cube faces are stored as seen from inside the cube, with frames (centre, image-right, image-down):
//!   +x: (+x, +z, -y), -x: (-x, -z, -y), +y: (+y, +x, -z), -y: (-y, +x, +z), +z: (+z, -x, -y), -z: (-z, +x, -y).
//!   A vertical cross (3 x 4 faces) holds +y (row 0, middle), -x, -z, +x (row 1), -y (row 2, middle) and +z (row 3,
//!   middle, stored rotated by 180 degrees); six separate faces `px nx py ny pz nz` follow the three.js / OpenGL
//!   cube-map convention (a world direction w is looked up as (-w.x, w.y, w.z) in the GL face tables);
//! - equal-area octahedral (square, pbrt-v4's `imagemap` infinite lights): the centre is straight up (+y), the
//!   corners straight down, every texel the same solid angle (`equal_area.rs`).
//!
//! Texels that are NaN or negative are replaced by 0 (counted in a warning); infinite texels are an error.

mod cube;
mod equal_area;
mod image_file;

pub use cube::{CUBE_FACES, FaceFrame, cube_coords, cube_direction, cube_jacobian, cube_texel_solid_angle};
pub use equal_area::{EQUAL_AREA_JACOBIAN, equal_area_coords, equal_area_direction, octahedral_texel};

use crate::error::{PrismError, Result};
use crate::math::floor_f32;
use crate::texture::Wrap;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

/// One rectangular image of linear RGB radiance (a panorama or a cube face), row-major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height` texels of linear RGB radiance, finite and non-negative once loaded.
    pub texels: Vec<Vec3>,
}

impl EnvImage {
    /// The texel in column `x < width` and row `y < height`, counted from the top-left.
    #[inline]
    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        self.texels[(y * self.width + x) as usize]
    }

    /// The texel `(x0, y0)` up-left of the continuous coordinates `uv` (in texels, texel centres at `k + 0.5`)
    /// and the bilinear weights `(fx, fy)` towards `(x0 + 1, y0 + 1)`.
    #[inline]
    fn bilinear_corner(&self, uv: Vec2) -> (i64, i64, f32, f32) {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (floor_f32(x), floor_f32(y));
        (x0 as i64, y0 as i64, x - x0, y - y0)
    }

    /// Bilinear lookup at continuous coordinates `uv` in [0,1]^2; x wraps when `wrap_x`, otherwise clamps.
    #[inline]
    fn bilinear(&self, uv: Vec2, wrap_x: bool) -> Vec3 {
        let (x0, y0, fx, fy) = self.bilinear_corner(uv);
        // The image textures' index wrapping (which skips the division where both indices lie inside the image).
        let (c0, c1) = if wrap_x { Wrap::Repeat } else { Wrap::Clamp }.index_pair(x0, self.width);
        let (r0, r1) = Wrap::Clamp.index_pair(y0, self.height);
        let t = |c: usize, r: usize| self.texels[r * self.width as usize + c];
        lerp_corners([t(c0, r0), t(c1, r0), t(c0, r1), t(c1, r1)], fx, fy)
    }

    /// Bilinear lookup at `uv` in `[0, 1]^2` of an equal-area square, folding over its edges as the sphere does
    /// (the fold couples x and y, so the corners are not a product of column and row pairs).
    #[inline]
    fn bilinear_octahedral(&self, uv: Vec2) -> Vec3 {
        let (x0, y0, fx, fy) = self.bilinear_corner(uv);
        let (w, h) = (self.width as i64, self.height as i64);
        let t = |x: i64, y: i64| self.texels[EnvLayout::EqualArea.texel_index(x, y, w, h)];
        lerp_corners([t(x0, y0), t(x0 + 1, y0), t(x0, y0 + 1), t(x0 + 1, y0 + 1)], fx, fy)
    }
}

/// Bilinear interpolation of the corners (top-left, top-right, bottom-left, bottom-right).
#[inline]
fn lerp_corners(c: [Vec3; 4], fx: f32, fy: f32) -> Vec3 {
    let top = c[0] * (1.0 - fx) + c[1] * fx;
    let bottom = c[2] * (1.0 - fx) + c[3] * fx;
    top * (1.0 - fy) + bottom * fy
}

/// How the map's images are arranged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvLayout {
    /// One 2:1 latitude–longitude panorama.
    Equirect,
    /// Six square faces in the order +x, -x, +y, -y, +z, -z.
    Cube,
    /// One square, pbrt-v4's equal-area octahedral mapping.
    EqualArea,
}

impl EnvLayout {
    /// The index into a `w x h` image of the texel a lookup reads at integer coordinates `(x, y)`, which may lie
    /// one texel outside: x wraps around a panorama, the square folds over its edges (octahedral), cube faces
    /// clamp.
    #[inline]
    pub fn texel_index(self, x: i64, y: i64, w: i64, h: i64) -> usize {
        let (x, y) = match self {
            EnvLayout::Equirect => (x.rem_euclid(w), y.clamp(0, h - 1)),
            EnvLayout::Cube => (x.clamp(0, w - 1), y.clamp(0, h - 1)),
            EnvLayout::EqualArea => octahedral_texel(x, y, w, h),
        };
        (y * w + x) as usize
    }
}

/// Layout of the file(s) a map is read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
pub enum SourceLayout {
    /// One 2:1 latitude–longitude panorama.
    Equirect,
    /// One 3:4 image, the six faces in a vertical cross (see the module notes).
    Cross,
    /// Six square images `px nx py ny pz nz`, in the three.js / OpenGL cube-map convention.
    Faces,
    /// One square image in pbrt-v4's equal-area octahedral mapping.
    EqualArea,
}

/// An environment map: linear RGB radiance for every direction of its env frame.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMap {
    /// A panorama or a cube.
    pub layout: EnvLayout,
    /// One image (equirect) or six faces (cube).
    pub images: Vec<EnvImage>,
    /// Texels replaced by 0 because they were NaN or negative.
    pub clamped_texels: usize,
}

/// Equirect (u, v) of a unit direction in the env frame.
#[inline]
pub fn equirect_coords(d: Vec3A) -> Vec2 {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    Vec2::new(u - floor_f32(u), v)
}

/// Unit direction of equirect coordinates.
#[inline]
pub fn equirect_direction(uv: Vec2) -> Vec3A {
    let theta = uv.y * PI;
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let s = theta.sin();
    Vec3A::new(s * phi.sin(), theta.cos(), -s * phi.cos())
}

impl EnvMap {
    /// A panorama map of `image` (2:1 expected, not checked).
    pub fn equirect(image: EnvImage) -> Self {
        EnvMap { layout: EnvLayout::Equirect, images: vec![image], clamped_texels: 0 }
    }

    /// A cube map of six square `faces` of one size, in the order of [`CUBE_FACES`] (not checked).
    pub fn cube(faces: Vec<EnvImage>) -> Self {
        EnvMap { layout: EnvLayout::Cube, images: faces, clamped_texels: 0 }
    }

    /// Load a map. `paths` holds one file (equirect or cross) or six (faces, in the order px nx py ny pz nz).
    /// `layout` `None` guesses from the file count and the aspect ratio (2:1 equirect, 3:4 cross).
    pub fn load(paths: &[PathBuf], layout: Option<SourceLayout>) -> Result<Self> {
        let layout = match (layout, paths.len()) {
            (Some(l), _) => l,
            (None, 6) => SourceLayout::Faces,
            (None, 1) => {
                let img = image_file::read(&paths[0])?;
                return Self::from_single(img, &paths[0], None);
            }
            (None, n) => return Err(PrismError::invalid(format!("an environment map needs 1 or 6 files, got {n}"))),
        };
        match layout {
            SourceLayout::Faces => {
                if paths.len() != 6 {
                    return Err(PrismError::invalid(format!(
                        "a six-face environment map needs 6 files (px nx py ny pz nz), got {}",
                        paths.len()
                    )));
                }
                let mut files = Vec::with_capacity(6);
                let mut clamped = 0;
                for p in paths {
                    let (img, c) = image_file::read(p)?;
                    clamped += c;
                    files.push((img, p.clone()));
                }
                let mut map = cube::from_gl_faces(files)?;
                map.clamped_texels = clamped;
                Ok(map)
            }
            single => {
                if paths.len() != 1 {
                    return Err(PrismError::invalid(format!(
                        "a {single:?} environment map is one file, got {}",
                        paths.len()
                    )));
                }
                let img = image_file::read(&paths[0])?;
                Self::from_single(img, &paths[0], Some(single))
            }
        }
    }

    /// A map from one decoded image (equirect or cross; `path` names it in errors), as [`EnvMap::load`] makes it
    /// from a file: texels checked, layout guessed from the aspect ratio unless given.
    pub fn from_image(image: crate::io::Image, path: &Path, layout: Option<SourceLayout>) -> Result<Self> {
        if layout == Some(SourceLayout::Faces) {
            return Err(PrismError::invalid("a six-face environment map is six files"));
        }
        Self::from_single(image_file::from_image(image, path)?, path, layout)
    }

    fn from_single(img: (EnvImage, usize), path: &Path, layout: Option<SourceLayout>) -> Result<Self> {
        let (image, clamped) = img;
        let (w, h) = (image.width, image.height);
        // A given layout is used whatever the aspect ratio; only a missing one is guessed. (An `unwrap_or` here
        // evaluated the guess, and its error for unusual ratios, even when the layout was given.)
        let layout = match layout {
            Some(l) => l,
            None if w == 2 * h => SourceLayout::Equirect,
            None if 4 * w == 3 * h => SourceLayout::Cross,
            None if w == h => SourceLayout::EqualArea,
            None => {
                return Err(PrismError::format(
                    path,
                    format!(
                        "cannot tell the layout of a {w}x{h} map: expected 2:1 (equirect), 3:4 (vertical cross) or \
                         square (equal-area octahedral); give `layout: Equirect` to use it as a panorama"
                    ),
                ));
            }
        };
        let mut map = match layout {
            SourceLayout::Equirect => EnvMap::equirect(image),
            SourceLayout::Cross => {
                if w % 3 != 0 || 4 * w != 3 * h {
                    return Err(PrismError::format(
                        path,
                        format!("a vertical cross must be 3:4 with square faces, got {w}x{h}"),
                    ));
                }
                cube::from_cross(&image)
            }
            SourceLayout::EqualArea => {
                if w != h {
                    return Err(PrismError::format(path, format!("an equal-area map must be square, got {w}x{h}")));
                }
                EnvMap { layout: EnvLayout::EqualArea, images: vec![image], clamped_texels: 0 }
            }
            SourceLayout::Faces => unreachable!("faces are six files"),
        };
        map.clamped_texels = clamped;
        Ok(map)
    }

    /// Radiance arriving from unit direction `d` (env frame), bilinearly filtered.
    #[inline]
    pub fn lookup(&self, d: Vec3A) -> Vec3 {
        match self.layout {
            EnvLayout::Equirect => self.images[0].bilinear(equirect_coords(d), true),
            EnvLayout::Cube => {
                let (face, uv) = cube_coords(d);
                self.images[face].bilinear(uv, false)
            }
            EnvLayout::EqualArea => self.images[0].bilinear_octahedral(equal_area_coords(d)),
        }
    }

    /// (image, u, v) of a direction.
    #[inline]
    pub fn coords(&self, d: Vec3A) -> (usize, Vec2) {
        match self.layout {
            EnvLayout::Equirect => (0, equirect_coords(d)),
            EnvLayout::Cube => cube_coords(d),
            EnvLayout::EqualArea => (0, equal_area_coords(d)),
        }
    }

    /// Direction of (image, u, v).
    #[inline]
    pub fn direction(&self, image: usize, uv: Vec2) -> Vec3A {
        match self.layout {
            EnvLayout::Equirect => equirect_direction(uv),
            EnvLayout::Cube => cube_direction(image, uv),
            EnvLayout::EqualArea => equal_area_direction(uv),
        }
    }

    /// Solid angle per unit (u, v) area at a point of an image: 2 pi^2 sin(theta) for equirect, the face
    /// Jacobian 4 / (1 + s^2 + t^2)^(3/2) for cube faces, 4 pi for the equal-area square.
    #[inline]
    pub fn jacobian(&self, uv: Vec2) -> f32 {
        match self.layout {
            EnvLayout::Equirect => 2.0 * PI * PI * (uv.y * PI).sin(),
            EnvLayout::Cube => cube_jacobian(uv),
            EnvLayout::EqualArea => EQUAL_AREA_JACOBIAN,
        }
    }

    /// The integral of the looked-up radiance over the sphere, `integral map(w) dw` (RGB): each texel's mean
    /// bilinearly filtered value over its footprint (the lookup's 3x3 kernel, with its wrap/clamp rules) times the
    /// texel's exact solid angle. Exact for maps that are constant per face and to second order otherwise.
    pub fn integral(&self) -> Vec3 {
        let mut sum = glam::DVec3::ZERO;
        for (k, img) in self.images.iter().enumerate() {
            let (w, h) = (img.width as i64, img.height as i64);
            let at = |x: i64, y: i64| img.texels[self.layout.texel_index(x, y, w, h)].as_dvec3();
            for y in 0..h {
                for x in 0..w {
                    let edges = at(x - 1, y) + at(x + 1, y) + at(x, y - 1) + at(x, y + 1);
                    let corners = at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1);
                    let filtered = (36.0 * at(x, y) + 6.0 * edges + corners) / 64.0;
                    sum += filtered * self.texel_solid_angle(k, x as u32, y as u32) as f64;
                }
            }
        }
        sum.as_vec3()
    }

    /// Exact solid angle of texel (x, y) of an image.
    pub fn texel_solid_angle(&self, image: usize, x: u32, y: u32) -> f32 {
        let img = &self.images[image];
        match self.layout {
            EnvLayout::Equirect => {
                let t0 = y as f64 / img.height as f64 * std::f64::consts::PI;
                let t1 = (y + 1) as f64 / img.height as f64 * std::f64::consts::PI;
                ((t0.cos() - t1.cos()) * 2.0 * std::f64::consts::PI / img.width as f64) as f32
            }
            EnvLayout::Cube => cube_texel_solid_angle(img.width, x, y),
            EnvLayout::EqualArea => 4.0 * PI / (img.width as f32 * img.height as f32),
        }
    }
}
