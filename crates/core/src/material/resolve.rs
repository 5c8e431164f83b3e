//! Material to BSDF at one hit: orient the frame towards the viewer, perturb the shading normal (normal or bump
//! map of the outermost material), then turn the material tree into lobes with textures looked up and blend
//! weights multiplied in. Called once per shading point; no allocation.

use super::normal_map::{BUMP_DELTA, bump_normal, normal_map_normal, tangent_frame};
use super::{CoatBase, ConductorSpec, Material, MaterialKind, MaterialSet, Shading};
use crate::bsdf::{Bsdf, ConductorFresnel, Lobe};
use crate::math::Frame;
use crate::primitives::{Primitives, SurfaceHit};
use crate::texture::{ScalarParam, TexPoint, Texture, TextureSet};
use glam::{Vec2, Vec3A};

/// Smallest non-zero GGX alpha (smaller values are raised to it; exactly 0 means smooth).
const MIN_ALPHA: f32 = 1e-3;

/// The BSDF of the surface at `s` seen from `wo` (unit, pointing away from the surface). `two_sided` overrides
/// every material's sidedness when given (6.837 `-shade_back`). `None` when the surface neither scatters nor has
/// an ambient term towards `wo` (black, or the back of a one-sided material).
#[inline(always)]
pub fn bsdf(
    materials: &MaterialSet,
    textures: &TextureSet,
    prims: &Primitives,
    s: &SurfaceHit,
    wo: Vec3A,
    two_sided: Option<bool>,
) -> Option<Bsdf> {
    let mut out = Bsdf::new(Frame::from_normal(s.ng), s.ng, wo);
    bsdf_into(materials, textures, prims, s, wo, two_sided, &mut out).then_some(out)
}

/// [`bsdf`] written into `out` (its previous lobes are discarded), so a path loop reuses one `Bsdf` instead of
/// moving a new one out of every hit; false when the surface neither scatters nor has an ambient term.
#[inline(always)]
pub fn bsdf_into(
    materials: &MaterialSet,
    textures: &TextureSet,
    prims: &Primitives,
    s: &SurfaceHit,
    wo: Vec3A,
    two_sided: Option<bool>,
    out: &mut Bsdf,
) -> bool {
    let m = &materials[s.material as usize];
    let front = wo.dot(s.ng) >= 0.0;
    let side = Side { front, two_sided };
    let (ng, mut ns) = if front { (s.ng, s.ns) } else { (-s.ng, -s.ns) };
    let bsdf = out;
    if let Some(albedo) = materials.lambert(s.material) {
        // The common case (every wall of a Cornell box): one constant Lambertian lobe, classified when the scene
        // was built; no texture lookups.
        bsdf.reset(Frame::from_normal(facing(ns, ng, wo)), ng, wo);
        return side.shades(m) && bsdf.set_lambert(albedo);
    }
    let at = TexPoint { uv: s.uv, p: s.p };
    let top = match &m.kind {
        MaterialKind::NormalMap { base, texture, strength, flip_green } => {
            let (t, b) = tangent_frame(s.ns, s.dpdu, s.dpdv, prims.mesh_tangent(s));
            let c = match textures.get(*texture) {
                Texture::Image(map) => map.eval(s.uv),
                Texture::Solid(_) | Texture::UvChecker { .. } => glam::Vec3::new(0.5, 0.5, 1.0),
            };
            let n = normal_map_normal(s.ns, t, b, c, *strength, *flip_green, wo);
            ns = if front { n } else { -n };
            &materials[*base as usize]
        }
        MaterialKind::Bump { base, height } => {
            let h0 = textures.scalar(height, &at);
            let hu = textures
                .scalar(height, &TexPoint { uv: s.uv + Vec2::new(BUMP_DELTA, 0.0), p: s.p + BUMP_DELTA * s.dpdu });
            let hv = textures
                .scalar(height, &TexPoint { uv: s.uv + Vec2::new(0.0, BUMP_DELTA), p: s.p + BUMP_DELTA * s.dpdv });
            let n = bump_normal(s.ns, s.dpdu, s.dpdv, (hu - h0) / BUMP_DELTA, (hv - h0) / BUMP_DELTA);
            ns = facing(if front { n } else { -n }, ng, wo);
            &materials[*base as usize]
        }
        _ => {
            ns = facing(ns, ng, wo);
            m
        }
    };
    bsdf.reset(Frame::from_normal(ns), ng, wo);
    push_lobes(materials, textures, top, &at, side, 1.0, bsdf);
    bsdf.prepare()
}

