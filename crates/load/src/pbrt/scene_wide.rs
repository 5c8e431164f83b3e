//! pbrt's scene-wide directives (before `WorldBegin`) as Prism's camera and render settings:
//!
//! | pbrt | Prism |
//! |---|---|
//! | `Camera "perspective"` `fov` (of the shorter image axis, default 90) | `fov` (vertical): `2 atan(tan(fov/2) H/W)` for portrait images |
//! | `lensradius`, `focaldistance` | `aperture_radius`, `focus_distance` (camera-space units times the transform's scale) |
//! | `Camera "orthographic"` | `orthographic: 2` (the shorter axis spans [-1, 1] camera units) |
//! | camera transform (`LookAt` ...: pbrt's screen x is camera +x, `up x view` for a `LookAt`) | eye, target, up, and `mirror: true` when pbrt's image-right is Prism's image-left |
//! | `Film` `xresolution`, `yresolution` (v3: 640 x 480, v4: 1280 x 720) | `size` |
//! | `cropwindow [x0 x1 y0 y1]`, `pixelbounds` | `crop` (the window rounded to pbrt's pixel bounds), `size` its pixels |
//! | v3 `scale`, v4 `iso` x `exposuretime` / 100 | `exposure: log2(...)` (PNG only; EXR stays linear) |
//! | `Sampler "*" pixelsamples` (16) | `spp` |
//! | `Integrator "sppm"` `numiterations` (64), `radius` (1), `photonsperiteration` (-1: pixel count), `maxdepth` (5) | `ppm(radius, photons, eye_depth: maxdepth, photon_depth: maxdepth)` (pbrt limits eye and photon paths separately), `spp: numiterations` |
//! | `"path"`, `"volpath"`, ... `maxdepth` (5) | `envlight(max_depth: maxdepth + 1)` (pbrt counts bounces, Prism path segments) |
//! | `"bdpt"`, `"mlt"` `maxdepth` (5) | `vcm(mode: bdpt, max_depth: maxdepth + 1)`, `vcm(mode: vcm, ...)` (a note); `envlight` for a lens or orthographic camera, which `vcm` cannot connect to |
//! | `"directlighting"` | `envlight(max_depth: 2)` |
//! | `"whitted"` `maxdepth` | `phong(max_depth: maxdepth)` |
//! | `PixelFilter` `box`, `gaussian` (`sigma`), `triangle` (`xradius`) | `Box(radius)`, `Gaussian(sigma)`, `Tent(radius)`; others: box |

use super::Version;
use super::convert::{Converter, num, tuple3};
use super::params::Params;
use glam::{DMat4, DVec3};
use prism_core::error::{PrismError, Result, SourcePos};

#[derive(Clone, Debug, Default)]
pub struct SceneWide {
    pub camera_from_world: Option<DMat4>,
    ortho: bool,
    fov: f64,
    lens_radius: f64,
    /// The path tracer a bidirectional integrator falls back to for a camera that is not a pinhole.
    path_fallback: Option<String>,
    focal_distance: f64,
    resolution: Option<(u32, u32)>,
    /// pbrt's crop window `[x0, x1, y0, y1]`.
    crop: Option<[f64; 4]>,
    pixel_bounds: Option<[i64; 4]>,
    exposure: Option<f64>,
    spp: Option<u32>,
    integrator: Option<(String, Option<u32>)>,
    filter: Option<String>,
    version: Option<Version>,
}

fn bad(pos: &SourcePos, m: String) -> PrismError {
    PrismError::Parse { pos: pos.clone(), message: m }
}

