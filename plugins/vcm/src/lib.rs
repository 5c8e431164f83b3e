//! # vcm
//!
//! Bidirectional methods in one design: light tracing, bidirectional path tracing, bidirectional photon mapping and
//! vertex connection and merging (Georgiev et al. 2012, "Light Transport Simulation with Vertex Connection and
//! Merging"; Hachisuka et al. 2012, "A Path Space Extension for Robust Light Transport Simulation"), with the
//! recursive MIS quantities of the VCM technical report, so a path's weight costs O(1) per vertex whatever its
//! length.
//!
//! ```text
//! --integrator "vcm(mode: vcm, max_depth: -1, radius: None, radius_pixels: 2, alpha: 0.6667, light_paths: None, heuristic: balance)"
//! ```
//!
//! ## What it computes
//!
//! Each iteration is one sample per pixel of the render's budget (`--spp 64` is 64 iterations):
//!
//! 1. **Light pass**: `light_paths` paths from the lights, chosen by power and emitted through each light's
//!    `sample_le` (area lights including textured and curved emitters, point, spot and directional lights, and the
//!    environment through its quad-tree), scattered with importance-transport sampling and Russian roulette on the
//!    throughput drop. Their vertices with a smooth lobe are kept, and each is connected to the camera (light
//!    tracing): a splat on every pixel whose filter covers its projection.
//! 2. **Merging grid** (modes `bpm` and `vcm`): the light vertices in `prism_core`'s point hash grid (the one `ppm`
//!    gathers photons from), cells twice the iteration's radius.
//! 3. **Camera pass**: one path per pixel; at each vertex with a smooth lobe, next-event estimation, a connection to
//!    every vertex of one light path (pixel `i` takes path `i mod light_paths`), and merging with the light vertices
//!    within the radius; emission the path hits is weighted against all of these.
//!
//! Every strategy's contribution is weighted by the balance (or power) heuristic against every other strategy of the
//! mode that could have built the same path, so the image is unbiased for `light` and `bdpt` and consistent for `bpm`
//! and `vcm` (merging's bias shrinks with the radius, which iteration `k` (from 0) sets to
//! `r_k = radius (k + 1)^((alpha - 1) / 2)`: with alpha 2/3 the merged part's error falls at the optimal
//! `N^(-2/3)` rate, Kaplanyan & Dachsbacher 2013, Knaus & Zwicker 2011).
//!
//! | mode | strategies | best at |
//! |---|---|---|
//! | `light` | light tracing, plus emission seen directly or through mirrors and glass | light entering through a small gap; caustics seen directly |
//! | `bdpt` | all connections (`s`, `t` >= 0): emission hits, next-event estimation, light tracing, vertex pairs | glossy interiors, indirect light from small lights |
//! | `bpm` | merging at every camera vertex, plus emission along delta chains | specular-diffuse-specular paths (caustics seen in a mirror) |
//! | `vcm` | both | scenes with all of these |
//!
//! ## Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `mode` | `vcm` | `light`, `bdpt`, `bpm` or `vcm` (above) |
//! | `max_depth` | -1 | the longest path in segments, counted as `envlight` counts them (-1 unlimited; Russian roulette ends paths, and 256 segments bound loops of delta lobes) |
//! | `radius` | `None` | the merging radius at the first iteration, world units; by default `radius_pixels` pixel footprints at the median distance of the surfaces the camera sees |
//! | `radius_pixels` | 2 | the default radius in pixel footprints (positive) |
//! | `alpha` | 2/3 | radius reduction, in `(0, 1]`: 1 keeps the radius |
//! | `light_paths` | `None` | light paths per iteration; default the image's pixel count; 1 to 2^21 |
//! | `heuristic` | `balance` | `balance` or `power` (exponent 2) |
//!
//! ## Guarantees
//!
//! - **MIS weights of one path sum to 1**: every strategy's densities come from the same functions wherever they
//!   are evaluated (area conversions with geometric normals, lights' densities from `pdf_le` and the light
//!   sampler's choice probability, each BSDF's forward `pdf` and reverse `pdf_rev`). `path_weights::path_weights` computes
//!   every strategy's weight of an explicit path with the renderer's functions; on random paths in random scenes
//!   they sum to 1 and equal the heuristic written out as products of densities to 2e-7 (`tests/vcm_mis.rs`).
//! - **Deterministic** whatever the thread count: light path `j` of iteration `k` draws its numbers from (seed, k,
//!   j), pixel `i`'s camera path from (seed, i, k); light paths are traced in fixed chunks and kept in chunk order;
//!   every contribution to a pixel (its camera path's and each light-tracing splat) is converted to fixed point on
//!   its own and summed exactly, so the order splats arrive in changes nothing.
//! - **Resumable and shardable** by passes like `envlight`: the state of an iteration is its index alone (the radius
//!   follows from it), so `--resume` and `--shard K/N` + `prism merge` give the same bytes as one render.
//!
//! ## Measured
//!
//! Equal-time errors of every integrator on a spot-light caustic through glass, a glossy interior, Bitterli's
//! veach-bidir, a room lit through a slit and the two Mitsuba 3 boxes, with the rule of thumb they give: the
//! [plugins overview](overview.md#which-integrator-for-which-scene); the pictures, error maps and error-against-time
//! charts: the [report](../report/index.html) (its stability section's "Bidirectional methods" cases). Throughput
//! and thread scaling: the README's headline numbers. The status line counts light vertices and connections.
//!
//! ## Failure modes
//!
//! - **An orthographic camera**: a one-line error (light tracing connects light vertices to the eye, or to a point
//!   of a thin lens, which parallel rays do not have); `envlight` and `ppm` render it. Thin lenses work: each light
//!   vertex is connected to a lens point of its own, and the camera's density of a point is its ray's density per
//!   unit film area whichever lens point the ray leaves from.
//! - **Radius far too small**: merging is noisy but its MIS weight falls with the radius, so connections take over;
//!   the image mean stays right. **Far too large**: merged light blurred at first, shrinking with the radius.
//! - **Walls thinner than the radius** do not leak: a light vertex is merged only with camera vertices on surfaces
//!   facing the same way (the wall's far face faces the other way), and the BSDF refuses light from the other side
//!   of an opaque surface; a rough dielectric merges light it transmits.
//! - **A light of zero power**: a warning, nothing emitted; emission seen directly still appears.
//! - **Point lights with non-physical attenuation**: emitted with physical inverse-square falloff (a warning).
//! - `--adaptive` has no effect (a warning): light tracing's splats land on every pixel.
//! - Bad parameters (`alpha` outside `(0, 1]`, `radius` or `radius_pixels` not positive, `light_paths` 0 or above
//!   2^21, `max_depth` 0 or below -1, unknown values or fields) are one-line errors naming the parameter.
//!
//! ## In the source
//!
//! `params.rs` (the parameters and their checks), `mis.rs` (the MIS quantities and the lights' densities),
//! `weights.rs` (each strategy's weight where a path is completed), `path_weights.rs` (the weights of an explicit
//! path),
//! `light_paths.rs` (the light pass and light tracing), `camera_paths.rs` (the camera pass: emission, next-event
//! estimation, connections, merging), `lib.rs` (the iteration, the radius schedule, and the film tiles).

