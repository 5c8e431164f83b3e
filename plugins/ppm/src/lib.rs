//! # ppm
//!
//! Progressive photon mapping with a hash-grid photon lookup: stochastic progressive photon mapping (Hachisuka &
//! Jensen 2009) by default, or the original fixed-visible-point method.
//!
//! ```text
//! --integrator "ppm(alpha: 0.7, radius: None, radius_pixels: 3, photons: None, max_depth: -1, eye_depth: -1, photon_depth: -1, mode: stochastic, lookup: hash_grid, glossy: trace)"
//! ```
//!
//! ## What it computes
//!
//! Each iteration is one sample of the render's budget (`--spp 64` is 64 iterations; `--time` stops after the
//! iteration that crosses it):
//!
//! 1. **Eye pass**: one camera sample per pixel (sample index = iteration, so pixel positions and lens samples are
//!    stratified over iterations) traced through mirrors and dielectrics (exact Fresnel split) to its first vertex
//!    with a smooth lobe, the *visible point*, which also gets direct light by next-event estimation. Emission seen
//!    along the chain goes to the pixel. With `glossy: trace`, glossy surfaces (smooth lobes but none diffuse: rough
//!    metal and glass, a lone Phong lobe) are path-traced through as `envlight` does (next-event estimation and the
//!    BSDF sample weighted by MIS, Russian roulette from the fifth eye vertex), and the visible point lies on the next
//!    diffuse surface. Near-specular parts (a plastic's coat of GGX width under 0.01, such metals under
//!    `glossy: gather`), whose reflection photons and light samples cannot find, are split off by the lobe choice:
//!    the chain continues through them and the visible point takes the rest of the BSDF (a plastic sphere with a
//!    coat of width 0.001 in a white furnace is within 0.5% of Mitsuba 3's render; fixed mode gathers through the
//!    whole BSDF and loses that coat's reflection of area lights and the sky).
//! 2. **Photon pass**: `photons` photons from the lights (chosen by power), scattered with importance-transport
//!    sampling (no `1/eta^2` on refraction, the shading-normal correction) and Russian roulette on the throughput drop,
//!    stored from their *second* vertex on (direct light is the eye pass's) at surfaces with a smooth lobe (not on
//!    glossy ones with `glossy: trace`). The lookup over them is built while the eye pass runs.
//! 3. **Gather**: each visible point sums photon power x BSDF over the photons within its pixel's radius `R` that
//!    arrived on the side it is seen from, then updates `N <- N + alpha M`, `R <- R sqrt((N + alpha M) / (N + M))`,
//!    `tau <- (tau + beta Phi) (R_new / R)^2`.
//!
//! The pixel after k iterations is `direct / k + tau / (k photons pi R^2)`: the bias shrinks with `R` while the
//! variance stays bounded, so the error goes to 0 as iterations grow.
//!
//! **Fixed mode** (Hachisuka, Ogaki & Jensen 2008): one eye pass through the pixel centres at the start, fixed visible
//! points, then photon passes only, with photons stored from their first vertex (they carry direct light too). No
//! anti-aliasing and no depth of field: it converges to a point-sampled picture, not to the pixel-filtered reference.
//!
//! ## Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `alpha` | 0.7 | the fraction of new photons kept per iteration, in `(0, 1]` |
//! | `radius` | `None` | the initial gather radius in world units; by default each pixel's is `radius_pixels` pixel footprints at its first visible point (distance along the eye path x the pixel's angular size) |
//! | `radius_pixels` | 3 | the default radius in pixel footprints (positive) |
//! | `photons` | `None` | photons per iteration; default the image's pixel count; 1 to 2^24 |
//! | `max_depth` | -1 | the longest light path in segments, counted as `envlight` counts them (-1 unlimited): a photon deposited at its vertex v reaching a visible point after e specular eye vertices makes `e + v + 2` segments, so `ppm` and `envlight` render the same image for the same `max_depth` |
//! | `eye_depth` | -1 | the longest eye path to a visible point (or to emission it sees) in segments, on top of `max_depth`; -1 no limit of its own |
//! | `photon_depth` | -1 | the longest photon path to a stored photon in segments, on top of `max_depth`; -1 no limit of its own. pbrt's SPPM limits the two separately (`maxdepth` each): an imported `sppm` scene renders with `max_depth: -1, eye_depth: maxdepth, photon_depth: maxdepth` |
//! | `mode` | `stochastic` | `stochastic` or `fixed` |
//! | `lookup` | `hash_grid` | `hash_grid` or `kdtree` (the balanced photon map, on the same photons) |
//! | `glossy` | `trace` | `trace`: eye paths go on through glossy surfaces and photons are not stored on them; `gather`: visible points on them, which blurs what they reflect and blackens rough glass. Fixed mode always gathers |
//!
//! The defaults are scale-free: with `photons` = the pixel count, a radius of 3 pixel footprints holds a few photons
//! per iteration on any surface the camera sees, at any scene scale or resolution.
//!
//! ## What it is for
//!
//! Caustics, and light that reaches the camera through a diffuse bounce from specular paths: on the caustic Cornell
//! box it reaches Mitsuba's path-traced error in a fraction of Mitsuba's time, and with `glossy: trace` it renders
//! rough metal and glass well too ([Performance](../performance.md)). How it works in detail, with pictures of every
//! failure mode: [Photon mapping](../design/photon-mapping.md).
//!
//! ## Guarantees
//!
//! - **Deterministic** whatever the thread count: photon `j` of iteration `k` draws its numbers from (seed, k, j),
//!   photons are stored in a fixed order, and each pixel sums its photons in a fixed order without atomics.
//! - **Flat memory**: visible points, photons and lookup structures are allocated once and reused.
//! - **Shards** split pixel rows (`y % N == K`), every shard tracing the same photons; a cancelled iteration is dropped
//!   and the image of the completed ones kept; resumes are bit-identical.
//!
//! ## Failure modes
//!
//! - **Radius far too small** (`radius: 0.0001`, a hundredth of a pixel): almost no photon per pixel, speckle noise and
//!   a dark indirect image at first, but the image mean is right and keeps converging.
//! - **Radius far too large** (`radius: 0.5`, a quarter of the box): indirect light blurred across edges at first; the
//!   radius shrinks every iteration and the blur with it.
//! - **Walls thinner than the radius** do not leak: photons on the far side of a surface's normal are not gathered.
//! - **Only specular surfaces** (a mirror sphere under a sky): no visible points, a warning, and the image is the sky
//!   seen directly and in the mirror, exactly.
//! - **Only glossy surfaces**: no visible points, a note, and the eye paths traced through the glossy surfaces are the
//!   whole estimate, a path tracer's.
//! - **Very many iterations**: radii shrink as `k^((alpha - 1) / 2)` but stay positive and finite (f64 statistics, a
//!   floor at 1e-12 of the initial area).
//! - **A light of zero power**: a warning, nothing emitted, a black image.
//! - `--adaptive` has no effect (a warning).
//! - Bad parameters (`alpha` outside `(0, 1]`, `radius` or `radius_pixels` not positive, `photons` 0 or above 2^24,
//!   `max_depth` 0, unknown values of `mode`, `lookup` or `glossy`, unknown fields) are one-line errors naming the
//!   parameter.
//!
//! ## In the source
//!
//! `params.rs` (the parameters and their checks), `visible.rs` (the eye pass and its visible points), `photons.rs`
//! (the photon pass), `kd_tree.rs` and the shared `prism_core::accel::PointHashGrid` (the two photon lookups), `gather.rs` (the radius update and
//! the estimate), `lib.rs` (the iteration, its state for resumes, and the shard by pixel rows).

