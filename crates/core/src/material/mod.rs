//! Materials: what a surface is made of, with parameters that are constants or textures ([`ColorParam`],
//! [`ScalarParam`]). A material is resolved at every hit into a [`crate::bsdf::Bsdf`] by [`bsdf`] (lobes with
//! their textures looked up, blend weights applied, the shading frame perturbed by normal or bump maps); no
//! integrator reads material fields.
//!
//! Kinds (physically based units; a diffuse coefficient is an albedo, BRDF = kd / pi):
//! - `Phong`: Lambert + energy-normalised Phong lobe + ideal mirror + smooth Fresnel dielectric (Lambert, Phong,
//!   Mirror and Glass of the scene format), or the 6.837 course's shading (`Shading::Mit6837`: Blinn-Phong without
//!   normalisation, refraction without Fresnel), with an ambient reflectance for the scene's ambient light;
//! - `Conductor`: GGX rough metal (complex IOR per RGB channel, or a reflectance colour through Schlick); alpha 0
//!   is a smooth metal;
//! - `Dielectric`: GGX rough glass (reflection + transmission, Walter et al. 2007); alpha 0 is smooth glass;
//! - `Plastic`: a diffuse base under a GGX dielectric coat;
//! - `DiffuseTransmission`: Lambertian reflection and transmission (pbrt-v4's `diffusetransmission`);
//! - `ThinDielectric`: a thin slab of glass, reflection with its inter-reflections and straight transmission
//!   (pbrt-v4's `thindielectric`);
//! - `Coated`: pbrt-v4's stochastic layered BSDF, a dielectric coat over a diffuse or conductor base with an
//!   optional medium between (`coateddiffuse`, `coatedconductor`; `bsdf::layered`);
//! - `Blend`: `(1 - w) a + w b` for a scalar weight `w` in [0, 1] (constant or texture: 6.837 checkerboard, noise,
//!   marble and wood; glTF's metallic factor);
//! - `NormalMap`, `Bump`: a base material with its shading normal perturbed by a tangent-space normal map or by the
//!   gradient of a height texture. They wrap the outermost material (one shading frame per BSDF).

pub mod metals;
mod normal_map;
mod resolve;
mod set;

pub use normal_map::{bump_normal, normal_map_normal, tangent_frame};
pub use resolve::{bsdf, bsdf_into};
pub use set::MaterialSet;

/// Index of a material in the scene's material table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialId(pub u32);

use crate::bsdf::MAX_LOBES;
use crate::texture::{ColorParam, ScalarParam};

use glam::Vec3;

/// How a Phong-family material's terms are evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// Energy-normalised Phong lobe, Fresnel-weighted dielectric.
    #[default]
    Physical,
    /// The 6.837 course's conventions, for its scenes: radiance `kd c cos + ks (n.h)^e c` per light of colour `c`
    /// (Blinn-Phong half vector, no normalisation, no cosine on the specular term), mirror and refraction without
    /// Fresnel (refracted radiance is `transparent` times the radiance behind, nothing under total internal
    /// reflection).
    Mit6837,
}

/// The Phong family: Lambert, Phong, Mirror, Glass and the 6.837 course's material are special cases.
#[derive(Clone, Debug, PartialEq)]
pub struct PhongParams {
    /// Reflectance for the scene's ambient radiance (0 for physically based scenes).
    pub ambient: ColorParam,
    /// Lambertian albedo.
    pub diffuse: ColorParam,
    /// Phong specular reflectance.
    pub specular: ColorParam,
    /// Phong exponent.
    pub exponent: ScalarParam,
    /// Ideal mirror reflectance (no Fresnel).
    pub reflective: ColorParam,
    /// Smooth dielectric transmittance filter (reflection/refraction weighted by Fresnel).
    pub transparent: ColorParam,
    /// Index of refraction of the inside (the side opposite the geometric normal).
    pub ior: f32,
    /// Physically based terms, or the 6.837 course's.
    pub shading: Shading,
}

impl Default for PhongParams {
    /// Black: every term 0, exponent 1, ior 1.5.
    fn default() -> Self {
        PhongParams {
            ambient: ColorParam::ZERO,
            diffuse: ColorParam::ZERO,
            specular: ColorParam::ZERO,
            exponent: ScalarParam::Const(1.0),
            reflective: ColorParam::ZERO,
            transparent: ColorParam::ZERO,
            ior: 1.5,
            shading: Shading::Physical,
        }
    }
}

