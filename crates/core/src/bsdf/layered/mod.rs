//! pbrt-v4's stochastic layered BSDF (`LayeredBxDF` in `src/pbrt/bxdfs.h`; Guo et al. 2018, "Position-Free Monte
//! Carlo Simulation for Arbitrary Layered BSDFs"): a dielectric coat over a diffuse or conductor base, with an
//! optional scattering medium between them, two-sided. pbrt's `coateddiffuse` and `coatedconductor`.
//!
//! Nothing is tabulated: the value, the density and the sample are each a random walk between the two
//! interfaces (`interface.rs`), as pbrt computes them, so the walk's random numbers are drawn from a generator
//! seeded by a hash of the directions (pbrt does the same): the same `(wo, wi)` always gives the same estimate,
//! and a render stays deterministic whatever the threads.
//!
//! - `f(wo, wi)` is an unbiased estimate of the layered BSDF (`samples` walks, each with next-event estimation
//!   towards `wi` through the exit interface, MIS by the power heuristic);
//! - `sample` follows one walk from `wo` until it leaves the layers; its weight `f |cos| / pdf` is the walk's
//!   throughput (unbiased for the BSDF's), and `pdf` is only proportional to the true density (pbrt's
//!   `pdfIsProportional`), so the [`Bsdf`](super::Bsdf) uses [`Layers::pdf`] for multiple importance sampling;
//! - the one departure from pbrt-v4: the MIS weights of `f`'s two connections through the exit interface compare
//!   densities of the same variable (the direction inside the layer), which pbrt's do not (its open issue #187:
//!   `f` and `sample` disagree on rough coats); `tests/layered_bsdf.rs` checks that they now agree;
//! - [`Layers::pdf`] is pbrt's stochastic estimate of the walk's density mixed with 10% of the uniform sphere.
//!
//! Parameters ([`LayerSpec`], one per material): the coat's relative index `eta`, the medium's `thickness` (in
//! units of its mean free path; the medium has extinction 1), its Henyey–Greenstein `g`, `max_depth` (scattering
//! events per walk) and `samples` (walks per value estimate). Per hit: the coat's GGX width (pbrt's `alpha`,
//! smooth below 1e-3), the base (a reflectance, or a conductor's width and complex index relative to the coat)
//! and the medium's albedo (0: no medium).

mod interface;

use super::TransportMode;
use crate::sampling::{Rng, hash_u64};
use glam::{Vec2, Vec3, Vec3A};
use interface::{Interface, InterfaceSample, Parts, henyey_greenstein, sample_henyey_greenstein};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// What lies under the coat.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayerBase {
    /// A Lambertian base (`coateddiffuse`).
    Diffuse,
    /// A GGX conductor (`coatedconductor`).
    Conductor,
}

/// The constant parameters of a layered material (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerSpec {
    /// The base's kind.
    pub base: LayerBase,
    /// The coat's index of refraction over the outside's.
    pub eta: f32,
    /// The medium's thickness in mean free paths (pbrt's default 0.01).
    pub thickness: f32,
    /// The medium's Henyey–Greenstein asymmetry, in `[-1, 1]`.
    pub g: f32,
    /// Most scattering events per walk (pbrt's `maxdepth`, default 10).
    pub max_depth: u32,
    /// Walks per value and density estimate (pbrt's `nsamples`, default 1).
    pub samples: u32,
}

impl LayerSpec {
    /// The interned copy of `self`: lobes refer to it, so it lives as long as the process (one per distinct
    /// specification).
    pub fn intern(self) -> &'static LayerSpec {
        static SPECS: OnceLock<Mutex<HashMap<[u32; 6], &'static LayerSpec>>> = OnceLock::new();
        let key = [
            self.base as u32,
            self.eta.to_bits(),
            self.thickness.to_bits(),
            self.g.to_bits(),
            self.max_depth,
            self.samples,
        ];
        let mut m = SPECS.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
        m.entry(key).or_insert_with(|| Box::leak(Box::new(self)))
    }
}