pub mod gather;
mod kd_tree;
mod params;
pub mod photons;
mod visible;

pub use gather::PixelStats;
/// The hash-grid photon lookup: the shared point grid over photons.
pub type PhotonHashGrid = prism_core::accel::PointHashGrid<Photon>;
pub use kd_tree::PhotonKdTree;
pub use params::{GlossyEye, MAX_PHOTONS, PhotonLookup, PpmMode, PpmParams};
pub use visible::{EyePass, EyeResult, VisiblePoint};

use glam::Vec3;
use photons::{Photon, PhotonPass};
use prism_core::error::{PrismError, Result};
use prism_core::integrator::{Integrator, PassInfo, PassOutput};
use prism_core::lights::{EnvStrategy, LightSampler};
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;
use prism_engine::{App, Plugin};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

pub struct PpmPlugin;

impl Plugin for PpmPlugin {
    fn name(&self) -> &str {
        "ppm"
    }

    fn build(&self, app: &mut App) {
        app.register_integrator(
            "ppm",
            Box::new(|cfg| {
                let params: PpmParams = cfg.parse_params()?;
                params.validate()?;
                Ok(Box::new(Ppm::new(params)))
            }),
        );
    }
}

/// The photon mapper's state between passes.
pub struct Ppm {
    params: PpmParams,
    lights: Option<LightSampler>,
    stats: Vec<PixelStats>,
    eye: Vec<EyeResult>,
    chunks: Vec<Vec<Photon>>,
    grid: PhotonHashGrid,
    kd: PhotonKdTree,
    /// Iterations completed.
    iterations: u64,
    photons_per_iteration: u64,
    photons_stored: u64,
    warned_no_visible_points: bool,
    /// Fixed mode: the visible points of this process's eye pass exist (they are recomputed after a resume).
    eye_ready: bool,
    /// The current radii of the pixels with a visible point (reused buffer, for the grid's cell size).
    radii: Vec<f32>,
    /// Rows this process renders: `(k, n)` = rows `y % n == k` (a row shard), `(0, 1)` = all.
    rows: (u32, u32),
    /// The hash grid's cell size from the last iteration's radii (the next iteration builds its grid with it while
    /// the eye pass runs); `None` before the first.
    cell: Option<f32>,
    /// With a noise target: the sums of each iteration's own per-pixel estimate `direct + beta Phi / (photons pi
    /// R^2)` in two contiguous halves, whose difference estimates the image's variance (`prism_core::film::noise`).
    noise: Option<Box<prism_core::film::NoiseHalves>>,
    /// The iteration's per-pixel estimates (reused buffer; with a noise target only).
    iteration_estimates: Vec<glam::DVec3>,
    /// Image width in pixels.
    width: u32,
}

