//! The lobes a BSDF is made of, each evaluated and sampled in the local shading frame (z = shading normal, `wo`
//! the unit direction towards the viewer, normally `wo.z > 0`). A [`Lobe`] is a plain enum: a BSDF is a small
//! fixed array of them and every call is a `match`, never a virtual call.
//!
//! | lobe | f(wo, wi) |
//! |---|---|
//! | `Diffuse` | `albedo / pi` |
//! | `DiffuseTransmission` | `r / pi` on `wo`'s side, `t / pi` on the other (pbrt-v4's `DiffuseTransmissionBxDF`) |
//! | `ThinDielectric` | a thin slab of glass (pbrt-v4's `ThinDielectricBxDF`): reflection `R' = R + T^2 R / (1 - R^2)` (`R` Fresnel's, `T = 1 - R`, the slab's inter-reflections summed), straight transmission `1 - R'` (delta) |
//! | `Phong` | `ks (e + 2) / (2 pi) cos^e(angle between wi and the mirror direction of wo)` (energy-normalised) |
//! | `Blinn6837` | `ks (n.h)^e / (pi wi.z)`: the 6.837 course's specular term (times the irradiance pi c cos of a light of colour c it gives `ks (n.h)^e c`) |
//! | `Mirror` | ideal reflection, weight `r` (delta) |
//! | `Dielectric` | smooth Fresnel dielectric: reflection `r F`, refraction `t (1 - F)` (`/ eta^2` for radiance) (delta) |
//! | `CourseRefraction` | the course's refraction: weight `t`, no Fresnel, nothing under total internal reflection (delta) |
//! | `Conductor` | GGX `F D G / (4 wo.z wi.z)` with a conductor Fresnel term, times `scale`; smooth (delta) when alpha = 0 |
//! | `RoughDielectric` | GGX reflection `r F D G / (4 |wo.z wi.z|)` and transmission (Walter et al. 2007) `t (1 - F) D G |wo.m| |wi.m| / (|wo.z wi.z| (wo.m + eta wi.m)^2)` (times `eta^2` for importance) |
//! | `Layered` | pbrt-v4's stochastic layered BSDF: a dielectric coat over a diffuse or conductor base with a medium between (`layered/`); value and density are random-walk estimates, samples carry the walk's throughput |
//! | `Plastic` | GGX dielectric coat `specular F D G / (4 wo.z wi.z)` over a diffuse base `diffuse T(wo.z) T(wi.z) / (pi eta^2 (1 - R_int))`, `T` and `R_int` the rough coat's transmittance and internal reflectance (Mitsuba 3's roughplastic; `rough_interface.rs`) |
//!
//! `eta` is the relative index (transmitted side over `wo`'s side). Microfacet terms: [`super::microfacet`].

use super::TransportMode;
use super::fresnel::{fresnel_conductor, fresnel_schlick};
use super::layered::{LayerSpec, Layers};
use super::microfacet::{ggx_d, ggx_g1, sample_visible, visible_pdf};
use super::rough_dielectric::{refract_about, rough_dielectric_eval, rough_dielectric_eval_pdf, rough_dielectric_pdf};
use super::rough_interface::InterfaceAt;
use crate::math::{Frame, fresnel_dielectric, luminance};
use crate::sampling::warp;
use glam::{Vec2, Vec3, Vec3A};
use std::f32::consts::FRAC_1_PI;

/// A conductor's Fresnel term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Exact, from the complex index of refraction `eta + i k` per RGB channel.
    Complex {
        /// Real part of the conductor's index relative to the outside, per RGB channel.
        eta: Vec3,
        /// Imaginary part (extinction coefficient), per RGB channel.
        k: Vec3,
    },
    /// Schlick's approximation from the reflectance at normal incidence.
    Schlick(Vec3),
}