/// The shading normal `ns`, or the geometric `ng` where `ns` turns away from `wo` (a shading frame must face the
/// viewer).
#[inline(always)]
fn facing(ns: Vec3A, ng: Vec3A, wo: Vec3A) -> Vec3A {
    if ns.dot(wo) <= 0.0 { ng } else { ns }
}

#[derive(Clone, Copy)]
struct Side {
    /// `wo` is on the side the primitive's normal points to.
    front: bool,
    two_sided: Option<bool>,
}

impl Side {
    /// Whether a material with this sidedness reflects towards `wo`.
    #[inline]
    fn shades(self, m: &Material) -> bool {
        self.front || self.two_sided.unwrap_or(m.two_sided)
    }

    /// Relative index `eta_t / eta_i` for a ray leaving `wo`'s side through an interface with `ior` inside.
    #[inline]
    fn eta(self, ior: f32) -> f32 {
        if self.front { ior } else { 1.0 / ior }
    }
}

#[inline]
fn alpha(textures: &TextureSet, p: &ScalarParam, at: &TexPoint) -> f32 {
    let a = textures.scalar(p, at);
    if a.is_nan() || a <= 0.0 { 0.0 } else { a.clamp(MIN_ALPHA, 1.0) }
}

/// Add material `m`'s lobes, times `w`, to `bsdf`.
fn push_lobes(
    materials: &[Material],
    textures: &TextureSet,
    m: &Material,
    at: &TexPoint,
    side: Side,
    w: f32,
    bsdf: &mut Bsdf,
) {
    let color = |c| textures.color(c, at) * w;
    match &m.kind {
        MaterialKind::Phong(p) => {
            let shades = side.shades(m);
            if shades {
                if !p.ambient.is_zero() {
                    bsdf.add_ambient(color(&p.ambient));
                }
                if !p.diffuse.is_zero() {
                    bsdf.push(Lobe::Diffuse { albedo: color(&p.diffuse) });
                }
                if !p.specular.is_zero() {
                    let (ks, exponent) = (color(&p.specular), textures.scalar(&p.exponent, at).max(0.0));
                    bsdf.push(match p.shading {
                        Shading::Physical => Lobe::Phong { ks, exponent },
                        Shading::Mit6837 => Lobe::Blinn6837 { ks, exponent },
                    });
                }
                if !p.reflective.is_zero() {
                    bsdf.push(Lobe::Mirror { r: color(&p.reflective) });
                }
            }
            if !p.transparent.is_zero() {
                let t = color(&p.transparent);
                let eta = side.eta(p.ior);
                bsdf.push(match p.shading {
                    Shading::Physical => Lobe::Dielectric { r: t, t, eta },
                    Shading::Mit6837 => Lobe::CourseRefraction { t, eta },
                });
            }
        }
        MaterialKind::Conductor { alpha: a, fresnel, scale } => {
            if side.shades(m) {
                let fresnel = match fresnel {
                    ConductorSpec::Complex { eta, k } => ConductorFresnel::Complex { eta: *eta, k: *k },
                    ConductorSpec::Schlick(r0) => ConductorFresnel::Schlick(textures.color(r0, at)),
                };
                bsdf.push(Lobe::Conductor { alpha: alpha(textures, a, at), fresnel, scale: color(scale) });
            }
        }
        MaterialKind::Dielectric { alpha: a, ior, reflectance, transmittance } => {
            let (r, t, eta) = (color(reflectance), color(transmittance), side.eta(*ior));
            let a = alpha(textures, a, at);
            bsdf.push(if a == 0.0 {
                Lobe::Dielectric { r, t, eta }
            } else {
                Lobe::RoughDielectric { alpha: a, r, t, eta }
            });
        }
        MaterialKind::Plastic { alpha: a, ior, diffuse, specular, interface } => {
            if side.shades(m) {
                let alpha = alpha(textures, a, at).max(MIN_ALPHA);
                bsdf.push(Lobe::Plastic {
                    alpha,
                    eta: *ior,
                    diffuse: color(diffuse),
                    specular: color(specular),
                    coat: interface.at(alpha),
                });
            }
        }
        MaterialKind::DiffuseTransmission { reflectance, transmittance } => {
            bsdf.push(Lobe::DiffuseTransmission { r: color(reflectance), t: color(transmittance) });
        }
        MaterialKind::ThinDielectric { ior, reflectance, transmittance } => {
            bsdf.push(Lobe::ThinDielectric { r: color(reflectance), t: color(transmittance), eta: *ior });
        }
        MaterialKind::Coated { coat_alpha, base, albedo, spec } => {
            if side.shades(m) {
                bsdf.push(coated_lobe(textures, at, coat_alpha, base, albedo, spec, w));
            }
        }
        MaterialKind::Blend { a, b, weight } => {
            let t = textures.scalar(weight, at);
            let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
            if t < 1.0 {
                push_lobes(materials, textures, &materials[*a as usize], at, side, w * (1.0 - t), bsdf);
            }
            if t > 0.0 {
                push_lobes(materials, textures, &materials[*b as usize], at, side, w * t, bsdf);
            }
        }
        // Validated away at load time: maps only wrap the outermost material.
        MaterialKind::NormalMap { base, .. } | MaterialKind::Bump { base, .. } => {
            push_lobes(materials, textures, &materials[*base as usize], at, side, w, bsdf)
        }
    }
}