impl Ppm {
    pub fn new(params: PpmParams) -> Self {
        Ppm {
            params,
            lights: None,
            stats: vec![],
            eye: vec![],
            chunks: vec![],
            grid: PhotonHashGrid::default(),
            kd: PhotonKdTree::default(),
            iterations: 0,
            photons_per_iteration: 0,
            photons_stored: 0,
            warned_no_visible_points: false,
            eye_ready: false,
            radii: vec![],
            rows: (0, 1),
            cell: None,
            noise: None,
            iteration_estimates: vec![],
            width: 0,
        }
    }

    /// Iterations completed so far.
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// The per-pixel statistics (radius, photon count, flux).
    pub fn pixel_stats(&self) -> &[PixelStats] {
        &self.stats
    }

    /// Photons stored in the last iteration.
    pub fn photons_stored(&self) -> u64 {
        self.photons_stored
    }

    /// Bytes held by the photon storage and the lookup structures (for memory reports).
    pub fn memory_bytes(&self) -> usize {
        self.chunks.iter().map(|c| c.capacity() * std::mem::size_of::<Photon>()).sum::<usize>()
            + self.grid.memory_bytes()
            + self.kd.memory_bytes()
            + self.stats.capacity() * std::mem::size_of::<PixelStats>()
            + self.eye.capacity() * std::mem::size_of::<EyeResult>()
    }