impl ConductorFresnel {
    /// The reflectance per RGB channel at `cos_i`, the cosine between the incident direction and the (micro)surface
    /// normal.
    #[inline]
    pub fn eval(&self, cos_i: f32) -> Vec3 {
        match self {
            ConductorFresnel::Complex { eta, k } => fresnel_conductor(cos_i, *eta, *k),
            ConductorFresnel::Schlick(r0) => fresnel_schlick(cos_i, *r0),
        }
    }
}

/// One lobe of a BSDF, with its parameters already resolved at the hit (textures looked up, blend weights applied).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    /// Lambertian reflection, `albedo / pi`.
    Diffuse {
        /// Reflectance per RGB channel (the hemispherical albedo, normally in `[0, 1]`).
        albedo: Vec3,
    },
    /// Lambertian reflection and Lambertian transmission to the other side.
    DiffuseTransmission {
        /// Reflectance per RGB channel.
        r: Vec3,
        /// Transmittance per RGB channel.
        t: Vec3,
    },
    /// A thin dielectric slab: Fresnel reflection with the slab's inter-reflections, transmission straight
    /// through (delta).
    ThinDielectric {
        /// Filter on the reflected part, per RGB channel.
        r: Vec3,
        /// Filter on the transmitted part, per RGB channel.
        t: Vec3,
        /// The slab's index of refraction over the outside's.
        eta: f32,
    },
    /// Energy-normalised Phong lobe about the mirror direction of `wo`.
    Phong {
        /// Specular reflectance per RGB channel.
        ks: Vec3,
        /// Phong exponent (0 or more; larger is sharper).
        exponent: f32,
    },
    /// The 6.837 course's unnormalised Blinn-Phong term, `ks (n.h)^e / (pi wi.z)`.
    Blinn6837 {
        /// Specular colour per RGB channel.
        ks: Vec3,
        /// Blinn-Phong exponent `e` on `n.h` (0 or more).
        exponent: f32,
    },
    /// Ideal mirror reflection without Fresnel (delta).
    Mirror {
        /// Reflectance per RGB channel.
        r: Vec3,
    },
    /// Smooth Fresnel dielectric: reflection and refraction (delta).
    Dielectric {
        /// Filter on the reflected part, per RGB channel.
        r: Vec3,
        /// Filter on the refracted part, per RGB channel.
        t: Vec3,
        /// Relative index of refraction, transmitted side over `wo`'s side.
        eta: f32,
    },
    /// The 6.837 course's refraction: no Fresnel, no reflected part, nothing under total internal reflection
    /// (delta).
    CourseRefraction {
        /// Filter on the refracted radiance, per RGB channel.
        t: Vec3,
        /// Relative index of refraction, transmitted side over `wo`'s side.
        eta: f32,
    },
    /// GGX conductor (delta when `alpha` is 0).
    Conductor {
        /// GGX width, 0 (smooth) or in `[1e-3, 1]`.
        alpha: f32,
        /// Fresnel reflectance: exact from a complex index, or Schlick's approximation.
        fresnel: ConductorFresnel,
        /// Factor on the reflectance per RGB channel (Mitsuba's `specular_reflectance`), blend weight included.
        scale: Vec3,
    },
    /// GGX rough dielectric: microfacet reflection and transmission (Walter et al. 2007).
    RoughDielectric {
        /// GGX width, in `[1e-3, 1]` (alpha 0 is [`Lobe::Dielectric`]).
        alpha: f32,
        /// Filter on the reflected part, per RGB channel.
        r: Vec3,
        /// Filter on the transmitted part, per RGB channel.
        t: Vec3,
        /// Relative index of refraction, transmitted side over `wo`'s side.
        eta: f32,
    },
    /// A diffuse base under a GGX dielectric coat (Mitsuba's rough plastic).
    Plastic {
        /// GGX width of the coat, in `[1e-3, 1]`.
        alpha: f32,
        /// The coat's index of refraction (over the outside).
        eta: f32,
        /// The base's albedo per RGB channel.
        diffuse: Vec3,
        /// Filter on the coat's specular reflection, per RGB channel.
        specular: Vec3,
        /// The rough coat's transmittance `T(mu)` and internal reflectance `R_int` at `alpha`.
        coat: InterfaceAt,
    },
    /// pbrt-v4's layered BSDF (`coateddiffuse`, `coatedconductor`): a dielectric coat over a base, evaluated
    /// and sampled by random walks between them ([`super::layered`]).
    Layered {
        /// The coat's GGX width (smooth below 1e-3).
        coat_alpha: f32,
        /// A diffuse base's reflectance, or a conductor base's `eta` relative to the coat, per RGB channel.
        base: Vec3,
        /// A conductor base's `k` relative to the coat (0 for a diffuse base).
        base_k: Vec3,
        /// A conductor base's GGX width (smooth below 1e-3).
        base_alpha: f32,
        /// The medium's single-scattering albedo between coat and base (0: no medium).
        albedo: Vec3,
        /// Factor on the whole lobe (a blend weight).
        scale: f32,
        /// The material's constant parameters.
        spec: &'static LayerSpec,
    },
}