/// A conductor's Fresnel term as the material states it.
#[derive(Clone, Debug, PartialEq)]
pub enum ConductorSpec {
    /// Complex index of refraction per RGB channel.
    Complex {
        /// Real part of the index, per RGB channel.
        eta: Vec3,
        /// Imaginary part (extinction coefficient), per RGB channel.
        k: Vec3,
    },
    /// Reflectance at normal incidence (Schlick's approximation), may be textured.
    Schlick(ColorParam),
}

/// The base under a [`MaterialKind::Coated`] coat.
#[derive(Clone, Debug, PartialEq)]
pub enum CoatBase {
    /// A Lambertian base of this reflectance (clamped to `[0, 1]`).
    Diffuse(ColorParam),
    /// A GGX conductor; a reflectance (`ConductorSpec::Schlick`) becomes the conductor with that reflectance at
    /// normal incidence (`eta = 1`, `k = 2 sqrt(r) / sqrt(1 - r)`, as pbrt does).
    Conductor {
        /// GGX width (smooth below 1e-3).
        alpha: ScalarParam,
        /// Its index relative to the outside (divided by the coat's at each hit).
        fresnel: ConductorSpec,
    },
}

/// What a material is made of, with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialKind {
    /// The Phong family (Lambert, Phong, mirror, glass, the 6.837 course's material).
    Phong(PhongParams),
    /// GGX conductor; `scale` multiplies the reflectance (Mitsuba's `specular_reflectance`).
    Conductor {
        /// GGX width: 0 is a smooth metal, otherwise clamped to `[1e-3, 1]` at each hit.
        alpha: ScalarParam,
        /// Fresnel reflectance: a complex index, or a reflectance at normal incidence for Schlick's approximation.
        fresnel: ConductorSpec,
        /// Factor on the reflectance per RGB channel.
        scale: ColorParam,
    },
    /// GGX dielectric with index `ior` inside; reflection and transmission filters.
    Dielectric {
        /// GGX width: 0 is smooth glass, otherwise clamped to `[1e-3, 1]` at each hit.
        alpha: ScalarParam,
        /// Index of refraction of the inside (the side opposite the geometric normal) over the outside.
        ior: f32,
        /// Filter on the reflected part, per RGB channel.
        reflectance: ColorParam,
        /// Filter on the transmitted part, per RGB channel.
        transmittance: ColorParam,
    },
    /// Diffuse base under a GGX dielectric coat of index `ior` (Mitsuba 3's `roughplastic`); `interface` holds
    /// the rough coat's transmittance and internal reflectance for its `alpha`.
    Plastic {
        /// GGX width of the coat, clamped to `[1e-3, 1]` at each hit (the coat is never perfectly smooth).
        alpha: ScalarParam,
        /// Index of refraction of the coat over the outside.
        ior: f32,
        /// The base's albedo per RGB channel.
        diffuse: ColorParam,
        /// Filter on the coat's specular reflection, per RGB channel.
        specular: ColorParam,
        /// The coat's tabulated transmittance and internal reflectance ([`RoughInterface::get`](crate::bsdf::rough_interface::RoughInterface::get) of `ior` and the
        /// constant `alpha`, or of every `alpha` for a textured one).
        interface: &'static crate::bsdf::rough_interface::RoughInterface,
    },
    /// pbrt-v4's layered BSDF: a dielectric coat of GGX width `coat_alpha` over `base`, with a medium of
    /// single-scattering `albedo` between them; the coat's index, the medium's thickness and phase function and
    /// the walks' limits are in `spec`. A coat narrower than the near-specular width
    /// ([`NEAR_SPECULAR_ALPHA`](crate::bsdf::NEAR_SPECULAR_ALPHA), pbrt roughness 1e-4) is smooth, so that
    /// estimators without multiple importance sampling find its mirror reflection.
    Coated {
        /// GGX width of the coat.
        coat_alpha: ScalarParam,
        /// What lies under the coat.
        base: CoatBase,
        /// The medium's single-scattering albedo (0: no medium).
        albedo: ColorParam,
        /// The constant parameters (interned).
        spec: &'static crate::bsdf::layered::LayerSpec,
    },
    /// Lambertian reflection `reflectance / pi` and transmission `transmittance / pi` to the other side; always
    /// two-sided.
    DiffuseTransmission {
        /// Reflectance per RGB channel.
        reflectance: ColorParam,
        /// Transmittance per RGB channel.
        transmittance: ColorParam,
    },
    /// A thin dielectric slab of index `ior`: Fresnel reflection with the slab's inter-reflections summed, the
    /// rest transmitted straight through; always two-sided.
    ThinDielectric {
        /// Index of refraction of the slab over the outside.
        ior: f32,
        /// Filter on the reflected part, per RGB channel.
        reflectance: ColorParam,
        /// Filter on the transmitted part, per RGB channel.
        transmittance: ColorParam,
    },
    /// `(1 - weight) a + weight b`, materials by index.
    Blend {
        /// Index of the material at weight 0.
        a: u32,
        /// Index of the material at weight 1.
        b: u32,
        /// The blend weight, clamped to `[0, 1]` at each hit (NaN counts as 0).
        weight: ScalarParam,
    },
    /// Material `base` with a tangent-space normal map (texture index): `n = normalize(2 c - 1)` with x, y scaled
    /// by `strength` (and y negated by `flip_green`).
    NormalMap {
        /// Index of the wrapped material.
        base: u32,
        /// Index of the normal map in the scene's texture table (an image texture).
        texture: u32,
        /// Factor on the map normal's tangent-plane components (1: as stored).
        strength: f32,
        /// Negate the map's green (y) component before use, for maps authored with the other y convention.
        flip_green: bool,
    },
    /// Material `base` with a height texture: the surface displaced by `height` along its normal.
    Bump {
        /// Index of the wrapped material.
        base: u32,
        /// Displacement along the normal, world units (its uv derivatives tilt the shading normal).
        height: ScalarParam,
    },
}

