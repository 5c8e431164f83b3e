//! The light pass of one iteration: `n` light paths from lights chosen by power (`sample_le`), scattered with the
//! BSDFs' importance-transport sampling, their MIS quantities kept at every vertex ([`Partial`]).
//!
//! At every vertex with a smooth lobe the path
//! - is stored for connections (the camera path of the same index connects to it) and for merging (the hash grid
//!   over every light vertex of the iteration), and
//! - is connected to the camera (light tracing, `t = 1`): a splat on the pixels whose filter covers the point's
//!   projection, weighted against every other strategy (`[tech. rep. (46)]`).
//!
//! Path `j` of iteration `k` draws its numbers from the sampler keyed by (seed, k), sample index `j`: light
//! choice, origin and direction first (stratified over the iteration's paths), then (lobe, direction, roulette) per
//! bounce (and a lens point before them at each vertex connected to a thin lens). Paths are traced in fixed chunks in parallel; vertices and splats are kept in chunk order, and splats
//! are summed in fixed point, so the iteration's result does not depend on the thread count.

use glam::{Vec2, Vec3, Vec3A};
use prism_core::accel::GridPoint;
use prism_core::bsdf::{Bsdf, TransportMode};
use prism_core::lights::LightSampler;
use prism_core::math::luminance;
use prism_core::primitives::SurfaceHit;
use prism_core::sampling::{PixelFilter, Rng, Sampler, SamplerKind, hash_u64};
use prism_core::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

use super::mis::{Mis, Partial, light_pdfs};
use super::weights;

/// A light-path vertex kept for connections: its point, its BSDF (seen from the previous vertex, built once in the
/// light pass for every camera vertex that connects to it), and its weights.
#[derive(Clone, Copy, Debug)]
pub struct LightVertex {
    /// The BSDF at the vertex, `wo` towards the previous vertex of the light path.
    pub bsdf: Bsdf,
    /// Position.
    pub p: Vec3A,
    /// Floating-point error bound of `p` (shadow rays start off the surface).
    pub p_err: Vec3A,
    /// Geometric normal, as the primitive orients it.
    pub ng: Vec3A,
    /// Throughput from the light: the light's power over the densities of the path so far.
    pub beta: Vec3,
    /// MIS quantities at the vertex.
    pub mis: Partial,
    /// Segments from the light to the vertex.
    pub length: u32,
}

/// A light-path vertex in the merging grid: only what a merge reads.
#[derive(Clone, Copy, Debug)]
pub struct MergeVertex {
    /// Position.
    pub p: Vec3A,
    /// Unit direction towards the previous vertex of the light path.
    pub wo: Vec3A,
    /// Geometric normal as the primitive orients it: merging with a camera vertex whose surface faces the other
    /// way (the far side of a wall thinner than the radius) is refused.
    pub ng: Vec3A,
    /// Throughput from the light.
    pub beta: Vec3,
    /// The MIS quantity for connection and merging.
    pub dvcm: f32,
    /// The MIS quantity for merging.
    pub dvm: f32,
    /// Segments from the light to the vertex.
    pub length: u32,
}

impl GridPoint for MergeVertex {
    #[inline(always)]
    fn position(&self) -> Vec3A {
        self.p
    }
}

/// Light paths traced per parallel chunk (fixed, so storage order does not depend on the thread count).
pub const CHUNK: u64 = 256;

/// What one chunk of light paths left: vertices (with the end of each path's run), merge vertices and splats.
#[derive(Default)]
pub struct ChunkOut {
    /// The chunk's connection vertices, path by path.
    pub vertices: Vec<LightVertex>,
    /// For each path of the chunk, the end of its run in `vertices`.
    pub ends: Vec<u32>,
    /// The chunk's merge vertices.
    pub merge: Vec<MergeVertex>,
    /// Light tracing: (pixel index, contribution) per splat.
    pub splats: Vec<(u32, Vec3)>,
}