/// A direction drawn from one lobe; `weight` is the throughput `f |cos| / p` of delta lobes and layered walks
/// (unused otherwise).
#[derive(Clone, Copy, Debug)]
pub struct LobeSample {
    /// The drawn direction, unit length, in the local shading frame.
    pub wi: Vec3A,
    /// `f |cos| / p` per RGB channel for delta lobes and walks; zero (and unused) for the others, whose caller
    /// evaluates value and density itself.
    pub weight: Vec3,
    /// True when the direction is a delta direction (a delta lobe's, or a walk that met only specular events).
    pub delta: bool,
    /// True when `weight` is the sample's throughput (delta lobes and layered walks): the lobe's value and
    /// density at `wi` are estimates, not what produced the sample.
    pub weighted: bool,
}

impl LobeSample {
    /// A smooth lobe's direction (its caller evaluates value and density).
    #[inline]
    fn smooth(wi: Vec3A) -> Self {
        LobeSample { wi, weight: Vec3::ZERO, delta: false, weighted: false }
    }

    /// A delta lobe's direction with its throughput.
    #[inline]
    fn delta(wi: Vec3A, weight: Vec3) -> Self {
        LobeSample { wi, weight, delta: true, weighted: true }
    }
}

#[inline]
fn reflect_z(w: Vec3A) -> Vec3A {
    Vec3A::new(-w.x, -w.y, w.z)
}

/// Reflect `w` about the unit vector `m`.
#[inline]
fn reflect_about(w: Vec3A, m: Vec3A) -> Vec3A {
    2.0 * w.dot(m) * m - w
}

impl Lobe {
    /// True for lobes concentrated on single directions (mirror, smooth dielectric, smooth conductor).
    #[inline]
    pub fn is_delta(&self) -> bool {
        match self {
            Lobe::Mirror { .. }
            | Lobe::Dielectric { .. }
            | Lobe::CourseRefraction { .. }
            | Lobe::ThinDielectric { .. } => true,
            Lobe::Conductor { alpha, .. } => *alpha == 0.0,
            Lobe::Layered { .. } => self.layers().is_some_and(|l| l.is_delta()),
            _ => false,
        }
    }

    /// The layered lobe's BSDF (`None` for other lobes).
    #[inline]
    pub fn layers(&self) -> Option<Layers> {
        match *self {
            Lobe::Layered { coat_alpha, base, base_k, base_alpha, albedo, spec, .. } => {
                Some(Layers::new(spec, coat_alpha, base, base_k, base_alpha, albedo))
            }
            _ => None,
        }
    }

    /// Probability that [`Lobe::sample`] returns a delta direction for a lobe number drawn uniformly, seen from
    /// `wo` (local): 1 for delta lobes, the smooth coat's mirror reflection for a layered lobe, 0 otherwise. The
    /// choice depends on the lobe number only: a lobe number below this probability gives the delta direction.
    #[inline]
    pub fn delta_probability(&self, wo: Vec3A) -> f32 {
        if self.is_delta() {
            return 1.0;
        }
        match self.layers() {
            Some(l) => l.coat_mirror_probability(wo),
            None => 0.0,
        }
    }

