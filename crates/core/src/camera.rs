//! Camera ray generation. Film positions `(px, py)` are in pixels, `px` to the right and `py` down from the top-left
//! corner. A pinhole maps them to the camera-space direction `(x, y, 1)` with
//! `x = (2 px / W - 1) tan(fov_y / 2) W / H` towards image-right and `y = (1 - 2 py / H) tan(fov_y / 2)` towards
//! image-up, where image-right = normalize(forward x up) and image-up = right x forward: the image is not mirrored
//! (the same convention as Mitsuba 3's `perspective` sensor with a vertical fov).
//!
//! **Thin lens** (`aperture_radius > 0`, Mitsuba's `thinlens`): the pinhole direction `d = (x, y, 1)` meets the
//! plane of focus (camera-space depth `focus_distance`, a plane perpendicular to the view, not a sphere) at
//! `f = focus_distance d`; the ray starts at a point `a` of the aperture disk (concentric map of the lens sample,
//! radius `aperture_radius`, in the image-right/image-up plane through the eye) and goes through `f`. Every ray has
//! weight 1. Points in the plane of focus are sharp; an aperture of 0 is exactly the pinhole. Orthographic
//! cameras get the same lens: rays parallel to the view through the film point converge at the focus plane.
//!
//! **Mirror and crop** (for pbrt scenes): `mirror` makes image-right `up x forward` (pbrt's left-handed screen
//! space); `crop: [x0, y0, x1, y1]` renders only that window of the full frame (pbrt's `cropwindow`): film
//! position `(px, py)` of the `W x H` window maps to the full-frame fraction `(x0 + (x1 - x0) px / W, y0 + (y1 -
//! y0) py / H)`, and the fov and aspect ratio are the full frame's.

use crate::geometry::Ray;
use crate::sampling::warp::concentric_disk;
use glam::{Affine3A, Vec2, Vec3, Vec3A};

/// Camera projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole; `fov_y` is the full vertical field of view in degrees.
    Perspective {
        /// Full vertical field of view of the full frame, degrees, in `(0, 180)`.
        fov_y: f32,
    },
    /// Parallel projection; `height` is the world-space height of the view.
    Orthographic {
        /// Height of the full frame's view, world units.
        height: f32,
    },
}

/// A camera looking from `eye` to `target` (local frame of its entity), with an image size in pixels. An
/// `aperture_radius` above 0 makes it a thin lens focused at `focus_distance` along the view direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Position of the eye (the pinhole, or the lens centre), in the entity's frame.
    pub eye: Vec3,
    /// The point looked at, in the entity's frame; `target - eye` is the view direction.
    pub target: Vec3,
    /// Up hint, in the entity's frame: image-up is the part of it perpendicular to the view (it must not be
    /// parallel to the view).
    pub up: Vec3,
    /// Perspective or orthographic, with its field of view.
    pub projection: Projection,
    /// Image width in pixels (the crop window's, when cropped).
    pub width: u32,
    /// Image height in pixels (the crop window's, when cropped).
    pub height: u32,
    /// Radius of the thin lens's aperture disk, world units; 0 is a pinhole.
    pub aperture_radius: f32,
    /// Distance from the eye to the plane of focus along the view direction, world units (used only when
    /// `aperture_radius > 0`).
    pub focus_distance: f32,
    /// Mirror the image left-right: image-right is `up x forward` instead of `forward x up` (pbrt's left-handed
    /// screen space; a pbrt `LookAt` camera sees the world mirrored relative to Prism's convention).
    pub mirror: bool,
    /// Render only this window of the full frame, `[x_min, y_min, x_max, y_max]` as fractions of the frame
    /// (0 = left/top edge, 1 = right/bottom; pbrt's `cropwindow`). `width` x `height` are the window's pixels,
    /// so the full frame's aspect ratio is `(width / (x_max - x_min)) / (height / (y_max - y_min))`.
    pub crop: Option<[f32; 4]>,
}

