//! The photon pass: photons leave the lights (one light chosen by power, an emitted ray from its `sample_le`),
//! scatter through the scene with the BSDFs' importance-transport sampling (exact Fresnel at mirrors and
//! dielectrics) and Russian roulette on the throughput's drop, and are stored at every vertex with a smooth BSDF
//! lobe from `first_deposit` on (1 in stochastic mode: direct light comes from the eye pass's next-event estimation;
//! 0 in fixed mode, where photons carry all light) — except on glossy surfaces when the eye pass traces through
//! them (`store_on_glossy` false), where no visible point would ever gather them.
//!
//! Photon `j` of iteration `k` draws its numbers from the sampler keyed by (seed, k), sample index `j`: the first
//! five dimensions (light choice, origin, direction) are a stratified low-discrepancy set over the iteration's
//! photons, then (lobe, direction, roulette) per bounce. Photons are traced in fixed chunks in parallel and stored
//! in chunk order, so the photon array is the same whatever the thread count.

use glam::{Vec3, Vec3A};
use prism_core::bsdf::TransportMode;
use prism_core::lights::LightSampler;
use prism_core::math::luminance;
use prism_core::sampling::{Rng, Sampler, SamplerKind, hash_u64};
use prism_core::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A stored photon: where it landed, the direction it came from, the surface's geometric normal on that side, and
/// its power (the light's power divided by the number of photons of one iteration is `beta / photons`).
#[derive(Clone, Copy, Debug)]
pub struct Photon {
    pub p: Vec3A,
    /// Unit direction towards where the photon came from.
    pub wi: Vec3A,
    /// Geometric normal at `p`, on the side the photon arrived from.
    pub ng: Vec3A,
    pub beta: Vec3,
    /// Index of this vertex on the photon's path (0: where it first hit the scene); the path from the light has
    /// `depth + 1` segments.
    pub depth: u32,
}

impl prism_core::accel::GridPoint for Photon {
    #[inline(always)]
    fn position(&self) -> Vec3A {
        self.p
    }
}

/// Photons traced per parallel chunk (fixed, so storage order does not depend on the thread count).
pub const CHUNK: u64 = 512;

/// What the photon pass needs.
pub struct PhotonPass<'a> {
    pub scene: &'a Scene,
    pub lights: &'a LightSampler,
    pub sampler: SamplerKind,
    pub seed: u64,
    pub iteration: u64,
    pub photons: u64,
    /// Most vertices a photon path follows.
    pub max_vertices: u32,
    pub first_deposit: u32,
    /// Store photons on glossy surfaces (smooth lobes, none diffuse) too; not when the eye pass traces through
    /// them and so never gathers there.
    pub store_on_glossy: bool,
}

impl PhotonPass<'_> {
    /// Trace the iteration's photons into `chunks` (one vector per chunk, cleared and refilled; the vectors keep
    /// their capacity between iterations). Returns false if cancelled.
    pub fn trace(&self, chunks: &mut Vec<Vec<Photon>>, cancel: &AtomicBool) -> bool {
        let n_chunks = self.photons.div_ceil(CHUNK) as usize;
        chunks.resize_with(n_chunks, Vec::new);
        chunks.par_iter_mut().enumerate().for_each(|(c, out)| {
            out.clear();
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            let start = c as u64 * CHUNK;
            for j in start..(start + CHUNK).min(self.photons) {
                self.trace_one(j, out);
            }
        });
        !cancel.load(Ordering::Relaxed)
    }

    fn trace_one(&self, j: u64, out: &mut Vec<Photon>) {
        let key = hash_u64(self.seed ^ hash_u64(self.iteration.wrapping_add(0x51ed_270b)));
        let mut sampler = Sampler::new(self.sampler, key as u32, Rng::new(key, j));
        sampler.start(j as u32);
        let scene = self.scene;
        let (u_choice, u_pos, u_dir) = (sampler.next_1d(), sampler.next_2d(), sampler.next_2d());
        let Some((le, prob)) = self.lights.sample_le(&scene.lights, &scene.prims, u_choice, u_pos, u_dir) else {
            return;
        };
        let mut beta = le.flux() / prob;
        if !(beta.is_finite() && beta.max_element() > 0.0) {
            return;
        }
        let mut ray = le.ray;
        for depth in 0..self.max_vertices {
            let Some(s) = scene.trace(&ray) else { break };
            let wo = -ray.dir;
            let Some(bsdf) = scene.bsdf(&s, wo) else { break };
            if depth >= self.first_deposit && bsdf.has_smooth() && (self.store_on_glossy || bsdf.has_diffuse()) {
                let ng = if s.ng.dot(wo) >= 0.0 { s.ng } else { -s.ng };
                out.push(Photon { p: s.p, wi: wo, ng, beta, depth });
            }
            let (u_lobe, u_bsdf, u_rr) = (sampler.next_1d(), sampler.next_2d(), sampler.next_1d());
            let Some(bs) = bsdf.sample_mode(u_lobe, u_bsdf, TransportMode::Importance) else { break };
            let next = beta * bs.weight;
            // Russian roulette on the drop in throughput (a mirror keeps a photon alive, a dark wall ends most).
            let (l0, l1) = (luminance(beta), luminance(next));
            if !(l1 > 0.0 && l1.is_finite()) {
                break;
            }
            let q = (1.0 - l1 / l0).max(0.0);
            if u_rr < q {
                break;
            }
            beta = next / (1.0 - q);
            ray = s.spawn(bs.wi);
        }
    }
}