    /// The relative index of refraction (transmitted side over `wo`'s) a refraction through this lobe crosses,
    /// for lobes whose radiance transmission is scaled by `1/eta^2` (smooth and rough dielectrics); 1 otherwise.
    #[inline]
    pub fn radiance_eta(&self) -> f32 {
        match self {
            Lobe::Dielectric { eta, .. } | Lobe::RoughDielectric { eta, .. } => *eta,
            _ => 1.0,
        }
    }

    /// The lobe times `w` (a blend weight).
    pub fn scaled(self, w: f32) -> Lobe {
        match self {
            Lobe::Diffuse { albedo } => Lobe::Diffuse { albedo: albedo * w },
            Lobe::DiffuseTransmission { r, t } => Lobe::DiffuseTransmission { r: r * w, t: t * w },
            Lobe::ThinDielectric { r, t, eta } => Lobe::ThinDielectric { r: r * w, t: t * w, eta },
            Lobe::Phong { ks, exponent } => Lobe::Phong { ks: ks * w, exponent },
            Lobe::Blinn6837 { ks, exponent } => Lobe::Blinn6837 { ks: ks * w, exponent },
            Lobe::Mirror { r } => Lobe::Mirror { r: r * w },
            Lobe::Dielectric { r, t, eta } => Lobe::Dielectric { r: r * w, t: t * w, eta },
            Lobe::CourseRefraction { t, eta } => Lobe::CourseRefraction { t: t * w, eta },
            Lobe::Conductor { alpha, fresnel, scale } => Lobe::Conductor { alpha, fresnel, scale: scale * w },
            Lobe::RoughDielectric { alpha, r, t, eta } => Lobe::RoughDielectric { alpha, r: r * w, t: t * w, eta },
            Lobe::Plastic { alpha, eta, diffuse, specular, coat } => {
                Lobe::Plastic { alpha, eta, diffuse: diffuse * w, specular: specular * w, coat }
            }
            Lobe::Layered { coat_alpha, base, base_k, base_alpha, albedo, scale, spec } => {
                Lobe::Layered { coat_alpha, base, base_k, base_alpha, albedo, scale: scale * w, spec }
            }
        }
    }

    /// Add `other` into `self` when both are the same lobe up to their (linear) colours. Returns false otherwise.
    pub fn merge(&mut self, other: &Lobe) -> bool {
        match (self, other) {
            (Lobe::Diffuse { albedo: a }, Lobe::Diffuse { albedo: b }) => *a += *b,
            (Lobe::DiffuseTransmission { r, t }, Lobe::DiffuseTransmission { r: r2, t: t2 }) => {
                *r += *r2;
                *t += *t2;
            }
            (Lobe::Phong { ks: a, exponent: e }, Lobe::Phong { ks: b, exponent: f }) if e == f => *a += *b,
            (Lobe::Blinn6837 { ks: a, exponent: e }, Lobe::Blinn6837 { ks: b, exponent: f }) if e == f => *a += *b,
            (Lobe::Mirror { r: a }, Lobe::Mirror { r: b }) => *a += *b,
            (Lobe::Dielectric { r, t, eta }, Lobe::Dielectric { r: r2, t: t2, eta: e2 }) if eta == e2 => {
                *r += *r2;
                *t += *t2;
            }
            (Lobe::CourseRefraction { t, eta }, Lobe::CourseRefraction { t: t2, eta: e2 }) if eta == e2 => *t += *t2,
            (Lobe::Conductor { alpha, fresnel, scale }, Lobe::Conductor { alpha: a2, fresnel: f2, scale: s2 })
                if alpha == a2 && fresnel == f2 =>
            {
                *scale += *s2
            }
            _ => return false,
        }
        true
    }

