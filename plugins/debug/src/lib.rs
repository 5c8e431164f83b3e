//! # debug
//!
//! Views of the geometry and of the accelerator instead of light transport.
//!
//! ```text
//! --integrator "debug(mode: heat, heat: nodes, max: None, signed: false, near: None, far: None, raw: false)"
//! ```
//!
//! ## Modes
//!
//! - `grid_cells`: the uniform grid's occupied cells as shaded cubes, coloured by how many primitives each holds (dark
//!   purple for one, through red and orange, to yellow for the fullest cell; logarithmic), cell edges darkened; nested
//!   grids show their finer cells. The 6.837 `-visualize_grid` view; needs `--accel grid` (otherwise an error says so).
//! - `heat` (the default): per pixel, the traversal work of the camera ray through the scene's accelerator, any of
//!   them: `heat: nodes` (BVH nodes tested, kd-tree nodes visited, grid cells visited), `prims` (primitive tests) or
//!   `total` (both). Black for 0 to white for `max`; without `max`, the 99th percentile of the image, printed on
//!   stderr. Give the same `max` to compare accelerators. One ray through each pixel centre, the image replaced each
//!   pass.
//! - `normals`: the shading normal (normal and bump maps included), `|n|` per channel (the 6.837 `-normals` view), or
//!   `(n + 1) / 2` with `signed: true`.
//! - `depth`: `(far - t) / (far - near)`, white near, black far (the 6.837 `-depth near far` view); `near` and `far`
//!   default to the nearest and farthest distance of the scene's bounds from the camera.
//!
//! ## Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `mode` | `heat` | `grid_cells`, `heat`, `normals` or `depth` |
//! | `heat` | `nodes` | `nodes`, `prims` or `total`: what a heat map counts |
//! | `max` | `None` | the count shown white (positive, finite); default the image's 99th percentile |
//! | `signed` | `false` | `normals`: `(n + 1) / 2` instead of `abs(n)` |
//! | `near`, `far` | `None` | `depth`: the distances shown white and black (finite; `far` must be greater than `near`) |
//! | `raw` | `false` | write the shown values themselves, for linear outputs such as the 6.837 `.tga`, instead of the linear radiance a PNG shows as those values |
//!
//! The colours are written so a PNG shows them as listed (sRGB values); with `raw: true` the values themselves are
//! written, so a linear `.tga` shows them as listed, as the course's images do. `grid_cells`, `normals` and `depth`
//! trace one camera ray per sample through the pixel pattern.
//!
//! ## What it is for
//!
//! Comparing accelerators (`prism render scene.txt --accel kdtree --integrator 'debug(mode: heat, max: 100)'`),
//! seeing where a grid is crowded, the 6.837 course's debug views, and checking normals and normal maps.
//!
//! ## Failure modes
//!
//! - `grid_cells` without a uniform grid is an error naming the accelerator in use.
//! - A non-positive or non-finite `max`, non-finite `near` or `far`, or `far` not greater than `near`, are one-line
//!   errors naming the parameter.

use glam::{Vec2, Vec3, Vec3A};
use prism_core::accel::TraversalWork;
use prism_core::error::{PrismError, Result};
use prism_core::geometry::Ray;
use prism_core::integrator::{Integrator, PassInfo, PassOutput, PerPixel, PixelIntegrator};
use prism_core::io::srgb_to_linear;
use prism_core::sampling::Sampler;
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;
use prism_engine::{App, Plugin};
use rayon::prelude::*;
use serde::Deserialize;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(Deserialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DebugMode {
    GridCells,
    #[default]
    Heat,
    Normals,
    Depth,
}

/// What a heat map counts.
#[derive(Deserialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum HeatCount {
    #[default]
    Nodes,
    Prims,
    Total,
}

impl HeatCount {
    /// The count of one ray's work.
    pub fn of(self, work: TraversalWork) -> f32 {
        match self {
            HeatCount::Nodes => work.nodes as f32,
            HeatCount::Prims => work.prims as f32,
            HeatCount::Total => (work.nodes + work.prims) as f32,
        }
    }
}

#[derive(Deserialize, Debug, Clone, Copy, Default)]
#[serde(deny_unknown_fields, default)]
pub struct DebugParams {
    pub mode: DebugMode,
    /// `heat`: what to count.
    pub heat: HeatCount,
    /// `heat`: the count shown white (default: the image's 99th percentile).
    pub max: Option<f32>,
    /// `normals`: `(n + 1) / 2` instead of `|n|`.
    pub signed: bool,
    /// `depth`: distance shown white.
    pub near: Option<f32>,
    /// `depth`: distance shown black.
    pub far: Option<f32>,
    /// Write the shown values themselves into the film (for linear outputs such as the 6.837 `.tga`), instead of
    /// the linear radiance a PNG shows as those values.
    pub raw: bool,
}