/// One layered BSDF at a hit: the spec with the per-hit parameters.
#[derive(Clone, Copy, Debug)]
pub struct Layers {
    top: Interface,
    bottom: Interface,
    thickness: f32,
    g: f32,
    albedo: Vec3,
    max_depth: u32,
    samples: u32,
}

/// A direction drawn by a walk: the throughput weight `f |cos| / pdf` and whether every event was specular.
#[derive(Clone, Copy, Debug)]
pub struct LayeredSample {
    /// The direction, local.
    pub wi: Vec3A,
    /// `f |wi.z| / pdf` per RGB channel.
    pub weight: Vec3,
    /// True when the walk only met specular events (the coat's mirror reflection, or a smooth coat over a smooth
    /// metal): a delta direction.
    pub specular: bool,
}

/// Beer–Lambert transmittance over height `dz` along `w` (extinction 1).
#[inline]
fn tr(dz: f32, w: Vec3A) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE { 1.0 } else { (-(dz / w.z).abs()).exp() }
}

#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

#[inline]
fn hash_dir(w: Vec3A) -> u64 {
    let bits = (w.x.to_bits() as u64) ^ ((w.y.to_bits() as u64) << 21) ^ ((w.z.to_bits() as u64) << 42);
    hash_u64(bits ^ hash_u64(w.z.to_bits() as u64))
}

/// The walk's uniform numbers (pbrt clamps them below 1; `next_f32` never returns 1).
struct Walk(Rng);

impl Walk {
    fn new(a: u64, b: u64) -> Self {
        Walk(Rng::new(a, b))
    }
    #[inline]
    fn r(&mut self) -> f32 {
        self.0.next_f32()
    }
    #[inline]
    fn r2(&mut self) -> Vec2 {
        let x = self.r();
        Vec2::new(x, self.r())
    }
}

#[inline]
fn flip(m: TransportMode) -> TransportMode {
    match m {
        TransportMode::Radiance => TransportMode::Importance,
        TransportMode::Importance => TransportMode::Radiance,
    }
}

impl Layers {
    /// The layered BSDF of `spec` with the coat's GGX width `coat_alpha`, the base's `base` (a reflectance for a
    /// diffuse base, the conductor's `eta` relative to the coat otherwise), `base_k` (the conductor's `k` relative
    /// to the coat), `base_alpha` (the conductor's width) and the medium's `albedo`.
    pub fn new(spec: &LayerSpec, coat_alpha: f32, base: Vec3, base_k: Vec3, base_alpha: f32, albedo: Vec3) -> Self {
        let bottom = match spec.base {
            LayerBase::Diffuse => Interface::Diffuse { r: base },
            LayerBase::Conductor => Interface::Conductor { alpha: base_alpha, eta: base, k: base_k },
        };
        Layers {
            top: Interface::Dielectric { eta: spec.eta, alpha: coat_alpha },
            bottom,
            thickness: spec.thickness.max(f32::MIN_POSITIVE),
            g: spec.g,
            albedo,
            max_depth: spec.max_depth,
            samples: spec.samples.max(1),
        }
    }

    /// True when every walk is specular: a smooth coat over a smooth conductor without a medium.
    pub fn is_delta(&self) -> bool {
        self.top.is_specular() && self.bottom.is_specular() && self.albedo == Vec3::ZERO
    }

    /// The probability that [`Layers::sample`] returns the coat's mirror reflection (a delta direction) for the
    /// lobe number `uc`: Fresnel's reflectance at `wo` for a smooth coat, 0 for a rough one.
    pub fn coat_mirror_probability(&self, wo: Vec3A) -> f32 {
        match self.top {
            Interface::Dielectric { eta, .. } if self.top.is_specular() => interface::fr_dielectric(wo.z.abs(), eta),
            _ => 0.0,
        }
    }