    /// One iteration; false (and nothing changed) if cancelled.
    fn iterate(&mut self, scene: &Scene, settings: &RenderSettings, cancel: &AtomicBool) -> bool {
        let lights = self.lights.as_ref().expect("prepared");
        let fixed = self.params.mode == PpmMode::Fixed;
        let k = self.iterations;
        let w = settings.width as usize;
        // 1. Photon pass (it does not depend on the eye pass).
        let pass = PhotonPass {
            scene,
            lights,
            sampler: settings.sampler,
            seed: settings.seed,
            iteration: k,
            photons: self.photons_per_iteration,
            max_vertices: self.params.photon_vertices(),
            first_deposit: if fixed { 0 } else { 1 },
            store_on_glossy: !self.params.traces_glossy(),
        };
        if !pass.trace(&mut self.chunks, cancel) {
            return false;
        }
        self.photons_stored = self.chunks.iter().map(|c| c.len() as u64).sum();
        // 2. Eye pass (fixed mode: once, with iteration 0's numbers, also after a resume), with the photon lookup
        //    built meanwhile: the build is one thread's work and the eye pass's rows keep the other threads busy.
        //    The hash grid then takes its cell size from the previous iteration's radii; cells change only how
        //    fast the lookup is, never what it finds (gathered sums are exact fixed point, order-free).
        let lookup = self.params.lookup;
        let last_cell = self.cell;
        let mut built = false;
        if !fixed || !self.eye_ready {
            let index = if fixed { 0 } else { k };
            let (rk, rn) = self.rows;
            let eye = EyePass {
                scene,
                lights,
                settings,
                sampler: settings.sampler,
                max_segments: self.params.segments(),
                eye_segments: self.params.eye_segments(),
                direct_lighting: !fixed,
                pixel_centre: fixed,
                trace_glossy: self.params.traces_glossy(),
                split_near_specular: !fixed,
            };
            let (eye_rows, grid, kd, chunks) = (&mut self.eye, &mut self.grid, &mut self.kd, &self.chunks);
            // True when the lookup was built here (the hash grid needs a previous iteration's cell size).
            let build = || match lookup {
                PhotonLookup::HashGrid => last_cell.map(|cell| grid.build(chunks, cell)).is_some(),
                PhotonLookup::Kdtree => {
                    kd.build(chunks);
                    true
                }
            };
            let trace = || {
                eye_rows.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
                    if cancel.load(Ordering::Relaxed) || y as u32 % rn != rk {
                        return;
                    }
                    for (x, r) in row.iter_mut().enumerate() {
                        *r = eye.trace_pixel(x as u32, y as u32, index);
                    }
                })
            };
            (built, _) = rayon::join(build, trace);
            if cancel.load(Ordering::Relaxed) {
                return false;
            }
            self.eye_ready = true;
        }
        // 3. Gather and update.
        let initial = |vp: &VisiblePoint| {
            self.params
                .radius
                .unwrap_or_else(|| self.params.radius_pixels * scene.camera.pixel_footprint(vp.path_length.max(1e-30)))
        };
        self.radii.clear();
        self.radii.par_extend(self.stats.par_iter_mut().zip(self.eye.par_iter()).filter_map(|(st, e)| {
            let vp = e.vp.as_ref()?;
            st.init_radius(initial(vp));
            Some(st.radius() as f32)
        }));
        let r_max = self.radii.iter().copied().fold(0.0f32, f32::max);
        if r_max > 0.0 {
            match lookup {
                PhotonLookup::HashGrid => {
                    // Cells twice the median radius: most queries touch 2 x 2 x 2 cells.
                    let mid = self.radii.len() / 2;
                    let (_, median, _) = self.radii.select_nth_unstable_by(mid, f32::total_cmp);
                    let cell = (2.0 * *median).max(r_max * 1e-3);
                    self.cell = Some(cell);
                    if !built {
                        self.grid.build(&self.chunks, cell);
                    }
                }
                PhotonLookup::Kdtree if !built => self.kd.build(&self.chunks),
                PhotonLookup::Kdtree => {}
            }
        }
        let (grid, kd, lookup, alpha) = (&self.grid, &self.kd, self.params.lookup, self.params.alpha as f64);
        let max_segments = self.params.segments();
        let add_direct = !fixed || k == 0;
        // Pieces of at most 256 pixels: the gather's cost varies across the image, and rayon's even split left one
        // thread idle at the end of each iteration (1.78x on two threads; 1.98x with this).
        let photons = self.photons_per_iteration as f64;
        let track = self.noise.is_some();
        self.iteration_estimates.resize(if track { self.stats.len() } else { 0 }, glam::DVec3::ZERO);
        let gather_one = |st: &mut PixelStats, e: &EyeResult| {
            let (phi, m) = match &e.vp {
                Some(vp) if r_max > 0.0 => {
                    gather::gather(scene, vp, st.radius() as f32, max_segments, !fixed, |p, r, f| match lookup {
                        PhotonLookup::HashGrid => grid.query(p, r, f),
                        PhotonLookup::Kdtree => kd.query(p, r, f),
                    })
                }
                _ => (glam::DVec3::ZERO, 0),
            };
            // This iteration's own estimate, with the radius it gathered in (before the update shrinks it).
            let mut own = if add_direct { e.direct.as_dvec3() } else { glam::DVec3::ZERO };
            if let Some(vp) = &e.vp
                && st.r2 > 0.0
            {
                own += vp.beta.as_dvec3() * phi / (photons * std::f64::consts::PI * st.r2);
            }
            st.update(e, phi, m, alpha, add_direct);
            own
        };
        if track {
            self.stats
                .par_iter_mut()
                .zip(self.eye.par_iter())
                .zip(self.iteration_estimates.par_iter_mut())
                .with_max_len(256)
                .for_each(|((st, e), out)| *out = gather_one(st, e));
        } else {
            self.stats.par_iter_mut().zip(self.eye.par_iter()).with_max_len(256).for_each(|(st, e)| {
                gather_one(st, e);
            });
        }
        if let Some(h) = &mut self.noise {
            h.add_estimates(&self.iteration_estimates);
        }
        self.iterations += 1;
        true
    }

    /// The current image estimate.
    fn image(&self, fixed: bool) -> Vec<Vec3> {
        let k = self.iterations.max(1) as f64;
        let direct_count = if fixed { 1.0 } else { k };
        let photons = k * self.photons_per_iteration as f64;
        self.stats.par_iter().map(|s| s.estimate(direct_count, photons)).collect()
    }
}