pub struct DebugPlugin;

impl Plugin for DebugPlugin {
    fn name(&self) -> &str {
        "debug"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "debug",
            Box::new(|cfg| {
                let p: DebugParams = cfg.parse_params()?;
                if let Some(m) = p.max
                    && !(m.is_finite() && m > 0.0)
                {
                    return Err(PrismError::invalid(format!("debug: max must be positive, got {m}")));
                }
                for (name, v) in [("near", p.near), ("far", p.far)] {
                    if let Some(v) = v
                        && !v.is_finite()
                    {
                        return Err(PrismError::invalid(format!("debug: {name} must be a finite distance, got {v}")));
                    }
                }
                Ok(match p.mode {
                    DebugMode::Heat => Box::new(HeatMap { params: p, announced: false }),
                    _ => Box::new(PerPixel::new(DebugView { params: p, near: 0.0, far: 1.0, max_count: 1 })),
                })
            }),
        );
    }
}

/// Colour ramp black - purple - red - orange - yellow - white (inferno-like), `t` in [0, 1], as sRGB (the heat
/// maps' colours; `prism report` colours its own heat maps with it).
pub fn ramp(t: f32) -> Vec3 {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [0.26, 0.04, 0.41],
        [0.58, 0.15, 0.40],
        [0.87, 0.32, 0.23],
        [0.99, 0.65, 0.04],
        [0.99, 1.0, 0.65],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    Vec3::from(STOPS[i]).lerp(Vec3::from(STOPS[i + 1]), f)
}

/// A colour given in sRGB, as the linear radiance that a PNG shows as that colour.
fn srgb(c: Vec3) -> Vec3 {
    Vec3::new(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z))
}

/// `grid_cells`, `normals` and `depth`: per-sample views.
struct DebugView {
    params: DebugParams,
    near: f32,
    far: f32,
    /// Largest primitive count of a grid cell.
    max_count: u32,
}