    /// The layered BSDF's value `f(wo, wi)`, estimated by `samples` walks (pbrt's `LayeredBxDF::f`).
    pub fn f(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> Vec3 {
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        // Two-sided: the walk always enters through the coat.
        let same = wo.z * wi.z > 0.0;
        let (exit, non_exit) = if !same { (&self.bottom, &self.top) } else { (&self.top, &self.bottom) };
        let exit_z = if !same { 0.0 } else { self.thickness };
        let n = self.samples as f32;
        let mut f = if same { self.top.f(wo, wi, mode) * n } else { Vec3::ZERO };
        let mut rng = Walk::new(hash_dir(wo), hash_dir(wi));
        let has_medium = self.albedo != Vec3::ZERO;
        for _ in 0..self.samples {
            let uc = rng.r();
            let u = rng.r2();
            let Some(wos) = self.top.sample(wo, uc, u, mode, Parts::Transmission).filter(InterfaceSample::usable)
            else {
                continue;
            };
            let uc = rng.r();
            let u = rng.r2();
            let Some(wis) = exit.sample(wi, uc, u, flip(mode), Parts::Transmission).filter(InterfaceSample::usable)
            else {
                continue;
            };
            let mut beta = wos.f * wos.wi.z.abs() / wos.pdf;
            let mut z = self.thickness;
            let mut w = wos.wi;
            for depth in 0..self.max_depth {
                if depth > 3 && beta.max_element() < 0.25 {
                    let q = (1.0 - beta.max_element()).max(0.0);
                    if rng.r() < q {
                        break;
                    }
                    beta /= 1.0 - q;
                }
                if !has_medium {
                    z = if z == self.thickness { 0.0 } else { self.thickness };
                    beta *= tr(self.thickness, w);
                } else {
                    let dz = -(1.0 - rng.r()).ln() / (1.0 / w.z.abs());
                    let zp = if w.z > 0.0 { z + dz } else { z - dz };
                    if zp == z {
                        continue;
                    }
                    if 0.0 < zp && zp < self.thickness {
                        // A scattering event in the medium: next-event estimation through the exit interface
                        // along the presampled `wis`, then a phase-function sample.
                        let mut wt = 1.0;
                        if !exit.is_specular() {
                            wt = power_heuristic(wis.pdf, henyey_greenstein((-w).dot(-wis.wi), self.g));
                        }
                        f += beta
                            * self.albedo
                            * henyey_greenstein((-w).dot(-wis.wi), self.g)
                            * wt
                            * tr(zp - exit_z, wis.wi)
                            * wis.f
                            / wis.pdf;
                        let (pw, ppdf) = sample_henyey_greenstein(-w, self.g, rng.r2());
                        if ppdf == 0.0 || pw.z == 0.0 {
                            continue;
                        }
                        // The phase function is sampled exactly: p / pdf = 1.
                        beta *= self.albedo;
                        w = pw;
                        z = zp;
                        // The MIS weights of the exit connections compare densities of the inner direction: the
                        // exit interface's is of `-w` sampled from `wi`, as `wis` was (pbrt-v4 weighs by the density
                        // of `wi` given `-w`, which on a rough coat biases the value; its issue #187).
                        if ((z < exit_z && w.z > 0.0) || (z > exit_z && w.z < 0.0)) && !exit.is_specular() {
                            let f_exit = exit.f(-w, wi, mode);
                            if f_exit.max_element() > 0.0 {
                                let exit_pdf = exit.pdf(wi, -w, Parts::Transmission);
                                let wt = power_heuristic(ppdf, exit_pdf);
                                f += beta * tr(zp - exit_z, pw) * f_exit * wt;
                            }
                        }
                        continue;
                    }
                    z = zp.clamp(0.0, self.thickness);
                }
                if z == exit_z {
                    // Reflection at the exit interface.
                    let uc = rng.r();
                    let u = rng.r2();
                    let Some(bs) = exit.sample(-w, uc, u, mode, Parts::Reflection).filter(InterfaceSample::usable)
                    else {
                        break;
                    };
                    beta *= bs.f * bs.wi.z.abs() / bs.pdf;
                    w = bs.wi;
                } else {
                    // Scattering at the other interface: next-event estimation along `wis`, then a sample.
                    if !non_exit.is_specular() {
                        let mut wt = 1.0;
                        if !exit.is_specular() {
                            wt = power_heuristic(wis.pdf, non_exit.pdf(-w, -wis.wi, Parts::All));
                        }
                        f += beta
                            * non_exit.f(-w, -wis.wi, mode)
                            * wis.wi.z.abs()
                            * wt
                            * tr(self.thickness, wis.wi)
                            * wis.f
                            / wis.pdf;
                    }
                    let uc = rng.r();
                    let u = rng.r2();
                    let Some(bs) = non_exit.sample(-w, uc, u, mode, Parts::Reflection).filter(InterfaceSample::usable)
                    else {
                        break;
                    };
                    beta *= bs.f * bs.wi.z.abs() / bs.pdf;
                    w = bs.wi;
                    if !exit.is_specular() {
                        let f_exit = exit.f(-w, wi, mode);
                        if f_exit.max_element() > 0.0 {
                            let mut wt = 1.0;
                            if !non_exit.is_specular() {
                                let exit_pdf = exit.pdf(wi, -w, Parts::Transmission);
                                wt = power_heuristic(bs.pdf, exit_pdf);
                            }
                            f += beta * tr(self.thickness, bs.wi) * f_exit * wt;
                        }
                    }
                }
            }
        }
        let f = f / n;
        if f.is_finite() { f.max(Vec3::ZERO) } else { Vec3::ZERO }
    }

    /// One walk from `wo` (pbrt's `LayeredBxDF::Sample_f`): `uc` and `u` sample the coat, the rest of the walk
    /// draws from a generator seeded by them and `wo`.
    pub fn sample(&self, wo: Vec3A, uc: f32, u: Vec2, mode: TransportMode) -> Option<LayeredSample> {
        let flip_wi = wo.z < 0.0;
        let wo = if flip_wi { -wo } else { wo };
        let out = |wi: Vec3A, weight: Vec3, specular: bool| {
            let wi = if flip_wi { -wi } else { wi };
            (weight.is_finite() && weight.max_element() > 0.0).then_some(LayeredSample { wi, weight, specular })
        };
        let bs = self.top.sample(wo, uc, u, mode, Parts::All).filter(InterfaceSample::usable)?;
        if !bs.is_transmission(wo) {
            return out(bs.wi, bs.f * bs.wi.z.abs() / bs.pdf, bs.specular);
        }
        let mut w = bs.wi;
        let mut specular_path = bs.specular;
        let seed_u = hash_u64((uc.to_bits() as u64) | ((u.x.to_bits() as u64) << 32)) ^ (u.y.to_bits() as u64);
        let mut rng = Walk::new(hash_dir(wo), hash_u64(seed_u));
        let mut f = bs.f * bs.wi.z.abs();
        let mut pdf = bs.pdf;
        let mut z = self.thickness;
        let has_medium = self.albedo != Vec3::ZERO;
        for depth in 0..self.max_depth {
            let rr_beta = f.max_element() / pdf;
            if depth > 3 && rr_beta < 0.25 {
                let q = (1.0 - rr_beta).max(0.0);
                if rng.r() < q {
                    return None;
                }
                pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            if has_medium {
                let dz = -(1.0 - rng.r()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < self.thickness {
                    let (pw, ppdf) = sample_henyey_greenstein(-w, self.g, rng.r2());
                    if ppdf == 0.0 || pw.z == 0.0 {
                        return None;
                    }
                    f *= self.albedo * ppdf;
                    pdf *= ppdf;
                    specular_path = false;
                    w = pw;
                    z = zp;
                    continue;
                }
                z = zp.clamp(0.0, self.thickness);
            } else {
                z = if z == self.thickness { 0.0 } else { self.thickness };
                f *= tr(self.thickness, w);
            }
            let interface = if z == 0.0 { &self.bottom } else { &self.top };
            let uc = rng.r();
            let u = rng.r2();
            let bs = interface.sample(-w, uc, u, mode, Parts::All).filter(InterfaceSample::usable)?;
            f *= bs.f;
            pdf *= bs.pdf;
            specular_path &= bs.specular;
            let transmitted = bs.is_transmission(-w);
            w = bs.wi;
            if transmitted {
                // The walk has left the layers (through the coat, or through a transmissive base).
                return out(w, f * w.z.abs() / pdf, specular_path);
            }
            f *= w.z.abs();
        }
        None
    }
    /// pbrt's `LayeredBxDF::PDF`: a stochastic estimate of the density of [`Layers::sample`] (the coat's
    /// reflection, the transmit-reflect-transmit paths by MIS between their two interfaces), mixed 9:1 with the
    /// uniform sphere's. Deterministic in `(wo, wi)`.
    pub fn pdf(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> f32 {
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let mut rng = Walk::new(hash_dir(wi), hash_dir(wo));
        let same = wo.z * wi.z > 0.0;
        let n = self.samples as f32;
        let mut sum = if same { n * self.top.pdf(wo, wi, Parts::Reflection) } else { 0.0 };
        let (r_if, t_if) = (&self.bottom, &self.top);
        for _ in 0..self.samples {
            if same {
                // The transmit-reflect-transmit term.
                let (uc, u) = (rng.r(), rng.r2());
                let wos = t_if.sample(wo, uc, u, mode, Parts::Transmission);
                let (uc, u) = (rng.r(), rng.r2());
                let wis = t_if.sample(wi, uc, u, flip(mode), Parts::Transmission);
                let ok = |s: &Option<InterfaceSample>| s.is_some_and(|s| s.f.max_element() > 0.0 && s.pdf > 0.0);
                if !(ok(&wos) && ok(&wis)) {
                    continue;
                }
                let (wos, wis) = (wos.unwrap_or_else(|| unreachable!()), wis.unwrap_or_else(|| unreachable!()));
                if t_if.is_specular() {
                    sum += r_if.pdf(-wos.wi, -wis.wi, Parts::All);
                } else {
                    let (uc, u) = (rng.r(), rng.r2());
                    let rs = r_if.sample(-wos.wi, uc, u, mode, Parts::All);
                    if let Some(rs) = rs.filter(|s| s.f.max_element() > 0.0 && s.pdf > 0.0) {
                        if r_if.is_specular() {
                            sum += t_if.pdf(-rs.wi, wi, Parts::All);
                        } else {
                            let r_pdf = r_if.pdf(-wos.wi, -wis.wi, Parts::All);
                            sum += power_heuristic(wis.pdf, r_pdf) * r_pdf;
                            let t_pdf = t_if.pdf(-rs.wi, wi, Parts::All);
                            sum += power_heuristic(rs.pdf, t_pdf) * t_pdf;
                        }
                    }
                }
            } else {
                // The transmit-transmit term (only for a transmissive base; neither of Prism's bases is).
                let (to_if, ti_if) = (&self.top, &self.bottom);
                let (uc, u) = (rng.r(), rng.r2());
                let Some(wos) = to_if.sample(wo, uc, u, mode, Parts::All) else { continue };
                if !wos.usable() || !wos.is_transmission(wo) {
                    continue;
                }
                let (uc, u) = (rng.r(), rng.r2());
                let Some(wis) = ti_if.sample(wi, uc, u, flip(mode), Parts::All) else { continue };
                if !wis.usable() || !wis.is_transmission(wi) {
                    continue;
                }
                sum += if to_if.is_specular() {
                    ti_if.pdf(-wos.wi, wi, Parts::All)
                } else if ti_if.is_specular() {
                    to_if.pdf(wo, -wis.wi, Parts::All)
                } else {
                    (to_if.pdf(wo, -wis.wi, Parts::All) + ti_if.pdf(-wos.wi, wi, Parts::All)) / 2.0
                };
            }
        }
        let p = 0.1 / (4.0 * std::f32::consts::PI) + 0.9 * sum / n;
        if p.is_finite() { p } else { 0.0 }
    }
}