impl Default for Camera {
    /// A pinhole at (0, 0, 5) looking at the origin, +y up, 40 degrees, 256 x 256.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y: 40.0 },
            width: 256,
            height: 256,
            aperture_radius: 0.0,
            focus_distance: 5.0,
            mirror: false,
            crop: None,
        }
    }
}

/// A camera resolved to world space, ready to generate rays.
#[derive(Clone, Copy, Debug)]
pub struct CameraRig {
    eye: Vec3A,
    forward: Vec3A,
    right: Vec3A,
    up: Vec3A,
    /// Half-extent of the (full-frame) image plane at distance 1 (perspective) or in world units (orthographic).
    half_w: f32,
    half_h: f32,
    /// The film window as fractions of the full frame: `[x0, y0, x1 - x0, y1 - y0]` (`[0, 0, 1, 1]` uncropped).
    window: [f32; 4],
    /// `window[2] / width` and `window[3] / height`: film pixels to full-frame fractions by one multiplication (a
    /// division would sit on every sample's path from its pixel position to its first traversal step).
    film_scale: [f32; 2],
    ortho: bool,
    aperture_radius: f32,
    focus_distance: f32,
    /// Image width in pixels (the crop window's, when cropped).
    pub width: u32,
    /// Image height in pixels (the crop window's, when cropped).
    pub height: u32,
}

impl CameraRig {
    /// Returns `None` when the look-at frame is degenerate (eye == target, or up parallel to the view).
    pub fn new(cam: &Camera, world_from_local: &Affine3A) -> Option<Self> {
        let eye = world_from_local.transform_point3a(cam.eye.into());
        let target = world_from_local.transform_point3a(cam.target.into());
        let up_w = world_from_local.transform_vector3a(cam.up.into());
        let forward: Vec3A = crate::math::unit_vector((target - eye).into())?.into();
        let right: Vec3A =
            crate::math::unit_vector(forward.cross(crate::math::unit_vector(up_w.into())?.into()).into())?.into();
        let up = right.cross(forward);
        let right = if cam.mirror { -right } else { right };
        let [x0, y0, x1, y1] = cam.crop.unwrap_or([0.0, 0.0, 1.0, 1.0]);
        let window = [x0, y0, x1 - x0, y1 - y0];
        if !(window.iter().all(|v| v.is_finite()) && window[2] > 0.0 && window[3] > 0.0) {
            return None;
        }
        // The full frame's aspect ratio: the window's pixels stretched back to the whole frame.
        let aspect = (cam.width as f32 / window[2]) / (cam.height as f32 / window[3]);
        let (half_h, ortho) = match cam.projection {
            Projection::Perspective { fov_y } => ((0.5 * fov_y.to_radians()).tan(), false),
            Projection::Orthographic { height } => (0.5 * height, true),
        };
        Some(CameraRig {
            eye,
            forward,
            right,
            up,
            half_w: half_h * aspect,
            half_h,
            window,
            film_scale: [window[2] / cam.width as f32, window[3] / cam.height as f32],
            ortho,
            aperture_radius: cam.aperture_radius,
            focus_distance: cam.focus_distance,
            width: cam.width,
            height: cam.height,
        })
    }

    /// Image-plane coordinates (x towards image-right, y towards image-up) of film position `film` (pixels).
    #[inline]
    fn plane(&self, film: Vec2) -> (f32, f32) {
        let [x0, y0, ..] = self.window;
        let fx = x0 + film.x * self.film_scale[0];
        let fy = y0 + film.y * self.film_scale[1];
        ((2.0 * fx - 1.0) * self.half_w, (1.0 - 2.0 * fy) * self.half_h)
    }