/// A named material of the scene's table.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name in the scene (used in error messages and by name look-ups).
    pub name: String,
    /// Its kind and parameters.
    pub kind: MaterialKind,
    /// Shade both faces (the shading frame is flipped towards the viewer). One-sided materials reflect nothing
    /// from behind (dielectrics always see both sides).
    pub two_sided: bool,
}

impl Default for Material {
    /// The material of entities that name none: grey Lambert, albedo 0.5.
    fn default() -> Self {
        Material::lambert("default", Vec3::splat(0.5))
    }
}

impl Material {
    /// Whether shading this material reads the surface's texture coordinates or their derivatives: a texture in
    /// any parameter, or a normal or bump map, following blends and wrapped bases (`materials`: the scene's list,
    /// which the indices refer to). Shapes whose coordinates cost a computation per hit (spheres: an `atan2` and an
    /// `acos`) compute them only for materials that read them.
    pub fn uses_surface_coordinates(&self, materials: &[Material]) -> bool {
        self.reads_coordinates(materials, 0)
    }

    fn reads_coordinates(&self, materials: &[Material], depth: u32) -> bool {
        let c = |p: &ColorParam| p.constant().is_none();
        let x = |p: &ScalarParam| p.constant().is_none();
        // Blends nest (never cyclically: the loader rejects that); past this depth, assume they do read them.
        let sub =
            |i: u32| depth > 64 || materials.get(i as usize).is_none_or(|m| m.reads_coordinates(materials, depth + 1));
        match &self.kind {
            MaterialKind::Phong(p) => {
                c(&p.ambient)
                    || c(&p.diffuse)
                    || c(&p.specular)
                    || x(&p.exponent)
                    || c(&p.reflective)
                    || c(&p.transparent)
            }
            MaterialKind::Conductor { alpha, fresnel, scale } => {
                x(alpha) || c(scale) || matches!(fresnel, ConductorSpec::Schlick(f) if c(f))
            }
            MaterialKind::Dielectric { alpha, reflectance, transmittance, .. } => {
                x(alpha) || c(reflectance) || c(transmittance)
            }
            MaterialKind::Plastic { alpha, diffuse, specular, .. } => x(alpha) || c(diffuse) || c(specular),
            MaterialKind::Coated { coat_alpha, base, albedo, .. } => {
                x(coat_alpha)
                    || c(albedo)
                    || match base {
                        CoatBase::Diffuse(r) => c(r),
                        CoatBase::Conductor { alpha, fresnel } => {
                            x(alpha) || matches!(fresnel, ConductorSpec::Schlick(f) if c(f))
                        }
                    }
            }
            MaterialKind::DiffuseTransmission { reflectance, transmittance }
            | MaterialKind::ThinDielectric { reflectance, transmittance, .. } => c(reflectance) || c(transmittance),
            MaterialKind::Blend { a, b, weight } => x(weight) || sub(*a) || sub(*b),
            MaterialKind::NormalMap { .. } | MaterialKind::Bump { .. } => true,
        }
    }

    /// A Phong-family material.
    pub fn phong(name: &str, p: PhongParams) -> Self {
        Material { name: name.to_string(), kind: MaterialKind::Phong(p), two_sided: true }
    }

