//! The MIS bookkeeping of vertex connection and merging (Georgiev et al. 2012, "Light Transport Simulation with
//! Vertex Connection and Merging", and its technical report "Implementing Vertex Connection and Merging", whose
//! equation numbers the code cites as `[tech. rep. (n)]`; SmallVCM is the reference implementation).
//!
//! Each subpath vertex carries three running quantities, `dvcm`, `dvc` and `dvm`, from which the weight of any
//! connection or merge made there follows in O(1): the sum over every other strategy that could have built the
//! same path of the ratio of its density to this one's. All strategies' densities are defined by the same
//! functions wherever they are evaluated, so the weights of one path's strategies sum to 1:
//!
//! - area conversions use geometric normals (shading normals enter only the throughput);
//! - a light's next-event density ([`LightPdfs::nee`]) is its choice probability times its position density from
//!   `pdf_le` (area lights: uniform by area, whatever next-event estimation samples), 1 for a delta position, and
//!   the environment's solid-angle density;
//! - the probability of choosing a delta lobe counts as equal both ways, and Russian roulette is not part of the
//!   densities (it divides the throughput, so every strategy stays unbiased for its weighted share).

use glam::Vec3A;
use prism_core::lights::{LightSampler, LightSource};
use prism_core::scene::Scene;

use super::params::Heuristic;

/// The iteration's MIS constants.
#[derive(Clone, Copy, Debug)]
pub struct Mis {
    /// The heuristic's exponent applied to every density ratio.
    pub heuristic: Heuristic,
    /// Weight of merging relative to a connection, `eta_VCM = pi r^2 n_light` [tech. rep. (20)] (0 without merging).
    pub vm: f32,
    /// Weight of a connection relative to merging, `1 / eta_VCM` (0 without connections).
    pub vc: f32,
}

impl Mis {
    /// The constants for merging radius `radius` and `light_paths` light paths, with the strategies used.
    pub fn new(heuristic: Heuristic, radius: f32, light_paths: f32, connect: bool, merge: bool) -> Self {
        let eta = std::f32::consts::PI * radius * radius * light_paths;
        let h = |x: f32| match heuristic {
            Heuristic::Balance => x,
            Heuristic::Power => x * x,
        };
        Mis { heuristic, vm: if merge { h(eta) } else { 0.0 }, vc: if connect { h(1.0 / eta) } else { 0.0 } }
    }

    /// A density ratio under the heuristic.
    #[inline(always)]
    pub fn m(&self, x: f32) -> f32 {
        match self.heuristic {
            Heuristic::Balance => x,
            Heuristic::Power => x * x,
        }
    }
}

/// The running MIS quantities of a subpath at its current vertex.
#[derive(Clone, Copy, Debug, Default)]
pub struct Partial {
    /// Connection and merging.
    pub dvcm: f32,
    /// Connection.
    pub dvc: f32,
    /// Merging.
    pub dvm: f32,
}

impl Partial {
    /// A camera subpath at the eye, whose ray the camera chose with density `cam_pdf` (per unit film area, the
    /// pixel filter's density included), against `light_paths` light paths [tech. rep. (31)-(33)]; completed at
    /// the first hit by [`Partial::arrive`].
    #[inline(always)]
    pub fn camera(mis: &Mis, light_paths: f32, cam_pdf: f32) -> Self {
        Partial { dvcm: mis.m(light_paths / cam_pdf), dvc: 0.0, dvm: 0.0 }
    }

    /// A light subpath leaving its light with densities `pdfs` and geometric cosine `cos_light` at the light (1 for
    /// delta and infinitely distant lights) [tech. rep. (31)-(33), (48)-(50)]; completed at the first hit.
    #[inline(always)]
    pub fn light(mis: &Mis, pdfs: &LightPdfs, cos_light: f32) -> Self {
        let mut w = Partial { dvcm: mis.m(pdfs.nee / pdfs.emission), ..Partial::default() };
        if !pdfs.delta {
            w.dvc = mis.m(cos_light / pdfs.emission);
        }
        w.dvm = w.dvc * mis.vc;
        w
    }

    /// At a new vertex reached over `dist` with geometric cosine `cos_in`: the area conversion of the segment
    /// [tech. rep. (31)-(36)], completed here (`dist` is not applied for the first segment from a light at
    /// infinity).
    #[inline(always)]
    pub fn arrive(&mut self, mis: &Mis, dist: Option<f32>, cos_in: f32) {
        if let Some(d) = dist {
            self.dvcm *= mis.m(d * d);
        }
        let c = mis.m(cos_in);
        self.dvcm /= c;
        self.dvc /= c;
        self.dvm /= c;
    }

    /// After scattering into a direction of geometric cosine `cos_out`: a delta lobe (`pdf` `None`) or a smooth one
    /// of forward density `pdf` and reverse density `rev` [tech. rep. (34)-(36), (53)-(55)].
    #[inline(always)]
    pub fn scatter(&mut self, mis: &Mis, cos_out: f32, pdf: Option<(f32, f32)>) {
        match pdf {
            None => {
                self.dvcm = 0.0;
                let c = mis.m(cos_out);
                self.dvc *= c;
                self.dvm *= c;
            }
            Some((pdf, rev)) => {
                let g = mis.m(cos_out / pdf);
                let mr = mis.m(rev);
                let dvc = g * (self.dvc * mr + self.dvcm + mis.vm);
                let dvm = g * (self.dvm * mr + self.dvcm * mis.vc + 1.0);
                self.dvcm = mis.m(1.0 / pdf);
                self.dvc = dvc;
                self.dvm = dvm;
            }
        }
    }
}

/// The densities of a light point or direction as every strategy counts them (choice probability included).
#[derive(Clone, Copy, Debug)]
pub struct LightPdfs {
    /// Next-event estimation: area density of the point (finite lights; 1 for a delta position), or solid-angle
    /// density of the direction (lights at infinity; 1 for a directional light).
    pub nee: f32,
    /// Emission: position density times direction density (the environment's position is on its covering disk).
    pub emission: f32,
    /// A light at a finite distance (area, point, spot).
    pub finite: bool,
    /// A delta light (point, spot, directional): never hit by a path.
    pub delta: bool,
}

/// The densities of light `slot` (`lights.len()` is the environment) at point `p` with geometric normal `n`
/// emitting in unit direction `dir` (away from the light, towards the scene).
pub fn light_pdfs(scene: &Scene, sampler: &LightSampler, slot: usize, p: Vec3A, n: Vec3A, dir: Vec3A) -> LightPdfs {
    let lights = &scene.lights;
    let pick = sampler.choice.prob(slot);
    if slot == lights.len() {
        let (pos, d) = match (&lights.environment, &sampler.env) {
            (Some(env), Some(es)) => env.pdf_le(es, &lights.sphere, dir),
            _ => (0.0, 0.0),
        };
        let nee = sampler.pdf_li_env(lights, n, -dir);
        return LightPdfs { nee, emission: pick * pos * d, finite: false, delta: false };
    }
    let (pos, d) = lights.pdf_le(slot, &scene.prims, p, n, dir);
    let (finite, delta) = match &lights.lights[slot] {
        LightSource::Area(_) => (true, false),
        LightSource::Point(_) | LightSource::Spot(_) => (true, true),
        LightSource::Directional(_) => (false, true),
    };
    let nee = if delta { pick } else { pick * pos };
    LightPdfs { nee, emission: pick * pos * d, finite, delta }
}
