//! The camera pass of one iteration: one camera path per pixel, and at each of its vertices every strategy the
//! mode uses, each weighted by MIS against all the others ([`Partial`]).
//!
//! At a camera vertex with a smooth lobe, after `t` segments from the eye:
//! - **emission** the path hits (area lights, the environment): weight `1 / (1 + w_camera)` [tech. rep. (42)-(43)];
//! - **next-event estimation** (connections): one light point chosen by power and sampled towards the vertex
//!   (`sample_li`) [tech. rep. (44)-(45)];
//! - **connections** to the vertices of light path `pixel mod light_paths` [tech. rep. (40)-(41)];
//! - **merging** with every light vertex of the iteration within the radius on a surface facing the same way
//!   [tech. rep. (38)-(39)].
//!
//! In light-tracing mode the camera path only gathers emission seen directly or through delta lobes (which light
//! tracing cannot connect to) and ends at its first smooth vertex. In `bpm` mode emission is taken only along delta
//! chains from the eye (everything else is merging's).
//!
//! Pixel `i`'s path of iteration `k` draws its numbers from the pixel's sampler at sample index `k` (the pixel
//! position first (then the lens point, for a thin lens), then five per vertex: light choice, light point, lobe, direction, roulette), so pixel positions
//! are stratified over iterations and the path does not depend on any other pixel's.

use glam::{Vec2, Vec3, Vec3A};
use prism_core::accel::PointHashGrid;
use prism_core::bsdf::{Bsdf, TransportMode};
use prism_core::integrator::roulette::survival;
use prism_core::lights::LightSampler;
use prism_core::math::Frame;
use prism_core::primitives::{NO_LIGHT, SurfaceHit};
use prism_core::sampling::{Rng, Sampler, hash_u64};
use prism_core::scene::Scene;
use prism_core::settings::RenderSettings;

use super::light_paths::{CHUNK, ChunkOut, LightVertex, MergeVertex};
use super::mis::{Mis, Partial, light_pdfs};
use super::weights;

/// The throughput below which camera paths play Russian roulette (`envlight`'s default).
const RR_THRESHOLD: f32 = 0.5;

/// What the camera pass reads.
pub struct CameraPass<'a> {
    pub scene: &'a Scene,
    pub lights: &'a LightSampler,
    pub settings: &'a RenderSettings,
    /// The iteration (the pixels' sample index).
    pub iteration: u64,
    /// Most path segments.
    pub max_segments: u32,
    pub mis: Mis,
    /// Next-event estimation and connections to light vertices.
    pub connects: bool,
    /// Merging.
    pub merges: bool,
    /// Light tracing alone: emission through delta chains only.
    pub light_only: bool,
    /// Light paths this iteration.
    pub light_paths: u64,
    /// The light pass's vertices, chunk by chunk.
    pub chunks: &'a [ChunkOut],
    /// The merging grid over every light vertex.
    pub grid: &'a PointHashGrid<MergeVertex>,
    /// This iteration's merging radius.
    pub radius: f32,
    /// `1 / (pi r^2 light_paths)`: the merging estimate's kernel and sample count.
    pub vm_norm: f32,
}