/// The layered lobe of a [`MaterialKind::Coated`] material at `at`, times `w`.
fn coated_lobe(
    textures: &TextureSet,
    at: &TexPoint,
    coat_alpha: &ScalarParam,
    base: &CoatBase,
    albedo: &crate::texture::ColorParam,
    spec: &'static crate::bsdf::layered::LayerSpec,
    w: f32,
) -> Lobe {
    let a = alpha(textures, coat_alpha, at);
    let coat_alpha = if a < crate::bsdf::NEAR_SPECULAR_ALPHA { 0.0 } else { a };
    let (base, base_k, base_alpha) = match base {
        CoatBase::Diffuse(r) => (textures.color(r, at).clamp(glam::Vec3::ZERO, glam::Vec3::ONE), glam::Vec3::ZERO, 0.0),
        CoatBase::Conductor { alpha: ca, fresnel } => {
            let (eta, k) = match fresnel {
                ConductorSpec::Complex { eta, k } => (*eta, *k),
                ConductorSpec::Schlick(r) => {
                    let r = textures.color(r, at).clamp(glam::Vec3::ZERO, glam::Vec3::splat(0.9999));
                    (glam::Vec3::ONE, 2.0 * r.powf(0.5) / (glam::Vec3::ONE - r).powf(0.5))
                }
            };
            let a = textures.scalar(ca, at);
            let a = if a.is_nan() || a < 1e-3 { 0.0 } else { a.min(1.0) };
            (eta / spec.eta, k / spec.eta, a)
        }
    };
    let albedo = textures.color(albedo, at).clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
    Lobe::Layered { coat_alpha, base, base_k, base_alpha, albedo, scale: w, spec }
}