    /// Probability weight of choosing this lobe when sampling (about its albedo seen from `wo`); 0 drops it.
    pub fn selection_weight(&self, wo: Vec3A) -> f32 {
        let w = match self {
            Lobe::Diffuse { albedo } => luminance(*albedo),
            Lobe::DiffuseTransmission { r, t } => luminance(*r) + luminance(*t),
            Lobe::ThinDielectric { r, t, eta } => {
                let f = thin_reflectance(wo.z, *eta);
                f * luminance(*r) + (1.0 - f) * luminance(*t)
            }
            Lobe::Phong { ks, .. } | Lobe::Blinn6837 { ks, .. } => luminance(*ks),
            Lobe::Mirror { r } => luminance(*r),
            Lobe::Dielectric { r, t, eta } => {
                let f = fresnel_dielectric(wo.z, *eta);
                f * luminance(*r) + (1.0 - f) * luminance(*t)
            }
            Lobe::CourseRefraction { t, .. } => luminance(*t),
            Lobe::Conductor { fresnel, scale, .. } => luminance(fresnel.eval(wo.z) * *scale),
            Lobe::RoughDielectric { r, t, eta, .. } => {
                let f = fresnel_dielectric(wo.z, *eta);
                f * luminance(*r) + (1.0 - f) * luminance(*t)
            }
            Lobe::Plastic { eta, diffuse, specular, .. } => {
                let f = fresnel_dielectric(wo.z, *eta);
                f * luminance(*specular) + (1.0 - f) * luminance(*diffuse)
            }
            // About the coat's reflection plus what the base returns through it.
            Lobe::Layered { base, scale, spec, .. } => {
                let f = fresnel_dielectric(wo.z.abs(), spec.eta);
                let b = match spec.base {
                    super::layered::LayerBase::Diffuse => luminance(*base),
                    super::layered::LayerBase::Conductor => 1.0,
                };
                *scale * (f + (1.0 - f) * b)
            }
        };
        if w.is_finite() { w.max(0.0) } else { 0.0 }
    }