    /// The primary ray through film position `film` (pixels), marked coherent ([`Ray::coherent`]).
    #[inline]
    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let (x, y) = self.plane(film);
        if self.ortho {
            Ray::new(self.eye + self.right * x + self.up * y, self.forward).coherent()
        } else {
            Ray::new(self.eye, (self.forward + self.right * x + self.up * y).normalize()).coherent()
        }
    }

    /// [`CameraRig::generate_ray`] for each of `films` (at most 16) into `out`, the same rays bit for bit. A
    /// pinhole's perspective rays are computed sixteen lanes at a time (each lane the operations of `generate_ray`
    /// in their order: the plane position, `forward + right x + up y`, and glam's `normalize`, a division by the
    /// square root of `(x x + y y) + z z`); other cameras one at a time. For a chunk of camera-ray packets
    /// (`PerPixel`), where one at a time the rays' square roots and divisions were a few per cent of `textured`.
    pub fn generate_rays(&self, films: &[Vec2], out: &mut [Ray]) {
        const LANES: usize = 16;
        assert!(films.len() <= LANES && out.len() == films.len(), "{} film positions", films.len());
        if self.ortho {
            for (o, &f) in out.iter_mut().zip(films) {
                *o = self.generate_ray(f);
            }
            return;
        }
        let mut at = [Vec2::ZERO; LANES];
        at[..films.len()].copy_from_slice(films);
        let (f, r, u) = (self.forward.to_array(), self.right.to_array(), self.up.to_array());
        let mut dir = [[0.0f32; LANES]; 3];
        for (l, film) in at.iter().enumerate() {
            let (x, y) = self.plane(*film);
            let d = [0, 1, 2].map(|c| f[c] + r[c] * x + u[c] * y);
            let len = ((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]).sqrt();
            for c in 0..3 {
                dir[c][l] = d[c] / len;
            }
        }
        for (l, o) in out.iter_mut().enumerate() {
            *o = Ray::new(self.eye, Vec3A::new(dir[0][l], dir[1][l], dir[2][l])).coherent();
        }
    }

    /// True for a thin lens (rays need a lens sample).
    #[inline]
    pub fn has_lens(&self) -> bool {
        self.aperture_radius > 0.0
    }

    /// The ray through film position `film` (pixels) and lens sample `u_lens` in [0,1)^2 (ignored by a pinhole).
    #[inline]
    pub fn generate_ray_lens(&self, film: Vec2, u_lens: Vec2) -> Ray {
        if !self.has_lens() {
            return self.generate_ray(film);
        }
        let (x, y) = self.plane(film);
        let a = concentric_disk(u_lens) * self.aperture_radius;
        let lens = self.right * a.x + self.up * a.y;
        if self.ortho {
            let o = self.eye + self.right * x + self.up * y;
            let focus = o + self.forward * self.focus_distance;
            Ray::new(o + lens, (focus - (o + lens)).normalize()).coherent()
        } else {
            let focus = (self.forward + self.right * x + self.up * y) * self.focus_distance;
            Ray::new(self.eye + lens, (focus - lens).normalize()).coherent()
        }
    }

    /// Width in world units of one pixel's footprint at `distance` along the view (perspective), or of one pixel
    /// (orthographic): a scale for radii that must adapt to the image resolution.
    #[inline]
    pub fn pixel_footprint(&self, distance: f32) -> f32 {
        let per_pixel = 2.0 * self.half_h * self.window[3] / self.height as f32;
        if self.ortho { per_pixel } else { per_pixel * distance }
    }

    /// True for a pinhole perspective camera (no lens, not orthographic).
    pub fn is_pinhole(&self) -> bool {
        !self.ortho && !self.has_lens()
    }

    /// True for an orthographic camera (its rays are parallel: no eye point a light path could be connected to).
    pub fn is_orthographic(&self) -> bool {
        self.ortho
    }

    /// Distance from a pinhole to the image plane on which a pixel has area 1: the plane where film positions are
    /// pixels.
    #[inline]
    fn unit_pixel_plane(&self) -> f32 {
        self.height as f32 / (2.0 * self.half_h * self.window[3])
    }

    /// The density of a pinhole's camera ray in unit direction `dir`, in solid angle per unit of film area (pixels):
    /// `d^2 / cos^3` for the image plane at distance `d` where a pixel has area 1 and `cos` the angle to the view
    /// (SmallVCM's `cameraPdfW`). 0 behind the camera.
    #[inline]
    pub fn ray_pdf(&self, dir: Vec3A) -> f32 {
        let cos = dir.dot(self.forward);
        if cos <= 0.0 {
            return 0.0;
        }
        let d = self.unit_pixel_plane();
        d * d / (cos * cos * cos)
    }

    /// Where the world point `p` appears on a pinhole's film (pixels), with the unit direction from `p` to the eye,
    /// the distance and [`CameraRig::ray_pdf`] of the ray through it; `None` behind the camera, outside the film,
    /// or for cameras that are not pinholes. Light tracing splats a light vertex seen by the camera there.
    pub fn project(&self, p: Vec3A) -> Option<(Vec2, Vec3A, f32, f32)> {
        if !self.is_pinhole() {
            return None;
        }
        let d = p - self.eye;
        let z = d.dot(self.forward);
        if !(z > 0.0 && z.is_finite()) {
            return None;
        }
        let film = self.film_of(d.dot(self.right) / z, d.dot(self.up) / z)?;
        let dist = d.length();
        let to_eye = -d / dist;
        Some((film, to_eye, dist, self.ray_pdf(-to_eye)))
    }

    /// The film position (pixels) of image-plane coordinates `(x, y)` (the inverse of `plane`), `None` off the film.
    #[inline]
    fn film_of(&self, x: f32, y: f32) -> Option<Vec2> {
        let [x0, y0, ..] = self.window;
        let film = Vec2::new(
            ((0.5 * (x / self.half_w + 1.0)) - x0) / self.film_scale[0],
            ((0.5 * (1.0 - y / self.half_h)) - y0) / self.film_scale[1],
        );
        (film.x >= 0.0 && film.y >= 0.0 && film.x < self.width as f32 && film.y < self.height as f32).then_some(film)
    }

    /// [`CameraRig::project`] for a pinhole or a thin lens, seen from the lens point that `u_lens` picks (the
    /// concentric map of [`CameraRig::generate_ray_lens`]): the film position whose ray from that lens point passes
    /// through `p` (where the segment crosses the plane of focus, as a pinhole direction), the unit direction from `p`
    /// to the lens point, the distance, [`CameraRig::ray_pdf`] of that ray's direction, and the lens point. For a
    /// thin lens `ray_pdf` of the actual direction is still the ray's density per unit film area (film to focus
    /// plane to direction from the lens point has Jacobian `cos^3`, as for a pinhole); the lens point's own density
    /// is the same for every strategy and cancels. `None` for orthographic cameras.
    pub fn project_lens(&self, p: Vec3A, u_lens: Vec2) -> Option<(Vec2, Vec3A, f32, f32, Vec3A)> {
        if self.ortho {
            return None;
        }
        if !self.has_lens() {
            return self.project(p).map(|(film, to_eye, dist, pdf)| (film, to_eye, dist, pdf, self.eye));
        }
        let a = concentric_disk(u_lens) * self.aperture_radius;
        let offset = self.right * a.x + self.up * a.y;
        let lens = self.eye + offset;
        let d = p - lens;
        let z = d.dot(self.forward);
        if !(z > 0.0 && z.is_finite()) {
            return None;
        }
        // The segment meets the plane of focus at `eye + q`; `q`'s depth is the focus distance.
        let q = offset + d * (self.focus_distance / z);
        let depth = q.dot(self.forward);
        let film = self.film_of(q.dot(self.right) / depth, q.dot(self.up) / depth)?;
        let dist = d.length();
        let to_eye = -d / dist;
        Some((film, to_eye, dist, self.ray_pdf(-to_eye), lens))
    }

    /// The eye (pinhole or lens centre), world space.
    pub fn eye(&self) -> Vec3A {
        self.eye
    }

    /// The unit view direction, world space.
    pub fn forward(&self) -> Vec3A {
        self.forward
    }
}