impl Integrator for Ppm {
    fn prepare(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<()> {
        let lights = LightSampler::new(&scene.lights, &scene.prims, EnvStrategy::Quadtree);
        let pixels = settings.width as usize * settings.height as usize;
        self.photons_per_iteration = self.params.photons.unwrap_or(pixels as u64).min(MAX_PHOTONS);
        if !lights.has_power() {
            eprintln!("warning: ppm: no light emits anything: only emission seen directly can appear");
        }
        if scene
            .lights
            .lights
            .iter()
            .any(|l| matches!(l, prism_core::lights::LightSource::Point(p) if p.attenuation != Vec3::Z))
        {
            eprintln!(
                "warning: ppm: point lights emit photons with physical inverse-square falloff; their non-physical attenuation is ignored"
            );
        }
        self.lights = Some(lights);
        self.stats = vec![PixelStats::default(); pixels];
        self.eye = vec![EyeResult::default(); pixels];
        self.iterations = 0;
        self.eye_ready = false;
        self.cell = None;
        self.rows = settings.shard;
        self.width = settings.width;
        self.noise = settings.noise.map(|_| Box::new(prism_core::film::NoiseHalves::new(pixels)));
        if settings.width as u64 * settings.height as u64 > u32::MAX as u64 {
            return Err(PrismError::invalid("ppm: image too large"));
        }
        Ok(())
    }

    fn render_pass(&mut self, scene: &Scene, pass: &PassInfo, cancel: &AtomicBool) -> PassOutput {
        let fixed = self.params.mode == PpmMode::Fixed;
        // A pass cut short is dropped whole: the state goes back to the end of the last complete pass, which the
        // film and a saved `.prism-film` describe (an iteration of the cut pass would otherwise count twice on a
        // resume, which renders the pass again).
        let before = (pass.spp > 1).then(|| (self.iterations, self.stats.clone(), self.noise.clone()));
        let mut complete = true;
        for _ in 0..pass.spp.max(1) {
            if !self.iterate(scene, pass.settings, cancel) {
                complete = false;
                break;
            }
        }
        if !complete && let Some((iterations, stats, noise)) = before {
            self.iterations = iterations;
            self.stats = stats;
            self.noise = noise;
        }
        if self.iterations > 0 && !self.warned_no_visible_points && self.stats.iter().all(|s| !s.has_radius()) {
            self.warned_no_visible_points = true;
            if self.params.traces_glossy() {
                eprintln!(
                    "note: ppm: no eye path reached a diffuse surface, so no photon was gathered: the image is path \
                     traced through the specular and glossy surfaces alone (complete; `envlight` renders it without \
                     the photon passes)"
                );
            } else {
                eprintln!(
                    "warning: ppm: no visible points (no eye path reached a diffuse or glossy surface): only emission \
                     seen through specular surfaces and the background is rendered"
                );
            }
        }
        PassOutput::Estimate { image: self.image(fixed), complete }
    }

    fn samples_per_timed_pass(&self, _planned: u32) -> u32 {
        // A pass cut short is dropped whole (its iterations would double on a resume): one iteration per pass.
        1
    }

    fn shard_axis(&self) -> prism_core::integrator::ShardAxis {
        // Iterations depend on each other (radii shrink), so shards split the pixel rows; each shard traces every
        // photon (the same ones) and gathers for its rows only.
        prism_core::integrator::ShardAxis::Rows
    }

    fn save_state(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(16 + self.stats.len() * gather::STATS_BYTES);
        out.extend_from_slice(&self.iterations.to_le_bytes());
        out.extend_from_slice(&self.photons_per_iteration.to_le_bytes());
        for s in &self.stats {
            s.to_bytes(&mut out);
        }
        // With a noise target, its halves follow (so a resumed render stops where the uninterrupted one would).
        if let Some(h) = &self.noise {
            h.to_bytes(&mut out);
        }
        out
    }

    fn relative_error(&self) -> Option<f64> {
        let h = self.noise.as_deref()?;
        let image = self.image(self.params.mode == PpmMode::Fixed);
        let (w, (k, n)) = (self.width.max(1) as usize, self.rows);
        // Pixels of other row shards have no samples here.
        let counts: Vec<u64> =
            (0..image.len()).map(|i| if (i / w) as u32 % n == k { self.iterations } else { 0 }).collect();
        h.relative_error(&image, &counts)
    }

    fn load_state(&mut self, state: &[u8]) -> Result<()> {
        let expected = 16 + self.stats.len() * gather::STATS_BYTES;
        let with_noise = expected + prism_core::film::NoiseHalves::byte_len(self.stats.len());
        let (state, noise) = if state.len() == with_noise {
            let h = prism_core::film::NoiseHalves::from_bytes(&state[expected..], self.stats.len())
                .ok_or_else(|| PrismError::invalid("ppm: the film's noise halves hold invalid numbers"))?;
            (&state[..expected], Some(h))
        } else {
            (state, None)
        };
        if state.len() != expected {
            return Err(PrismError::invalid(format!(
                "ppm: the film's photon-mapping state has {} bytes, expected {expected} (a film of another integrator or size?)",
                state.len()
            )));
        }
        let u = |i: usize| u64::from_le_bytes(state[8 * i..8 * i + 8].try_into().unwrap_or_default());
        let (iterations, photons) = (u(0), u(1));
        if photons != self.photons_per_iteration {
            return Err(PrismError::invalid(format!(
                "ppm: the film was rendered with {photons} photons per iteration, this render uses {}",
                self.photons_per_iteration
            )));
        }
        let mut stats = Vec::with_capacity(self.stats.len());
        for chunk in state[16..].chunks_exact(gather::STATS_BYTES) {
            stats
                .push(PixelStats::from_bytes(chunk).ok_or_else(|| {
                    PrismError::invalid("ppm: the film's photon-mapping state holds invalid numbers")
                })?);
        }
        self.stats = stats;
        self.iterations = iterations;
        self.eye_ready = false;
        // A film without noise halves (rendered without a target) starts them empty.
        if self.noise.is_some() {
            self.noise = Some(Box::new(noise.unwrap_or_else(|| prism_core::film::NoiseHalves::new(self.stats.len()))));
        }
        Ok(())
    }

    fn status(&self) -> Option<String> {
        Some(format!(
            "{} iterations, {:.1} M photons emitted",
            self.iterations,
            (self.iterations * self.photons_per_iteration) as f64 / 1e6
        ))
    }
}