impl PixelIntegrator for DebugView {
    fn prepare(&mut self, scene: &Scene, _settings: &RenderSettings) -> Result<()> {
        match self.params.mode {
            DebugMode::GridCells => {
                let grid = scene.accel.as_grid().ok_or_else(|| {
                    PrismError::invalid(format!(
                        "debug(mode: grid_cells) shows a uniform grid: render with --accel grid (the scene uses {})",
                        scene.accel.stats().kind
                    ))
                })?;
                self.max_count = grid.occupied_cells().iter().map(|c| c.count).max().unwrap_or(1);
            }
            DebugMode::Depth => {
                let b = scene.prims.bounds;
                let eye = scene.camera.eye();
                let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
                if !b.is_empty() {
                    for i in 0..8 {
                        let c = Vec3A::new(
                            if i & 1 == 0 { b.min.x } else { b.max.x },
                            if i & 2 == 0 { b.min.y } else { b.max.y },
                            if i & 4 == 0 { b.min.z } else { b.max.z },
                        );
                        hi = hi.max((c - eye).length());
                    }
                    let inside = b.min.cmple(eye).all() && eye.cmple(b.max).all();
                    lo = if inside { 0.0 } else { (eye.clamp(b.min, b.max) - eye).length() };
                }
                self.near = self.params.near.unwrap_or(if lo.is_finite() { lo } else { 0.0 });
                self.far = self.params.far.unwrap_or(if hi > self.near { hi } else { self.near + 1.0 });
                if self.far.is_nan() || self.far <= self.near {
                    return Err(PrismError::invalid(format!(
                        "debug(mode: depth): far ({}) must be greater than near ({})",
                        self.far, self.near
                    )));
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn radiance(&self, scene: &Scene, ray: Ray, _sampler: &mut Sampler) -> Vec3 {
        match self.params.mode {
            DebugMode::GridCells => self.grid_cell(scene, &ray),
            DebugMode::Normals => scene.trace(&ray).map_or(Vec3::ZERO, |s| {
                // The BSDF's shading normal (normal and bump maps included), on the side of the surface's normal.
                let n = scene.bsdf(&s, -ray.dir).map_or(s.ns, |b| {
                    let n = b.normal();
                    if n.dot(s.ng) < 0.0 { -n } else { n }
                });
                let n = Vec3::from(n);
                self.shown(if self.params.signed { 0.5 * (n + 1.0) } else { n.abs() })
            }),
            DebugMode::Depth => scene.intersect(&ray).map_or(Vec3::ZERO, |h| {
                self.shown(Vec3::splat(((self.far - h.t) / (self.far - self.near)).clamp(0.0, 1.0)))
            }),
            DebugMode::Heat => Vec3::ZERO,
        }
    }
}

impl DebugView {
    /// The film value that an output shows as `c`: sRGB-decoded for PNG, or `c` itself with `raw`.
    fn shown(&self, c: Vec3) -> Vec3 {
        if self.params.raw { c } else { srgb(c) }
    }

    fn grid_cell(&self, scene: &Scene, ray: &Ray) -> Vec3 {
        let Some(grid) = scene.accel.as_grid() else {
            return Vec3::ZERO;
        };
        let Some(hit) = grid.first_occupied_cell(ray) else {
            return Vec3::ZERO;
        };
        let count = hit.cell.count.max(1) as f32;
        let t = if self.max_count > 1 { count.ln() / (self.max_count as f32).ln() } else { 0.5 };
        let base = ramp(0.25 + 0.75 * t);
        // Shade the face: a fixed key light plus a headlight, so the three visible faces differ.
        let n = hit.normal;
        let key = Vec3A::new(0.4, 0.8, 0.45).normalize();
        let shade = 0.3 + 0.4 * n.dot(key).abs() + 0.3 * n.dot(-ray.dir).abs();
        // Darken a thin band along the face's edges.
        let b = hit.cell.bounds;
        let p = ray.at(hit.t);
        let size = b.diagonal();
        let mut edge = false;
        for a in 0..3 {
            if n[a] != 0.0 {
                continue;
            }
            let f = ((p[a] - b.min[a]) / size[a].max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            edge |= !(0.04..=0.96).contains(&f);
        }
        self.shown(base * shade * if edge { 0.45 } else { 1.0 })
    }
}

/// The traversal work of the camera ray through each pixel centre of a `w x h` image of the scene's camera, one
/// row per image row (`None` for rows skipped because `cancel` was set).
pub fn heat_rows(scene: &Scene, w: u32, h: u32, cancel: &AtomicBool) -> Vec<Option<Vec<TraversalWork>>> {
    (0..h)
        .into_par_iter()
        .map(|y| {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let row = (0..w)
                .map(|x| {
                    let ray = scene.camera.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                    let mut work = TraversalWork::default();
                    scene.accel.intersect_counted(&scene.prims, &ray, &mut work);
                    work
                })
                .collect();
            Some(row)
        })
        .collect()
}

/// `heat`: the traversal work of the camera ray through each pixel centre.
struct HeatMap {
    params: DebugParams,
    announced: bool,
}

impl Integrator for HeatMap {
    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput {
        let (w, h) = (pass.settings.width, pass.settings.height);
        let counts: Vec<Option<Vec<f32>>> = heat_rows(scene, w, h, cancel)
            .into_iter()
            .map(|row| row.map(|r| r.iter().map(|&work| self.params.heat.of(work)).collect()))
            .collect();
        let complete = counts.iter().all(Option::is_some);
        let counts: Vec<f32> = counts.into_iter().flat_map(|r| r.unwrap_or_else(|| vec![0.0; w as usize])).collect();
        let max = self.params.max.unwrap_or_else(|| {
            let mut sorted: Vec<f32> = counts.iter().copied().filter(|&c| c > 0.0).collect();
            sorted.sort_by(f32::total_cmp);
            sorted.get((sorted.len() as f32 * 0.99) as usize).or(sorted.last()).copied().unwrap_or(1.0).max(1.0)
        });
        if !self.announced && self.params.max.is_none() {
            self.announced = true;
            let mean = counts.iter().sum::<f32>() / counts.len().max(1) as f32;
            let what = match self.params.heat {
                HeatCount::Nodes => "nodes or cells visited",
                HeatCount::Prims => "primitives tested",
                HeatCount::Total => "nodes/cells and primitives",
            };
            eprintln!(
                "debug heat ({}): {what}, mean {mean:.1} per ray; white = {max} (99th percentile; debug(max: ...) fixes \
                 the scale)",
                scene.accel.stats().kind
            );
        }
        let image = counts.iter().map(|&c| if self.params.raw { ramp(c / max) } else { srgb(ramp(c / max)) }).collect();
        PassOutput::Estimate { image, complete }
    }
}