    /// Black (emitters' material).
    pub fn black(name: &str) -> Self {
        Material::phong(name, PhongParams::default())
    }

    /// A two-sided Lambertian material of `albedo` (linear RGB reflectance).
    pub fn lambert(name: &str, albedo: Vec3) -> Self {
        Material::phong(name, PhongParams { diffuse: ColorParam::Const(albedo), ..PhongParams::default() })
    }

    /// The Phong parameters, for Phong-family materials.
    pub fn phong_params(&self) -> Option<&PhongParams> {
        match &self.kind {
            MaterialKind::Phong(p) => Some(p),
            _ => None,
        }
    }

    /// Materials this one refers to (blend components, wrapped base).
    pub fn children(&self) -> Vec<u32> {
        match &self.kind {
            MaterialKind::Blend { a, b, .. } => vec![*a, *b],
            MaterialKind::NormalMap { base, .. } | MaterialKind::Bump { base, .. } => vec![*base],
            _ => vec![],
        }
    }

    /// True when the material's BSDF needs mesh tangents (a normal map at its top).
    pub fn needs_tangents(&self) -> bool {
        matches!(self.kind, MaterialKind::NormalMap { .. })
    }
}

/// Check a material table: references in range and acyclic, normal/bump maps only at the top of a material (not
/// inside a blend or another map), at most [`MAX_LOBES`] lobes per BSDF once equal lobes are merged. Errors name
/// the material.
pub fn validate(materials: &[Material]) -> Result<(), String> {
    for (i, m) in materials.iter().enumerate() {
        let mut keys = Vec::new();
        lobe_keys(materials, i as u32, 0, true, &mut keys)?;
        keys.sort();
        keys.dedup();
        if keys.len() > MAX_LOBES {
            return Err(format!(
                "material '{}': its blends add up to {} different lobes, more than the {MAX_LOBES} one BSDF holds",
                m.name,
                keys.len()
            ));
        }
    }
    Ok(())
}

/// The lobes a material can produce, as keys: lobes with equal keys merge into one at run time (same kind and
/// equal constant non-linear parameters; a textured exponent or roughness never merges).
fn lobe_keys(ms: &[Material], id: u32, depth: usize, top: bool, out: &mut Vec<String>) -> Result<(), String> {
    let m = ms.get(id as usize).ok_or_else(|| format!("material index {id} out of range"))?;
    if depth > ms.len() {
        return Err(format!("material '{}' refers to itself (through blends or maps)", m.name));
    }
    // Textured parameters never merge: a key no other lobe has.
    let unique = format!("unique {id} {depth} {}", out.len());
    let scalar = |p: &ScalarParam| p.constant().map_or_else(|| unique.clone(), |c| c.to_bits().to_string());
    match &m.kind {
        MaterialKind::Phong(p) => {
            if !p.diffuse.is_zero() {
                out.push("diffuse".into());
            }
            if !p.specular.is_zero() {
                out.push(format!("specular {:?} {}", p.shading, scalar(&p.exponent)));
            }
            if !p.reflective.is_zero() {
                out.push("mirror".into());
            }
            if !p.transparent.is_zero() {
                out.push(format!("dielectric {:?} {}", p.shading, p.ior.to_bits()));
            }
        }
        MaterialKind::Conductor { alpha, fresnel, .. } => {
            let f = match fresnel {
                ConductorSpec::Complex { eta, k } => format!("{eta:?} {k:?}"),
                ConductorSpec::Schlick(c) => c.constant().map_or_else(|| unique.clone(), |c| format!("{c:?}")),
            };
            out.push(format!("conductor {} {f}", scalar(alpha)));
        }
        MaterialKind::DiffuseTransmission { .. } => out.push("diffuse transmission".into()),
        MaterialKind::ThinDielectric { ior, .. } => out.push(format!("thin dielectric {}", ior.to_bits())),
        MaterialKind::Dielectric { .. } | MaterialKind::Plastic { .. } | MaterialKind::Coated { .. } => {
            out.push(unique.clone())
        }
        MaterialKind::Blend { a, b, .. } => {
            lobe_keys(ms, *a, depth + 1, false, out)?;
            lobe_keys(ms, *b, depth + 1, false, out)?;
        }
        MaterialKind::NormalMap { base, .. } | MaterialKind::Bump { base, .. } => {
            if !top {
                return Err(format!(
                    "material '{}': a normal or bump map must wrap the outermost material (not be inside a blend or \
                     another map)",
                    m.name
                ));
            }
            lobe_keys(ms, *base, depth + 1, false, out)?;
        }
    }
    Ok(())
}