mod camera_paths;
mod light_paths;
mod mis;
mod params;
pub mod path_weights;
mod weights;

pub use params::{DEPTH_CAP, Heuristic, MAX_LIGHT_PATHS, VcmMode, VcmParams};

use camera_paths::CameraPass;
use glam::{Vec2, Vec3};
use light_paths::{ChunkOut, LightPass, MergeVertex};
use mis::Mis;
use prism_core::accel::PointHashGrid;
use prism_core::error::{PrismError, Result};
use prism_core::film::FixedRgb;
use prism_core::integrator::{Integrator, PassInfo, PassOutput, TileSamples, tiles};
use prism_core::lights::{EnvStrategy, LightSampler, LightSource};
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;
use prism_engine::{App, Plugin};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Registers the `vcm` integrator.
pub struct VcmPlugin;

impl Plugin for VcmPlugin {
    fn name(&self) -> &str {
        "vcm"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "vcm",
            Box::new(|cfg| {
                let params: VcmParams = cfg.parse_params()?;
                params.validate()?;
                Ok(Box::new(Vcm::new(params)))
            }),
        );
    }
}

/// The bidirectional integrator's state between passes (buffers reused across iterations; no state a resume needs).
pub struct Vcm {
    params: VcmParams,
    lights: Option<LightSampler>,
    light_paths: u64,
    /// The merging radius of iteration 0.
    radius: f32,
    chunks: Vec<ChunkOut>,
    merge: Vec<Vec<MergeVertex>>,
    grid: PointHashGrid<MergeVertex>,
    sums: Vec<FixedRgb>,
    /// Connections tried per row of the last iteration (summed into `connections`).
    row_connections: Vec<u64>,
    iterations: u64,
    /// Light-path vertices stored for connections or merging, over the render.
    light_vertices: u64,
    /// Camera-vertex to light-vertex connections tried (shadow ray or not), over the render.
    connections: u64,
}