impl SceneWide {
    pub fn directive(
        &mut self,
        c: &mut Converter,
        name: &str,
        ty: &str,
        p: &Params,
        pos: &SourcePos,
        ctm: DMat4,
    ) -> Result<()> {
        self.version = Some(c.version);
        match name {
            "Camera" => {
                if ctm.determinant() == 0.0 || !ctm.is_finite() {
                    return Err(bad(pos, "Camera: the current transform is singular".into()));
                }
                self.camera_from_world = Some(ctm);
                match ty {
                    "perspective" => {}
                    "orthographic" => self.ortho = true,
                    other => c.warn(format!("Camera \"{other}\" is approximated by a perspective camera")),
                }
                self.fov = p.float("fov", 90.0)?;
                if !(self.fov > 0.0 && self.fov < 180.0) {
                    return Err(bad(
                        &p.pos_of("fov").unwrap_or(pos.clone()),
                        format!("Camera: fov must be in (0, 180), got {}", self.fov),
                    ));
                }
                self.lens_radius = p.float("lensradius", 0.0)?;
                self.focal_distance = p.float("focaldistance", 1e6)?;
                if self.lens_radius < 0.0 || self.focal_distance <= 0.0 {
                    return Err(bad(pos, "Camera: lensradius must be >= 0 and focaldistance > 0".into()));
                }
                for unsupported in ["screenwindow", "frameaspectratio", "shutteropen", "shutterclose"] {
                    if p.has(unsupported) {
                        c.warn(format!("Camera: \"{unsupported}\" is ignored"));
                    }
                }
            }
            "Film" => {
                let (dx, dy) = if c.version == Version::V3 { (640, 480) } else { (1280, 720) };
                let (x, y) = (p.int("xresolution", dx)?, p.int("yresolution", dy)?);
                if !(1..=65536).contains(&x) || !(1..=65536).contains(&y) {
                    return Err(bad(pos, format!("Film: resolution {x} x {y} is out of range")));
                }
                self.resolution = Some((x as u32, y as u32));
                if let Some(w) = p.floats("cropwindow")? {
                    let ok = w.len() == 4 && w[0] < w[1] && w[2] < w[3] && w.iter().all(|v| (0.0..=1.0).contains(v));
                    if !ok {
                        return Err(bad(
                            &p.pos_of("cropwindow").unwrap_or(pos.clone()),
                            format!(
                                "Film: cropwindow must be [x0 x1 y0 y1] in [0, 1] with x0 < x1, y0 < y1, got {w:?}"
                            ),
                        ));
                    }
                    self.crop = Some([w[0], w[1], w[2], w[3]]);
                }
                if let Some(b) = p.floats("pixelbounds")? {
                    if b.len() != 4 {
                        return Err(bad(pos, "Film: pixelbounds needs 4 integers".into()));
                    }
                    self.pixel_bounds = Some([b[0] as i64, b[1] as i64, b[2] as i64, b[3] as i64]);
                }
                let scale = p.float("scale", 1.0)?;
                let ratio = p.float("exposuretime", 1.0)? * p.float("iso", 100.0)? / 100.0;
                let e = scale * ratio;
                if e > 0.0 && e != 1.0 {
                    self.exposure = Some(e.log2());
                }
                if let Some(f) = p.string("filename")? {
                    c.warn(format!("Film: the output name \"{f}\" is not used (use -o)"));
                }
                for ignored in ["diagonal", "maxcomponentvalue", "whitebalance", "sensor", "savefp16", "gamma"] {
                    p.has(ignored);
                }
            }
            "Sampler" => {
                let n = p.int("pixelsamples", 16)?;
                if n < 1 {
                    return Err(bad(pos, format!("Sampler: pixelsamples must be positive, got {n}")));
                }
                self.spp = Some(n.min(1 << 24) as u32);
                for ignored in ["seed", "dimensions", "jitter", "xsamples", "ysamples", "randomization"] {
                    p.has(ignored);
                }
            }
            "Integrator" | "SurfaceIntegrator" => {
                let depth = p.int("maxdepth", 5)?;
                if depth < 0 {
                    return Err(bad(pos, format!("Integrator: maxdepth must be >= 0, got {depth}")));
                }
                let segments = (depth + 1).min(1 << 20);
                self.integrator = Some(match ty {
                    "sppm" => {
                        let iters = p.int("numiterations", 64)?;
                        let radius = p.float("radius", 1.0)?;
                        let photons = p.int("photonsperiteration", -1)?;
                        if iters < 1 || radius.is_nan() || radius <= 0.0 {
                            return Err(bad(
                                pos,
                                "Integrator \"sppm\": numiterations must be >= 1 and radius > 0".into(),
                            ));
                        }
                        let photons = if photons > 0 { format!(", photons: {photons}") } else { String::new() };
                        p.has("imagewritefrequency");
                        p.has("seed");
                        (
                            // pbrt's SPPM follows camera paths and photon paths `maxdepth` segments each.
                            format!(
                                "ppm(radius: {}{photons}, eye_depth: {depth}, photon_depth: {depth})",
                                num(radius),
                                depth = depth.clamp(1, 1 << 20)
                            ),
                            Some(iters.min(1 << 24) as u32),
                        )
                    }
                    "path" | "volpath" | "bdpt" | "mlt" | "lightpath" | "randomwalk" | "simplepath"
                    | "simplevolpath" => {
                        let bidirectional = match ty {
                            "bdpt" => Some("vcm(mode: bdpt"),
                            "mlt" => Some("vcm(mode: vcm"),
                            _ => None,
                        };
                        if let Some(spec) = bidirectional {
                            c.warn(format!(
                                "Integrator \"{ty}\" renders with {spec}) (envlight where the camera is orthographic)"
                            ));
                        } else if ty != "path" && ty != "volpath" && ty != "simplepath" {
                            c.warn(format!(
                                "Integrator \"{ty}\" is approximated by unidirectional path tracing (envlight)"
                            ));
                        }
                        for ignored in [
                            "rrthreshold",
                            "lightsampler",
                            "regularize",
                            "visualizestrategies",
                            "visualizeweights",
                            "bootstrapsamples",
                            "chains",
                            "mutationsperpixel",
                            "largestepprobability",
                            "sigma",
                        ] {
                            p.has(ignored);
                        }
                        self.path_fallback = bidirectional.map(|_| format!("envlight(max_depth: {segments})"));
                        match bidirectional {
                            Some(spec) => (format!("{spec}, max_depth: {segments})"), None),
                            None => (format!("envlight(max_depth: {segments})"), None),
                        }
                    }
                    "directlighting" => {
                        c.warn("Integrator \"directlighting\" is approximated by envlight(max_depth: 2)");
                        p.has("strategy");
                        ("envlight(max_depth: 2)".into(), None)
                    }
                    "whitted" => (format!("phong(max_depth: {})", depth.clamp(1, 1 << 20)), None),
                    "ambientocclusion" | "aov" => {
                        c.warn(format!("Integrator \"{ty}\" is not supported; path tracing instead"));
                        ("envlight".into(), None)
                    }
                    other => return Err(bad(pos, format!("unknown integrator \"{other}\""))),
                });
            }
            "PixelFilter" => {
                let f = match ty {
                    "box" => {
                        let r = p.float("xradius", 0.5)?.max(p.float("yradius", 0.5)?);
                        format!("Box(radius: {})", num(r))
                    }
                    "gaussian" => {
                        p.has("xradius");
                        p.has("yradius");
                        p.has("alpha");
                        format!("Gaussian(sigma: {})", num(p.float("sigma", 0.5)?))
                    }
                    "triangle" => {
                        let r = p.float("xradius", 2.0)?.max(p.float("yradius", 2.0)?);
                        format!("Tent(radius: {})", num(r))
                    }
                    other => {
                        c.warn(format!("PixelFilter \"{other}\" is approximated by a box filter"));
                        for ignored in ["xradius", "yradius", "B", "C", "tau"] {
                            p.has(ignored);
                        }
                        "Box(radius: 0.5)".into()
                    }
                };
                self.filter = Some(f);
            }
            "Accelerator" | "ColorSpace" | "Option" => {
                for q in &p.list {
                    p.has(&q.name);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The `camera:` and `render:` fields of the RON scene.
    pub fn ron(&self) -> String {
        let v3 = self.version == Some(Version::V3) || self.version.is_none();
        let (w, h) = self.resolution.unwrap_or(if v3 { (640, 480) } else { (1280, 720) });
        let mut out = String::new();
        let cfw = self.camera_from_world.unwrap_or(DMat4::IDENTITY);
        let wfc = cfw.inverse();
        let eye = wfc.transform_point3(DVec3::ZERO);
        let fwd = wfc.transform_vector3(DVec3::Z);
        let up = wfc.transform_vector3(DVec3::Y);
        let right = wfc.transform_vector3(DVec3::X);
        let mirror = right.dot(fwd.cross(up)) < 0.0;
        // The window in pixels, as pbrt rounds it (ceil of the fractions), then back to fractions.
        let (mut px0, mut py0, mut px1, mut py1) = (0i64, 0i64, w as i64, h as i64);
        if let Some([x0, x1, y0, y1]) = self.crop {
            px0 = (w as f64 * x0).ceil() as i64;
            px1 = (w as f64 * x1).ceil() as i64;
            py0 = (h as f64 * y0).ceil() as i64;
            py1 = (h as f64 * y1).ceil() as i64;
        }
        if let Some([x0, x1, y0, y1]) = self.pixel_bounds {
            px0 = px0.max(x0);
            px1 = px1.min(x1);
            py0 = py0.max(y0);
            py1 = py1.min(y1);
        }
        let (px1, py1) = (px1.max(px0 + 1).min(w as i64), py1.max(py0 + 1).min(h as i64));
        let (px0, py0) = (px0.clamp(0, px1 - 1), py0.clamp(0, py1 - 1));
        let cropped = (px0, py0, px1, py1) != (0, 0, w as i64, h as i64);
        let size = ((px1 - px0) as u32, (py1 - py0) as u32);
        let target = eye + fwd.normalize_or_zero();
        let _ = write!(
            out,
            "    camera: (eye: {}, target: {}, up: {}, size: ({}, {})",
            tuple3(eye.to_array()),
            tuple3(target.to_array()),
            tuple3(up.normalize_or_zero().to_array()),
            size.0,
            size.1
        );
        let short_scale = if w >= h { 1.0 } else { h as f64 / w as f64 };
        if self.ortho {
            let _ = write!(out, ", orthographic: Some({})", num(2.0 * short_scale * up.length()));
        } else {
            let half = (0.5 * self.fov.to_radians()).tan() * short_scale;
            let _ = write!(out, ", fov: {}", num(2.0 * half.atan().to_degrees()));
        }
        if mirror {
            out.push_str(", mirror: true");
        }
        if cropped {
            let f = |a: i64, n: u32| num(a as f64 / n as f64);
            let _ = write!(out, ", crop: Some(({}, {}, {}, {}))", f(px0, w), f(py0, h), f(px1, w), f(py1, h));
        }
        if self.lens_radius > 0.0 {
            let _ = write!(
                out,
                ", aperture_radius: {}, focus_distance: Some({})",
                num(self.lens_radius * right.length()),
                num(self.focal_distance * fwd.length())
            );
        }
        out.push_str("),\n    render: (");
        let (mut integrator, iterations) =
            self.integrator.clone().unwrap_or_else(|| ("envlight(max_depth: 6)".into(), None));
        // `vcm` connects light paths to the eye or a lens point: orthographic cameras are path traced.
        if let Some(fallback) = &self.path_fallback
            && self.ortho
        {
            integrator = fallback.clone();
        }
        let _ = write!(out, "integrator: {integrator}, spp: {}", iterations.or(self.spp).unwrap_or(16));
        if let Some(f) = &self.filter {
            let _ = write!(out, ", filter: {f}");
        }
        if let Some(e) = self.exposure {
            let _ = write!(out, ", exposure: {}", num(e));
        }
        out.push_str("),\n");
        out
    }
}

use std::fmt::Write as _;