    /// The lobe's value `f(wo, wi)` (0 for delta lobes).
    #[inline]
    pub fn eval(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> Vec3 {
        let reflect = wo.z > 0.0 && wi.z > 0.0;
        match *self {
            Lobe::Diffuse { albedo } => {
                if reflect {
                    albedo * FRAC_1_PI
                } else {
                    Vec3::ZERO
                }
            }
            Lobe::Phong { ks, exponent } => {
                let c = reflect_z(wo).dot(wi);
                if reflect && c > 0.0 {
                    ks * ((exponent + 2.0) * 0.5 * FRAC_1_PI * c.powf(exponent))
                } else {
                    Vec3::ZERO
                }
            }
            Lobe::Blinn6837 { ks, exponent } => {
                if !reflect {
                    return Vec3::ZERO;
                }
                let cos_h = (wo + wi).normalize_or_zero().z;
                if cos_h > 0.0 { ks * (cos_h.powf(exponent) * FRAC_1_PI / wi.z) } else { Vec3::ZERO }
            }
            Lobe::DiffuseTransmission { r, t } => {
                if wo.z * wi.z > 0.0 {
                    r * FRAC_1_PI
                } else if wo.z * wi.z < 0.0 {
                    t * FRAC_1_PI
                } else {
                    Vec3::ZERO
                }
            }
            Lobe::Mirror { .. }
            | Lobe::Dielectric { .. }
            | Lobe::CourseRefraction { .. }
            | Lobe::ThinDielectric { .. } => Vec3::ZERO,
            Lobe::Conductor { alpha, fresnel, scale } => {
                if !reflect || alpha == 0.0 {
                    return Vec3::ZERO;
                }
                let h = (wo + wi).normalize();
                let g = ggx_g1(wo, h, alpha) * ggx_g1(wi, h, alpha);
                fresnel.eval(wo.dot(h)) * scale * (ggx_d(h, alpha) * g / (4.0 * wo.z * wi.z))
            }
            Lobe::RoughDielectric { alpha, r, t, eta } => rough_dielectric_eval(alpha, r, t, eta, wo, wi, mode),
            Lobe::Plastic { alpha, eta, diffuse, specular, coat } => {
                if !reflect {
                    return Vec3::ZERO;
                }
                let h = (wo + wi).normalize();
                let g = ggx_g1(wo, h, alpha) * ggx_g1(wi, h, alpha);
                let fs = fresnel_dielectric(wo.dot(h), eta) * ggx_d(h, alpha) * g / (4.0 * wo.z * wi.z);
                let t = coat.transmittance(wo.z) * coat.transmittance(wi.z);
                specular * fs + diffuse * (t * FRAC_1_PI / (eta * eta * (1.0 - coat.internal_reflectance())))
            }
            Lobe::Layered { scale, .. } => match self.layers() {
                Some(l) if wo.z * wi.z > 0.0 => l.f(wo, wi, mode) * scale,
                _ => Vec3::ZERO,
            },
        }
    }

    /// `(eval, pdf)` of one direction together, bit for bit what [`Lobe::eval`] and [`Lobe::pdf`] return: the
    /// microfacet lobes compute the half vector, `D` and `G1(wo)` once instead of twice (next-event estimation
    /// with MIS and BSDF sampling need both).
    #[inline(always)]
    pub fn eval_pdf(&self, wo: Vec3A, wi: Vec3A, mode: TransportMode) -> (Vec3, f32) {
        match *self {
            // The common case inline (`eval` and `pdf` of the lobe, without their calls and second dispatch).
            Lobe::Diffuse { albedo } => {
                if wo.z > 0.0 && wi.z > 0.0 {
                    (albedo * FRAC_1_PI, warp::cosine_hemisphere_pdf(wi))
                } else {
                    (Vec3::ZERO, 0.0)
                }
            }
            Lobe::Conductor { alpha, fresnel, scale } if alpha != 0.0 => {
                if !(wo.z > 0.0 && wi.z > 0.0) {
                    return (Vec3::ZERO, 0.0);
                }
                let h = (wo + wi).normalize();
                let (g1o, d) = (ggx_g1(wo, h, alpha), ggx_d(h, alpha));
                let g = g1o * ggx_g1(wi, h, alpha);
                let f = fresnel.eval(wo.dot(h)) * scale * (d * g / (4.0 * wo.z * wi.z));
                // `visible_pdf(wo, h) / (4 wo.h)`, its factors shared with `f`.
                let pdf = g1o * wo.dot(h).max(0.0) * d / wo.z / (4.0 * wo.dot(h));
                (f, pdf)
            }
            Lobe::RoughDielectric { alpha, r, t, eta } => rough_dielectric_eval_pdf(alpha, r, t, eta, wo, wi, mode),
            _ => (self.eval(wo, wi, mode), self.pdf(wo, wi)),
        }
    }

    /// Density (solid angle) with which [`Lobe::sample`] draws `wi` (0 for delta lobes).
    #[inline]
    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let reflect = wo.z > 0.0 && wi.z > 0.0;
        match *self {
            Lobe::Diffuse { .. } => {
                if reflect {
                    warp::cosine_hemisphere_pdf(wi)
                } else {
                    0.0
                }
            }
            Lobe::Phong { exponent, .. } | Lobe::Blinn6837 { exponent, .. } => {
                if wo.z <= 0.0 {
                    return 0.0;
                }
                warp::phong_lobe_pdf(Frame::from_normal(reflect_z(wo)).to_local(wi), exponent)
            }
            Lobe::DiffuseTransmission { r, t } => {
                if wo.z == 0.0 || wi.z == 0.0 {
                    return 0.0;
                }
                let pr = diffuse_reflection_probability(r, t);
                let side = if wo.z * wi.z > 0.0 { pr } else { 1.0 - pr };
                side * wi.z.abs() * FRAC_1_PI
            }
            Lobe::Mirror { .. }
            | Lobe::Dielectric { .. }
            | Lobe::CourseRefraction { .. }
            | Lobe::ThinDielectric { .. } => 0.0,
            Lobe::Conductor { alpha, .. } => {
                if !reflect || alpha == 0.0 {
                    return 0.0;
                }
                let h = (wo + wi).normalize();
                visible_pdf(wo, h, alpha) / (4.0 * wo.dot(h))
            }
            Lobe::RoughDielectric { alpha, eta, .. } => rough_dielectric_pdf(alpha, eta, wo, wi),
            Lobe::Plastic { alpha, eta, diffuse, specular, .. } => {
                if !reflect {
                    return 0.0;
                }
                let ps = plastic_specular_probability(wo, eta, diffuse, specular);
                let h = (wo + wi).normalize();
                ps * visible_pdf(wo, h, alpha) / (4.0 * wo.dot(h)) + (1.0 - ps) * warp::cosine_hemisphere_pdf(wi)
            }
            // The walk's density estimate is that of radiance transport either way.
            Lobe::Layered { .. } => match self.layers() {
                Some(l) if wo.z * wi.z > 0.0 => l.pdf(wo, wi, TransportMode::Radiance),
                _ => 0.0,
            },
        }
    }