/// Pixel-centre rays per side of the grid whose median hit distance sets the default radius.
const RADIUS_PROBES: u32 = 64;

impl Vcm {
    /// The integrator with `params` (checked by the factory).
    pub fn new(params: VcmParams) -> Self {
        Vcm {
            params,
            lights: None,
            light_paths: 0,
            radius: 0.0,
            chunks: Vec::new(),
            merge: Vec::new(),
            grid: PointHashGrid::default(),
            sums: Vec::new(),
            row_connections: Vec::new(),
            iterations: 0,
            light_vertices: 0,
            connections: 0,
        }
    }

    /// The merging radius of iteration 0 (after `prepare`).
    pub fn initial_radius(&self) -> f32 {
        self.radius
    }

    /// Light paths per iteration (after `prepare`).
    pub fn light_paths(&self) -> u64 {
        self.light_paths
    }

    /// The merging radius of iteration `k`: `radius (k + 1)^((alpha - 1) / 2)`.
    pub fn radius_at(&self, k: u64) -> f32 {
        self.radius * ((k + 1) as f64).powf((self.params.alpha as f64 - 1.0) / 2.0) as f32
    }

    /// The default radius: `radius_pixels` pixel footprints at the median distance of the surfaces seen through a
    /// grid of pixel centres (a thousandth of the scene's radius if the camera sees none).
    fn default_radius(&self, scene: &Scene, settings: &RenderSettings) -> f32 {
        let (w, h) = (settings.width, settings.height);
        let (gx, gy) = (w.min(RADIUS_PROBES), h.min(RADIUS_PROBES));
        let mut dist: Vec<f32> = (0..gx * gy)
            .into_par_iter()
            .filter_map(|i| {
                let (x, y) = (i % gx, i / gx);
                let film = Vec2::new((x as f32 + 0.5) * w as f32 / gx as f32, (y as f32 + 0.5) * h as f32 / gy as f32);
                let ray = scene.camera.generate_ray(film);
                scene.trace(&ray).map(|s| (s.p - ray.origin).length()).filter(|d| d.is_finite() && *d > 0.0)
            })
            .collect();
        if dist.is_empty() {
            return 1e-3 * scene.lights.sphere.radius;
        }
        let mid = dist.len() / 2;
        let (_, median, _) = dist.select_nth_unstable_by(mid, f32::total_cmp);
        self.params.radius_pixels * scene.camera.pixel_footprint(*median)
    }

    /// One iteration's contributions added to `self.sums`; false (sums unchanged) if cancelled.
    fn iterate(&mut self, scene: &Scene, settings: &RenderSettings, k: u64, cancel: &AtomicBool) -> bool {
        let lights = self.lights.as_ref().expect("prepared");
        let p = &self.params;
        let radius = self.radius_at(k);
        let n_light = self.light_paths;
        let mis = Mis::new(p.heuristic, radius, n_light as f32, p.connects(), p.merges());
        let light_only = p.mode == VcmMode::Light;
        let pass = LightPass {
            scene,
            lights,
            sampler: settings.sampler,
            filter: settings.filter,
            seed: settings.seed,
            iteration: k,
            paths: n_light,
            max_segments: p.segments(),
            mis,
            keep_vertices: p.connects(),
            keep_merge: p.merges(),
            to_camera: p.connects() || light_only,
            light_only,
        };
        if !pass.trace(&mut self.chunks, cancel) {
            return false;
        }
        let stored: u64 = self.chunks.iter().map(|c| c.vertices.len().max(c.merge.len()) as u64).sum();
        if p.merges() {
            self.merge.resize_with(self.chunks.len(), Vec::new);
            for (m, c) in self.merge.iter_mut().zip(self.chunks.iter_mut()) {
                std::mem::swap(m, &mut c.merge);
            }
            self.grid.build(&self.merge, 2.0 * radius);
        }
        let w = settings.width as usize;
        let camera = CameraPass {
            scene,
            lights,
            settings,
            iteration: k,
            max_segments: p.segments(),
            mis,
            connects: p.connects(),
            merges: p.merges(),
            light_only,
            light_paths: n_light,
            chunks: &self.chunks,
            grid: &self.grid,
            radius,
            vm_norm: 1.0 / (std::f32::consts::PI * radius * radius * n_light as f32),
        };
        let mut own = vec![FixedRgb::default(); self.sums.len()];
        self.row_connections.resize(settings.height as usize, 0);
        own.par_chunks_mut(w).zip(self.row_connections.par_iter_mut()).enumerate().with_max_len(1).for_each(
            |(y, (row, tried))| {
                *tried = 0;
                if cancel.load(Ordering::Relaxed) {
                    return;
                }
                for (x, out) in row.iter_mut().enumerate() {
                    let (c, n) = camera.trace_pixel(x as u32, y as u32);
                    out.add_sample(c);
                    *tried += n as u64;
                }
            },
        );
        if cancel.load(Ordering::Relaxed) {
            return false;
        }
        for c in &self.chunks {
            for &(pixel, v) in &c.splats {
                own[pixel as usize].add_sample(v);
            }
        }
        self.sums.par_iter_mut().zip(own.par_iter()).for_each(|(s, o)| s.add(*o));
        self.iterations += 1;
        self.connections += self.row_connections.iter().sum::<u64>();
        self.light_vertices += stored;
        true
    }
}

