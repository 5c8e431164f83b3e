//! The glTF's cameras and the automatic one: perspective and orthographic cameras looking down their node's -z,
//! the one `--camera NAME|INDEX` picks, and without one a camera framing the box of what is drawn, leaving out
//! planar parts (grounds, backdrops) more than 3 times the size of the rest, which would leave the model sub-pixel
//! (TonemappingTest's ground quad).

use super::Loader;
use glam::{Mat4, Vec3};
use hecs::World;
use prism_core::error::Result;
use prism_engine::components::{Camera, Name, Projection};

impl Loader<'_> {
    pub(super) fn camera(&self, cam: &gltf::Camera, label: &str) -> Result<Camera> {
        let (projection, aspect) = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let fov = p.yfov().to_degrees();
                if !(fov > 0.0 && fov < 180.0) {
                    return Err(self.err(format!("{label}: camera yfov must be in (0, pi), got {}", p.yfov())));
                }
                (Projection::Perspective { fov_y: fov }, p.aspect_ratio())
            }
            gltf::camera::Projection::Orthographic(o) => {
                if !(o.ymag() > 0.0 && o.xmag() > 0.0) {
                    return Err(self.err(format!("{label}: orthographic xmag and ymag must be positive")));
                }
                (Projection::Orthographic { height: 2.0 * o.ymag() }, Some(o.xmag() / o.ymag()))
            }
        };
        let width = match aspect {
            Some(a) if a.is_finite() && a > 0.0 => ((480.0 * a).round() as u32).clamp(1, 16384),
            _ => 640,
        };
        Ok(Camera {
            eye: Vec3::ZERO,
            target: Vec3::NEG_Z,
            up: Vec3::Y,
            projection,
            width,
            height: 480,
            focus_distance: 1.0,
            ..Camera::default()
        })
    }

    /// The camera the user asked for (or the first, or one framing the scene).
    pub(super) fn spawn_camera(&mut self, world: &mut World, want: Option<&str>) -> Result<()> {
        let chosen = match want {
            Some(w) => {
                let by_name = self.cameras.iter().find(|(c, n, ..)| c == w || n == w);
                let by_index = || w.trim().parse::<usize>().ok().and_then(|i| self.cameras.get(i));
                Some(by_name.or_else(by_index).ok_or_else(|| {
                    let names: Vec<String> = self
                        .cameras
                        .iter()
                        .enumerate()
                        .map(|(i, (c, n, ..))| match (c.is_empty(), n.is_empty()) {
                            (false, _) => format!("{i} '{c}'"),
                            (true, false) => format!("{i} '{n}'"),
                            (true, true) => format!("{i} (unnamed)"),
                        })
                        .collect();
                    self.err(format!(
                        "no camera named or numbered '{w}' (cameras by index: {})",
                        if names.is_empty() { "none".into() } else { names.join(", ") }
                    ))
                })?)
            }
            None => self.cameras.first(),
        };
        match chosen {
            Some((_, _, c, e)) => {
                world.insert_one(*e, *c).map_err(|_| self.err("camera entity vanished".into()))?;
            }
            None => {
                let (lo, hi) = framed_box(&self.parts).unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
                let center = 0.5 * (lo + hi);
                let radius = (0.5 * (hi - lo).length()).max(1e-6);
                let fov: f32 = 40.0;
                let dist = 1.1 * radius / (0.5 * fov.to_radians()).sin();
                let cam = world.spawn((
                    Name("camera".into()),
                    Camera {
                        eye: center + dist * Vec3::new(0.5, 0.4, 1.0).normalize(),
                        target: center,
                        projection: Projection::Perspective { fov_y: fov },
                        width: 512,
                        height: 512,
                        focus_distance: dist,
                        ..Camera::default()
                    },
                ));
                // Framing the file's own frame: under the entity the file is placed in.
                if let Some(p) = self.placement.parent {
                    world
                        .insert_one(cam, prism_engine::components::Parent(p))
                        .map_err(|_| self.err("camera vanished".into()))?;
                }
            }
        }
        Ok(())
    }
}

/// A drawn primitive's world-space box, and whether all its vertices lie in one plane (a ground or a backdrop).
pub(super) struct PartBound {
    lo: Vec3,
    hi: Vec3,
    planar: bool,
}

impl PartBound {
    pub(super) fn of(positions: &[Vec3], m: &Mat4) -> Self {
        let world: Vec<Vec3> = positions.iter().map(|p| m.transform_point3(*p)).collect();
        let (lo, hi) = world.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
        let diag = (hi - lo).length();
        // The plane through the first vertex, the vertex farthest from it, and the vertex farthest from that line;
        // planar when every vertex is within 1e-4 of the part's size of it.
        let planar = world.first().is_some_and(|&a| {
            let far = |f: &dyn Fn(Vec3) -> f32| world.iter().copied().max_by(|x, y| f(*x).total_cmp(&f(*y)));
            let b = far(&|p| (p - a).length_squared()).unwrap_or(a);
            let c = far(&|p| (b - a).cross(p - a).length_squared()).unwrap_or(a);
            let n = (b - a).cross(c - a);
            diag == 0.0
                || (n.length() > 1e-12 * diag * diag
                    && world.iter().all(|&p| (p - a).dot(n.normalize()).abs() <= 1e-4 * diag))
        });
        PartBound { lo, hi, planar }
    }

    fn diagonal(&self) -> f32 {
        (self.hi - self.lo).length()
    }
}

/// The box the automatic camera frames: every part, except planar parts (grounds, backdrops) more than 3 times the
/// size of the box of the other parts, which would leave the model sub-pixel. `None` when nothing is drawn.
pub(super) fn framed_box(parts: &[PartBound]) -> Option<(Vec3, Vec3)> {
    let union = |it: &mut dyn Iterator<Item = &PartBound>| {
        it.fold(None, |acc: Option<(Vec3, Vec3)>, b| {
            if !b.lo.cmple(b.hi).all() {
                return acc;
            }
            Some(acc.map_or((b.lo, b.hi), |(l, h)| (l.min(b.lo), h.max(b.hi))))
        })
    };
    let solid = union(&mut parts.iter().filter(|b| !b.planar));
    let Some((lo, hi)) = solid else { return union(&mut parts.iter()) };
    let size = (hi - lo).length();
    union(&mut parts.iter().filter(|b| !b.planar || b.diagonal() <= 3.0 * size))
}