/// What the light pass needs.
pub struct LightPass<'a> {
    pub scene: &'a Scene,
    pub lights: &'a LightSampler,
    pub sampler: SamplerKind,
    pub filter: PixelFilter,
    pub seed: u64,
    pub iteration: u64,
    /// Light paths this iteration.
    pub paths: u64,
    /// Most path segments.
    pub max_segments: u32,
    pub mis: Mis,
    /// Keep vertices for connections.
    pub keep_vertices: bool,
    /// Keep vertices for merging.
    pub keep_merge: bool,
    /// Connect vertices to the camera.
    pub to_camera: bool,
    /// Light tracing alone (its splats unweighted).
    pub light_only: bool,
}

impl LightPass<'_> {
    /// Trace the iteration's light paths into `chunks` (cleared and refilled, capacity kept). False if cancelled.
    pub fn trace(&self, chunks: &mut Vec<ChunkOut>, cancel: &AtomicBool) -> bool {
        let n = self.paths.div_ceil(CHUNK) as usize;
        chunks.resize_with(n, ChunkOut::default);
        chunks.par_iter_mut().enumerate().for_each(|(c, out)| {
            out.vertices.clear();
            out.ends.clear();
            out.merge.clear();
            out.splats.clear();
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            let start = c as u64 * CHUNK;
            for j in start..(start + CHUNK).min(self.paths) {
                self.trace_one(j, out);
                out.ends.push(out.vertices.len() as u32);
            }
        });
        !cancel.load(Ordering::Relaxed)
    }

    fn trace_one(&self, j: u64, out: &mut ChunkOut) {
        let scene = self.scene;
        let lights = &scene.lights;
        let key = hash_u64(self.seed ^ hash_u64(self.iteration.wrapping_add(0x7c3a_91e5)));
        let mut sampler = Sampler::new(self.sampler, key as u32, Rng::new(key, j));
        sampler.start(j as u32);
        let (u_choice, u_pos, u_dir) = (sampler.next_1d(), sampler.next_2d(), sampler.next_2d());
        if self.lights.is_empty() || !self.lights.has_power() {
            return;
        }
        let (slot, prob) = self.lights.choice.choose(u_choice);
        let le = if slot == lights.len() {
            match (&lights.environment, &self.lights.env) {
                (Some(env), Some(es)) => env.sample_le(es, &lights.sphere, u_pos, u_dir),
                _ => None,
            }
        } else {
            lights.sample_le(slot, &scene.prims, u_pos, u_dir)
        };
        let Some(le) = le else { return };
        if !(le.pdf_pos > 0.0 && le.pdf_dir > 0.0 && prob > 0.0) {
            return;
        }
        let mut beta = le.flux() / prob;
        if !(beta.is_finite() && beta.max_element() > 0.0) {
            return;
        }
        let mis = &self.mis;
        let dir = le.ray.dir;
        let pdfs = light_pdfs(scene, self.lights, slot, le.ray.origin, le.n, dir);
        if !(pdfs.emission > 0.0 && pdfs.emission.is_finite()) {
            return;
        }
        // [tech. rep. (31)-(33), (48)-(50)], completed at the first hit.
        let cos_light = if pdfs.finite && !pdfs.delta { le.n.dot(dir).abs() } else { 1.0 };
        let mut w = Partial::light(mis, &pdfs, cos_light);
        let mut ray = le.ray;
        let mut length = 1u32;
        let mut origin = ray.origin;
        while let Some(s) = scene.trace(&ray) {
            let wo = -ray.dir;
            let dist = (s.p - origin).length();
            let finite_segment = length > 1 || pdfs.finite;
            w.arrive(mis, finite_segment.then_some(dist), s.ng.dot(wo).abs());
            let Some(bsdf) = scene.bsdf(&s, wo) else { break };
            if bsdf.has_smooth() {
                if self.keep_vertices {
                    out.vertices.push(LightVertex { bsdf, p: s.p, p_err: s.p_err, ng: s.ng, beta, mis: w, length });
                }
                if self.keep_merge {
                    out.merge.push(MergeVertex { p: s.p, wo, ng: s.ng, beta, dvcm: w.dvcm, dvm: w.dvm, length });
                }
                if self.to_camera && length < self.max_segments {
                    // A thin lens's point is drawn only where there is a lens (a pinhole's numbers stay as they are).
                    let u_lens = if scene.camera.has_lens() { sampler.next_2d() } else { Vec2::ZERO };
                    self.connect_to_camera(&s, &bsdf, u_lens, beta, &w, &mut out.splats);
                }
            }
            if length + 2 > self.max_segments {
                break;
            }
            let (u_lobe, u_bsdf, u_rr) = (sampler.next_1d(), sampler.next_2d(), sampler.next_1d());
            let Some(bs) = bsdf.sample_mode(u_lobe, u_bsdf, TransportMode::Importance) else { break };
            let cos_out = s.ng.dot(bs.wi).abs();
            w.scatter(mis, cos_out, (!bs.delta).then(|| (bs.pdf, bsdf.pdf_rev(bs.wi))));
            let next = beta * bs.weight;
            // Russian roulette on the drop in throughput from the third segment on (survival capped at 0.95 on
            // very long paths, so lossless loops end).
            let (l0, l1) = (luminance(beta), luminance(next));
            if !(l1 > 0.0 && l1.is_finite()) {
                break;
            }
            let mut q = if length >= 2 { (l1 / l0).min(1.0) } else { 1.0 };
            if length >= 64 {
                q = q.min(0.95);
            }
            if q < 1.0 {
                if u_rr >= q {
                    break;
                }
                beta = next / q;
            } else {
                beta = next;
            }
            origin = s.p;
            ray = s.spawn(bs.wi);
            length += 1;
        }
    }

    /// Light tracing from the vertex `s` (BSDF `bsdf`) to the eye, or to the point of a thin lens that `u_lens`
    /// picks: the splats on the pixels whose filter covers its projection [tech. rep. (46)].
    fn connect_to_camera(
        &self,
        s: &SurfaceHit,
        bsdf: &prism_core::bsdf::Bsdf,
        u_lens: Vec2,
        beta: Vec3,
        w: &Partial,
        splats: &mut Vec<(u32, Vec3)>,
    ) {
        let scene = self.scene;
        let cam = &scene.camera;
        let Some((film, to_eye, dist, ray_pdf, eye)) = cam.project_lens(s.p, u_lens) else { return };
        let f = bsdf.eval_mode(to_eye, TransportMode::Importance);
        if f == Vec3::ZERO {
            return;
        }
        let cos_geo = s.ng.dot(to_eye).abs();
        let cos_shading = bsdf.normal().dot(to_eye).abs();
        let rev = bsdf.pdf_rev(to_eye);
        let mis = &self.mis;
        let dist2 = dist * dist;
        let n_light = self.paths as f32;
        let support = self.filter.support();
        let (x0, x1) = ((film.x - support - 0.5).floor().max(0.0) as u32, (film.x + support - 0.5).ceil() as u32);
        let (y0, y1) = ((film.y - support - 0.5).floor().max(0.0) as u32, (film.y + support - 0.5).ceil() as u32);
        let first = splats.len();
        for py in y0..=y1.min(cam.height - 1) {
            for px in x0..=x1.min(cam.width - 1) {
                let density = self.filter.density(film - Vec2::new(px as f32 + 0.5, py as f32 + 0.5));
                if !(density > 0.0 && density.is_finite()) {
                    continue;
                }
                // The camera's density of this point (per unit film area, pixel `(px, py)`'s filter).
                let cam_pdf_a = ray_pdf * density * cos_geo / dist2;
                let weight =
                    if self.light_only { 1.0 } else { weights::light_tracing(mis, w, cam_pdf_a, n_light, rev) };
                let c = beta * f * (weight * cos_shading * ray_pdf * density / (dist2 * n_light));
                if c.is_finite() && c.max_element() > 0.0 {
                    splats.push((py * cam.width + px, c));
                }
            }
        }
        if splats.len() > first {
            let ray = s.spawn_to(eye, Vec3A::ZERO, Vec3A::ZERO);
            if scene.occluded(&ray) {
                splats.truncate(first);
            }
        }
    }
}