impl Integrator for Vcm {
    fn prepare(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<()> {
        if scene.camera.is_orthographic() {
            return Err(PrismError::invalid(
                "vcm: light tracing connects light paths to the camera's eye or lens, which an orthographic camera \
                 does not have (render it with envlight or ppm)",
            ));
        }
        let pixels = settings.width as u64 * settings.height as u64;
        if pixels > u32::MAX as u64 {
            return Err(PrismError::invalid("vcm: image too large"));
        }
        let lights = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
        if !lights.has_power() {
            eprintln!("warning: vcm: no light emits anything: only emission seen directly can appear");
        }
        if scene.lights.lights.iter().any(|l| matches!(l, LightSource::Point(p) if p.attenuation != Vec3::Z)) {
            eprintln!(
                "warning: vcm: point lights emit with physical inverse-square falloff; their non-physical attenuation is ignored"
            );
        }
        self.lights = Some(lights);
        self.light_paths = self.params.light_paths.unwrap_or(pixels).clamp(1, MAX_LIGHT_PATHS);
        self.radius = match self.params.radius {
            Some(r) => r,
            None => self.default_radius(scene, settings),
        };
        if !(self.radius.is_finite() && self.radius > 0.0) {
            self.radius = 1e-3 * scene.lights.sphere.radius;
        }
        self.sums = vec![FixedRgb::default(); pixels as usize];
        self.iterations = 0;
        self.light_vertices = 0;
        self.connections = 0;
        Ok(())
    }

    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput {
        let s = pass.settings;
        self.sums.iter_mut().for_each(|v| *v = FixedRgb::default());
        for i in 0..pass.spp.max(1) as u64 {
            if !self.iterate(scene, s, pass.first_sample + i, cancel) {
                // A pass cut short is dropped whole (its iterations are rendered again on a resume).
                return PassOutput::Samples(Vec::new());
            }
        }
        let w = s.width as usize;
        let out = tiles(s.width, s.height)
            .into_iter()
            .map(|t| {
                let n = (t.w * t.h) as usize;
                let mut sums = Vec::with_capacity(n);
                for y in t.y0..t.y0 + t.h {
                    let row = y as usize * w;
                    sums.extend_from_slice(&self.sums[row + t.x0 as usize..row + (t.x0 + t.w) as usize]);
                }
                TileSamples { tile: t, counts: vec![pass.spp.max(1); n], sums, nonfinite: 0 }
            })
            .collect();
        PassOutput::Samples(out)
    }

    fn samples_per_timed_pass(&self, _planned: u32) -> u32 {
        // A pass cut short is dropped whole: one iteration per pass loses at most one to the time budget.
        1
    }

    fn status(&self) -> Option<String> {
        Some(format!(
            "{} iterations, {:.1} M light paths, {:.1} M light vertices, {:.1} M connections",
            self.iterations,
            (self.iterations * self.light_paths) as f64 / 1e6,
            self.light_vertices as f64 / 1e6,
            self.connections as f64 / 1e6
        ))
    }
}