    /// Draw a direction: `uc` in [0, 1) chooses between a lobe's parts (reflection or refraction), `u` places it.
    /// `None` when the direction falls where the lobe has no value (e.g. below the surface).
    #[inline(always)]
    pub fn sample(&self, wo: Vec3A, uc: f32, u: Vec2, mode: TransportMode) -> Option<LobeSample> {
        if wo.z <= 0.0 && !matches!(self, Lobe::Dielectric { .. } | Lobe::CourseRefraction { .. }) {
            return None;
        }
        let dir = |wi: Vec3A| Some(LobeSample::smooth(wi));
        match *self {
            Lobe::Diffuse { .. } => dir(warp::cosine_hemisphere(u)),
            Lobe::DiffuseTransmission { r, t } => {
                let w = warp::cosine_hemisphere(u);
                dir(if uc < diffuse_reflection_probability(r, t) { w } else { Vec3A::new(w.x, w.y, -w.z) })
            }
            Lobe::ThinDielectric { r, t, eta } => {
                let f = thin_reflectance(wo.z, eta);
                Some(if uc < f { LobeSample::delta(reflect_z(wo), r) } else { LobeSample::delta(-wo, t) })
            }
            Lobe::Phong { exponent, .. } | Lobe::Blinn6837 { exponent, .. } => {
                dir(Frame::from_normal(reflect_z(wo)).to_world(warp::phong_lobe(u, exponent)))
            }
            Lobe::Mirror { r } => Some(LobeSample::delta(reflect_z(wo), r)),
            Lobe::Dielectric { r, t, eta } => {
                let f = fresnel_dielectric(wo.z.abs(), eta);
                if uc < f {
                    return Some(LobeSample::delta(reflect_z(wo), r));
                }
                let wi = crate::math::refract(wo, Vec3A::Z, eta)?.normalize();
                let scale = match mode {
                    TransportMode::Radiance => 1.0 / (eta * eta),
                    TransportMode::Importance => 1.0,
                };
                Some(LobeSample::delta(wi, t * scale))
            }
            Lobe::CourseRefraction { t, eta } => {
                let wi = crate::math::refract(wo, Vec3A::Z, eta)?.normalize();
                Some(LobeSample::delta(wi, t))
            }
            Lobe::Conductor { alpha, fresnel, scale } => {
                if alpha == 0.0 {
                    return Some(LobeSample::delta(reflect_z(wo), fresnel.eval(wo.z) * scale));
                }
                let m = sample_visible(wo, alpha, u);
                dir(reflect_about(wo, m))
            }
            Lobe::RoughDielectric { alpha, eta, .. } => {
                let m = sample_visible(wo, alpha, u);
                let f = fresnel_dielectric(wo.dot(m), eta);
                // A reflection must stay above the surface and a refraction go below it (microfacets tilted far
                // enough can send either to the wrong side; the pdf counts them on the side they land).
                let wi = if uc < f { reflect_about(wo, m) } else { refract_about(wo, m, eta)? };
                if (wi.z > 0.0) != (uc < f) {
                    return None;
                }
                dir(wi)
            }
            Lobe::Plastic { alpha, eta, diffuse, specular, .. } => {
                if uc < plastic_specular_probability(wo, eta, diffuse, specular) {
                    dir(reflect_about(wo, sample_visible(wo, alpha, u)))
                } else {
                    dir(warp::cosine_hemisphere(u))
                }
            }
            Lobe::Layered { scale, .. } => {
                let s = self.layers()?.sample(wo, uc, u, mode)?;
                Some(LobeSample { wi: s.wi, weight: s.weight * scale, delta: s.specular, weighted: true })
            }
        }
    }