impl CameraPass<'_> {
    /// The vertices of light path `j`, in the order they were made (increasing length).
    fn light_path(&self, j: u64) -> &[LightVertex] {
        let chunk = &self.chunks[(j / CHUNK) as usize];
        let local = (j % CHUNK) as usize;
        let Some(&end) = chunk.ends.get(local) else { return &[] };
        let start = if local == 0 { 0 } else { chunk.ends[local - 1] };
        &chunk.vertices[start as usize..end as usize]
    }

    /// The camera path of pixel `(x, y)`: its estimate of the pixel for this iteration (light tracing's splats
    /// excluded), and the connections to light vertices it tried.
    pub fn trace_pixel(&self, x: u32, y: u32) -> (Vec3, u32) {
        let (scene, s, mis) = (self.scene, self.settings, &self.mis);
        let cam = &scene.camera;
        let pixel = y as u64 * s.width as u64 + x as u64;
        let key = hash_u64(s.seed ^ hash_u64(pixel)) as u32;
        let mut sampler = Sampler::new(s.sampler, key, Rng::for_pixel(s.seed, pixel, 0));
        sampler.start(self.iteration as u32);
        let offset = s.filter.warp(sampler.next_2d());
        let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
        let mut ray =
            if cam.has_lens() { cam.generate_ray_lens(film, sampler.next_2d()) } else { cam.generate_ray(film) };
        let cam_pdf = cam.ray_pdf(ray.dir) * s.filter.density(offset);
        if !(cam_pdf > 0.0 && cam_pdf.is_finite()) {
            return (Vec3::ZERO, 0);
        }
        let n_light = self.light_paths as f32;
        // [tech. rep. (31)-(33)], completed at the first hit.
        let mut w = Partial::camera(mis, n_light, cam_pdf);
        let (mut beta, mut color) = (Vec3::ONE, Vec3::ZERO);
        let (mut length, mut specular_path, mut eta2) = (1u32, true, 1.0f32);
        let mut origin = ray.origin;
        let partner = self.light_path(pixel % self.light_paths.max(1));
        let mut bsdf = Bsdf::new(Frame::from_normal(Vec3A::Z), Vec3A::Z, Vec3A::Z);
        let mut tried = 0u32;
        loop {
            let (u_choice, u_light) = (sampler.next_1d(), sampler.next_2d());
            let (u_lobe, u_bsdf, u_rr) = (sampler.next_1d(), sampler.next_2d(), sampler.next_1d());
            let Some(hit) = scene.trace(&ray) else {
                color += beta * self.escaped(&w, ray.dir, length, specular_path);
                break;
            };
            let wo = -ray.dir;
            w.arrive(mis, Some((hit.p - origin).length()), hit.ng.dot(wo).abs());
            if hit.light != NO_LIGHT {
                let le = scene.emitted(&hit, wo);
                if le != Vec3::ZERO {
                    color += beta * le * self.emission_weight(&w, &hit, wo, length, specular_path);
                }
            }
            if length >= self.max_segments {
                break;
            }
            if !scene.bsdf_into(&hit, wo, &mut bsdf) {
                break;
            }
            if bsdf.has_smooth() {
                if self.light_only {
                    break;
                }
                if self.connects {
                    color += beta * self.next_event(&hit, &bsdf, &w, u_choice, u_light);
                    for lv in partner {
                        if lv.length + length + 1 > self.max_segments {
                            break;
                        }
                        tried += 1;
                        color += beta * lv.beta * self.connect(&hit, &bsdf, &w, lv);
                    }
                }
                if self.merges {
                    color += beta * (self.merge(&hit, &bsdf, &w, length) * self.vm_norm);
                }
            }
            let Some(bs) = bsdf.sample_mode(u_lobe, u_bsdf, TransportMode::Radiance) else { break };
            w.scatter(mis, hit.ng.dot(bs.wi).abs(), (!bs.delta).then(|| (bs.pdf, bsdf.pdf_rev(bs.wi))));
            beta *= bs.weight;
            eta2 *= bs.eta * bs.eta;
            specular_path &= bs.delta;
            if !(beta.max_element() > 0.0 && beta.is_finite()) {
                break;
            }
            let q = survival(beta, eta2, RR_THRESHOLD, length as i32);
            if q < 1.0 {
                if u_rr >= q {
                    break;
                }
                beta /= q;
            }
            origin = hit.p;
            ray = hit.spawn(bs.wi);
            length += 1;
        }
        (color, tried)
    }

    /// What a camera path leaving the scene in direction `dir` after `length` segments sees, MIS-weighted: the
    /// environment (a light every strategy can find) or the background (which only camera paths see).
    fn escaped(&self, w: &Partial, dir: Vec3A, length: u32, specular_path: bool) -> Vec3 {
        let scene = self.scene;
        let Some(env) = &scene.lights.environment else { return scene.globals.background };
        let le = env.eval(dir);
        if le == Vec3::ZERO {
            return Vec3::ZERO;
        }
        if length == 1 {
            return le;
        }
        if self.light_only || !self.connects {
            return if specular_path { le } else { Vec3::ZERO };
        }
        let pdfs = light_pdfs(scene, self.lights, scene.lights.len(), Vec3A::ZERO, Vec3A::ZERO, -dir);
        le * weights::emission(&self.mis, w, &pdfs)
    }

    /// The MIS weight of emission the camera path hits at `hit` (seen from `wo`) after `length` segments.
    fn emission_weight(&self, w: &Partial, hit: &SurfaceHit, wo: Vec3A, length: u32, specular_path: bool) -> f32 {
        if length == 1 {
            return 1.0;
        }
        if self.light_only || !self.connects {
            return if specular_path { 1.0 } else { 0.0 };
        }
        let pdfs = light_pdfs(self.scene, self.lights, hit.light as usize, hit.p, hit.ng, wo);
        weights::emission(&self.mis, w, &pdfs)
    }

    /// Next-event estimation at `hit`: one light sample, weighted against emission found by BSDF sampling and
    /// against every longer light subpath [tech. rep. (44)-(45)].
    fn next_event(&self, hit: &SurfaceHit, bsdf: &Bsdf, w: &Partial, u_choice: f32, u: Vec2) -> Vec3 {
        let scene = self.scene;
        let Some((ls, slot)) = self.lights.sample_li(&scene.lights, &scene.prims, hit.p, bsdf.normal(), u_choice, u)
        else {
            return Vec3::ZERO;
        };
        if !(ls.pdf > 0.0 && ls.pdf.is_finite()) || ls.li == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let (f, bsdf_pdf, bsdf_rev) = bsdf.eval_pdfs(ls.wi, TransportMode::Radiance);
        if f == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let pdfs = light_pdfs(scene, self.lights, slot, ls.p, ls.n, -ls.wi);
        if !(pdfs.nee > 0.0 && pdfs.nee.is_finite()) {
            return Vec3::ZERO;
        }
        let cos_light = if pdfs.finite && !pdfs.delta { ls.n.dot(ls.wi).abs() } else { 1.0 };
        if !(cos_light > 0.0 && cos_light.is_finite()) {
            return Vec3::ZERO;
        }
        // Next-event estimation's density in solid angle at `hit`, as MIS counts it (see `LightPdfs`).
        let nee_w = match (pdfs.finite, pdfs.delta) {
            (true, true) => pdfs.nee * ls.dist * ls.dist,
            (true, false) => pdfs.nee * ls.dist * ls.dist / cos_light,
            (false, _) => pdfs.nee,
        };
        let cos_geo = hit.ng.dot(ls.wi).abs();
        let weight = weights::next_event(&self.mis, w, &pdfs, (bsdf_pdf, bsdf_rev), nee_w, cos_geo, cos_light);
        let c = f * ls.li * (bsdf.normal().dot(ls.wi).abs() * weight / ls.pdf);
        if !(c.max_element() > 0.0 && c.max_element().is_finite())
            || (!self.lights.proven_clear(hit, slot) && scene.occluded(&ls.shadow_ray(hit)))
        {
            return Vec3::ZERO;
        }
        c
    }

    /// The connection of camera vertex `hit` and light vertex `lv` (without the two throughputs)
    /// [tech. rep. (40)-(41)].
    fn connect(&self, hit: &SurfaceHit, bsdf: &Bsdf, w: &Partial, lv: &LightVertex) -> Vec3 {
        let d = lv.p - hit.p;
        let dist2 = d.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return Vec3::ZERO;
        }
        let dist = dist2.sqrt();
        let dir = d / dist;
        let (fc, camera_pdf, camera_rev) = bsdf.eval_pdfs(dir, TransportMode::Radiance);
        if fc == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let lb = &lv.bsdf;
        let (fl, light_pdf, light_rev) = lb.eval_pdfs(-dir, TransportMode::Importance);
        if fl == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let camera_pdf_a = camera_pdf * lv.ng.dot(dir).abs() / dist2;
        let light_pdf_a = light_pdf * hit.ng.dot(dir).abs() / dist2;
        let weight = weights::connection(&self.mis, w, &lv.mis, camera_pdf_a, light_pdf_a, camera_rev, light_rev);
        let g = bsdf.normal().dot(dir).abs() * lb.normal().dot(dir).abs() / dist2;
        let c = fc * fl * (g * weight);
        if !(c.max_element() > 0.0 && c.is_finite()) {
            return Vec3::ZERO;
        }
        if self.scene.occluded(&hit.spawn_to(lv.p, lv.p_err, lv.ng)) {
            return Vec3::ZERO;
        }
        c
    }

    /// Merging at camera vertex `hit` (after `length` segments): the MIS-weighted sum of BSDF x light throughput
    /// over the light vertices within the radius [tech. rep. (38)-(39)], before the kernel normalisation.
    fn merge(&self, hit: &SurfaceHit, bsdf: &Bsdf, w: &Partial, length: u32) -> Vec3 {
        let mis = &self.mis;
        // Surfaces facing opposite ways are different surfaces (a thin wall's two faces); on one surface the light
        // may arrive from either side (a rough dielectric transmits it), which the BSDF decides.
        let ng = hit.ng;
        let mut sum = Vec3::ZERO;
        self.grid.query(hit.p, self.radius, |mv| {
            if mv.length + length > self.max_segments || mv.ng.dot(ng) <= 0.0 {
                return;
            }
            let (f, pdf, rev) = bsdf.eval_pdfs(mv.wo, TransportMode::Radiance);
            if f == Vec3::ZERO {
                return;
            }
            let c = f * mv.beta * weights::merge(mis, w, mv.dvcm, mv.dvm, pdf, rev);
            if c.is_finite() {
                sum += c;
            }
        });
        sum
    }
}