    /// Every direction a delta lobe scatters `wo` into, with its throughput and the lobe's colour (for Whitted
    /// recursion, which follows all of them): `(wi, weight, filter)`.
    pub fn delta_branches(&self, wo: Vec3A, mut f: impl FnMut(Vec3A, Vec3, Vec3)) {
        match *self {
            Lobe::Mirror { r } => f(reflect_z(wo), r, r),
            Lobe::Conductor { alpha: 0.0, fresnel, scale } => f(reflect_z(wo), fresnel.eval(wo.z) * scale, scale),
            Lobe::Dielectric { r, t, eta } => {
                let fr = fresnel_dielectric(wo.z.max(0.0), eta);
                if fr > 0.0 {
                    f(reflect_z(wo), r * fr, t);
                }
                if fr < 1.0
                    && let Some(wi) = crate::math::refract(wo, Vec3A::Z, eta)
                {
                    // Radiance is scaled by 1/eta^2 across the interface (it cancels for closed objects).
                    f(wi.normalize(), t * ((1.0 - fr) / (eta * eta)), t);
                }
            }
            Lobe::CourseRefraction { t, eta } => {
                if let Some(wi) = crate::math::refract(wo, Vec3A::Z, eta) {
                    f(wi.normalize(), t, t);
                }
            }
            Lobe::ThinDielectric { r, t, eta } => {
                let fr = thin_reflectance(wo.z, eta);
                f(reflect_z(wo), r * fr, r);
                f(-wo, t * (1.0 - fr), t);
            }
            _ => {}
        }
    }
}

/// The reflectance of a thin dielectric slab seen at cosine `cos`: Fresnel's `R` with the slab's inter-reflections,
/// `R + T^2 R / (1 - R^2)` (pbrt-v4's `ThinDielectricBxDF`).
#[inline]
pub fn thin_reflectance(cos: f32, eta: f32) -> f32 {
    let r = fresnel_dielectric(cos.abs(), eta);
    if r < 1.0 { r + (1.0 - r) * (1.0 - r) * r / (1.0 - r * r) } else { 1.0 }
}

/// Probability of sampling a diffuse transmitter's reflection rather than its transmission.
#[inline]
fn diffuse_reflection_probability(r: Vec3, t: Vec3) -> f32 {
    let (a, b) = (luminance(r), luminance(t));
    if a + b > 0.0 { a / (a + b) } else { 0.5 }
}

/// Probability of sampling the plastic's specular coat rather than its base.
#[inline]
pub(super) fn plastic_specular_probability(wo: Vec3A, eta: f32, diffuse: Vec3, specular: Vec3) -> f32 {
    let f = fresnel_dielectric(wo.z, eta);
    let (s, d) = (f * luminance(specular), (1.0 - f) * luminance(diffuse));
    if s + d > 0.0 { s / (s + d) } else { 0.5 }
}
