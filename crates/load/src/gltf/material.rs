//! glTF materials as Prism materials (the table is in `docs/guide/import-gltf.md`):
//!
//! - `pbrMetallicRoughness`: `Blend(a: RoughPlastic(diffuse: base, specular: 1, ior: 1.5), b:
//!   RoughConductor(reflectance: base), weight: metallic)`, the specification's own split of its BRDF into a
//!   dielectric (a diffuse base under a Fresnel-weighted GGX coat of index 1.5) and a metal (Schlick Fresnel with
//!   F0 = base colour) mixed by `metallic`; a constant metallic of 0 or 1 keeps one side. Base colour = factor x
//!   texture (sRGB); metallic = factor x texture B, roughness r = factor x texture G (linear); GGX `alpha = r^2`
//!   as the specification defines it (a textured roughness is squared texel by texel);
//! - `normalTexture`: `NormalMap(strength: scale, flip_green: true)` (Prism's bitangent points down the image,
//!   glTF's green up; supplied tangents get their sign flipped to Prism's convention);
//! - emission = `emissiveFactor x emissiveTexture (sRGB) x KHR_materials_emissive_strength`: an area light on
//!   the primitive with that (textured) radiance, two-sided when the material is; `occlusionTexture` is ignored
//!   (a path tracer computes occlusion);
//! - `KHR_materials_specular`: `specularFactor x specularColorFactor` scales the coat (the plastic's `specular`);
//!   0 leaves the diffuse base alone: exactly `Lambert(albedo: base)` (its textures are reported and ignored);
//! - `KHR_materials_transmission` + `KHR_materials_ior`: `Blend(a: the above, b: RoughDielectric(alpha, ior,
//!   transmittance: base), weight: transmission)`;
//! - `alphaMode` MASK (`alphaCutoff`, 0.5) and BLEND: an alpha cut-out (`Mask` / stochastic `Blend`) with
//!   `alpha = baseColorFactor.a x baseColorTexture.a`;
//! - `doubleSided: false`: one-sided materials (the back is black) and one-sided emission;
//! - samplers' wrap modes (`wrapS`; a different `wrapT` is reported), `KHR_texture_transform` offset and scale
//!   (rotation reported), `texCoord` 0 or 1 (one set per primitive).

use super::data::{Buffers, uri_bytes};
use crate::schema::{ColorDesc, MaterialDesc, ScalarDesc, ScaleDesc, TextureRef};
use glam::{Vec2, Vec3};
use prism_core::alpha::{AlphaMask, AlphaMode};
use prism_core::error::{PrismError, Result};
use prism_core::texture::{ByteDecoding, Channel, ImageMap, TexImage, Texture, Wrap};
use prism_engine::Resources;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How an image's texels are decoded for one use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Variant {
    /// Colour: sRGB-decoded RGB.
    Srgb,
    /// Data: RGB as stored.
    Raw,
    /// The alpha channel (grey).
    Alpha,
    /// GGX alpha from a metallic-roughness image: green squared (grey).
    RoughnessAlpha,
}

/// A glTF material resolved for Prism.
#[derive(Clone, Debug)]
pub struct Resolved {
    pub id: u32,
    pub emission: Option<(Vec3, bool, Option<ImageMap>)>,
    pub alpha: Option<AlphaMask>,
    pub uv_set: u32,
    pub normal_mapped: bool,
}

/// Decoded images and the textures made from them, shared by every material of a document.
pub struct Materials<'a> {
    pub file: PathBuf,
    pub base: Option<PathBuf>,
    pub buffers: &'a Buffers,
    decoded: HashMap<usize, Arc<image::DynamicImage>>,
    variants: HashMap<(usize, Variant), Arc<TexImage>>,
    /// Texture names (for the material schema) -> index in `res.textures`.
    pub tex_names: HashMap<String, u32>,
    resolved: HashMap<Option<usize>, Resolved>,
    pub warnings: BTreeSet<String>,
}

/// The first bytes of every KTX2 file.
const KTX2_MAGIC: &[u8] = &[0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n'];

fn image_what(img: &gltf::Image) -> String {
    match (img.name(), img.source()) {
        (Some(n), _) => format!("image {} '{n}'", img.index()),
        (None, gltf::image::Source::Uri { uri, .. }) if !uri.starts_with("data:") => {
            format!("image {} ({uri})", img.index())
        }
        _ => format!("image {}", img.index()),
    }
}

impl<'a> Materials<'a> {
    pub fn new(file: &Path, base: Option<&Path>, buffers: &'a Buffers) -> Self {
        Materials {
            file: file.to_path_buf(),
            base: base.map(Path::to_path_buf),
            buffers,
            decoded: HashMap::new(),
            variants: HashMap::new(),
            tex_names: HashMap::new(),
            resolved: HashMap::new(),
            warnings: BTreeSet::new(),
        }
    }

    /// The decoded image, or `None` for a KTX2 texture in an encoding Prism does not decode (Basis Universal, block
    /// formats: the material keeps its factor, with a warning).
    fn decoded(&mut self, img: &gltf::Image) -> Result<Option<Arc<image::DynamicImage>>> {
        if let Some(d) = self.decoded.get(&img.index()) {
            return Ok(Some(d.clone()));
        }
        let what = image_what(img);
        let bytes = match img.source() {
            gltf::image::Source::View { view, .. } => self.buffers.view(&view, &what, &self.file)?.to_vec(),
            gltf::image::Source::Uri { uri, .. } => uri_bytes(uri, self.base.as_deref(), &what, &self.file)?,
        };
        let label = PathBuf::from(format!("{}: {what}", self.file.display()));
        if bytes.starts_with(KTX2_MAGIC) {
            let d = match super::ktx2_image::decode(&bytes) {
                Ok(super::ktx2_image::Ktx2::Image(img)) => Arc::new(img),
                Ok(super::ktx2_image::Ktx2::Unsupported(why)) => {
                    self.warnings.insert(format!(
                        "{what} is a KTX2 texture {why}, which Prism does not decode: its materials use their \
                         factors alone"
                    ));
                    return Ok(None);
                }
                Err(e) => return Err(PrismError::format(&label, format!("cannot decode KTX2 texture: {e}"))),
            };
            self.decoded.insert(img.index(), d.clone());
            return Ok(Some(d));
        }
        let d = Arc::new(TexImage::decode_bytes(&bytes, &label)?);
        self.decoded.insert(img.index(), d.clone());
        Ok(Some(d))
    }

    fn image(&mut self, img: &gltf::Image, v: Variant) -> Result<Option<Arc<TexImage>>> {
        if let Some(t) = self.variants.get(&(img.index(), v)) {
            return Ok(Some(t.clone()));
        }
        let Some(d) = self.decoded(img)? else { return Ok(None) };
        let t = match v {
            Variant::Srgb => TexImage::from_dynamic(&d, false),
            Variant::Raw => TexImage::from_dynamic(&d, true),
            Variant::Alpha => match TexImage::alpha_from_dynamic(&d) {
                Some(a) => a,
                None => return Ok(None),
            },
            // The green channel (roughness) squared: GGX alpha.
            Variant::RoughnessAlpha => TexImage::channel_from_dynamic(&d, 1, ByteDecoding::Squared),
        };
        let t = Arc::new(t);
        self.variants.insert((img.index(), v), t.clone());
        Ok(Some(t))
    }

    /// The image map of a texture reference (sampler wrap mode, texture transform).
    fn image_map(&mut self, info: &TexInfo, v: Variant) -> Result<Option<ImageMap>> {
        let tex = &info.texture;
        let Some(image) = self.image(&tex.source(), v)? else { return Ok(None) };
        let wrap = |m: gltf::texture::WrappingMode| match m {
            gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
            gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
            gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        };
        let s = tex.sampler();
        if s.wrap_s() != s.wrap_t() {
            self.warnings
                .insert(format!("texture {}: different wrap modes in s and t; using wrapS for both", tex.index()));
        }
        let (mut uv_scale, mut uv_offset, mut uv_rotation) = (Vec2::ONE, Vec2::ZERO, ImageMap::NO_ROTATION);
        if let Some((offset, rotation, scale)) = info.transform {
            if !(offset.iter().chain(&scale).all(|v| v.is_finite()) && rotation.is_finite()) {
                return Err(PrismError::format(
                    &self.file,
                    format!("texture {}: KHR_texture_transform values must be finite", tex.index()),
                ));
            }
            uv_scale = Vec2::from(scale);
            uv_offset = Vec2::from(offset);
            if rotation != 0.0 {
                uv_rotation = Vec2::new(rotation.cos(), rotation.sin());
            }
        }
        Ok(Some(ImageMap { image, wrap: wrap(s.wrap_s()), uv_scale, uv_offset, uv_rotation }))
    }

    /// Register a texture for the material schema; returns its name.
    fn named_texture(&mut self, info: &TexInfo, v: Variant, res: &mut Resources) -> Result<Option<String>> {
        let name = format!("t{}:{:?}:{:?}", info.texture.index(), v, info.transform);
        if self.tex_names.contains_key(&name) {
            return Ok(Some(name));
        }
        let Some(map) = self.image_map(info, v)? else { return Ok(None) };
        let id = res.textures.add(Texture::Image(map));
        self.tex_names.insert(name.clone(), id);
        Ok(Some(name))
    }

    /// The Prism material of a glTF material (`None`: the default material), made once.
    pub fn resolve(&mut self, m: &gltf::Material, res: &mut Resources) -> Result<Resolved> {
        if let Some(r) = self.resolved.get(&m.index()) {
            return Ok(r.clone());
        }
        let r = self.make(m, res)?;
        self.resolved.insert(m.index(), r.clone());
        Ok(r)
    }

    fn make(&mut self, m: &gltf::Material, res: &mut Resources) -> Result<Resolved> {
        let label = match (m.index(), m.name()) {
            (None, _) => "default material".to_string(),
            (Some(i), Some(n)) => format!("material {i} '{n}'"),
            (Some(i), None) => format!("material {i}"),
        };
        let key = format!("gltf{}", m.index().map_or("-default".into(), |i| i.to_string()));
        let pbr = m.pbr_metallic_roughness();
        let two_sided = m.double_sided();
        let mut sets = BTreeSet::new();
        fn info<'b>(i: Option<gltf::texture::Info<'b>>, sets: &mut BTreeSet<u32>) -> Option<TexInfo<'b>> {
            i.map(|i| {
                let t = i.texture_transform().map(|t| (t.offset(), t.rotation(), t.scale()));
                let set = i.texture_transform().and_then(|t| t.tex_coord()).unwrap_or(i.tex_coord());
                sets.insert(set);
                TexInfo { texture: i.texture(), transform: t }
            })
        }
        let base_info = info(pbr.base_color_texture(), &mut sets);
        let mr_info = info(pbr.metallic_roughness_texture(), &mut sets);
        let emit_info = info(m.emissive_texture(), &mut sets);
        let normal = m.normal_texture().map(|n| {
            sets.insert(n.tex_coord());
            (TexInfo { texture: n.texture(), transform: None }, n.scale())
        });
        let trans = m.transmission();
        let trans_info = info(trans.as_ref().and_then(|t| t.transmission_texture()), &mut sets);
        let file = self.file.clone();
        let check = |v: f32, what: &str| -> Result<f32> {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(PrismError::format(&file, format!("{label}: {what} must be finite and non-negative, got {v}")))
            }
        };
        let bc = pbr.base_color_factor();
        let base_rgb = Vec3::new(
            check(bc[0], "baseColorFactor")?,
            check(bc[1], "baseColorFactor")?,
            check(bc[2], "baseColorFactor")?,
        );
        let base = match &base_info {
            Some(i) => match self.named_texture(i, Variant::Srgb, res)? {
                Some(n) => ColorDesc::Texture(TextureRef::Map {
                    texture: n,
                    scale: Some(ScaleDesc::Rgb(base_rgb.to_array())),
                    channel: None,
                }),
                None => ColorDesc::Rgb(base_rgb.to_array()),
            },
            None => ColorDesc::Rgb(base_rgb.to_array()),
        };
        let metallic_f = check(pbr.metallic_factor(), "metallicFactor")?.min(1.0);
        let rough_f = check(pbr.roughness_factor(), "roughnessFactor")?.min(1.0);
        let (metallic, alpha) = match &mr_info {
            Some(i) => {
                let raw = self.named_texture(i, Variant::Raw, res)?.expect("RGB");
                let ra = self.named_texture(i, Variant::RoughnessAlpha, res)?.expect("RGB");
                (
                    ScalarDesc::Texture(TextureRef::Map {
                        texture: raw,
                        scale: Some(ScaleDesc::Uniform(metallic_f)),
                        channel: Some(Channel::B),
                    }),
                    ScalarDesc::Texture(TextureRef::Map {
                        texture: ra,
                        scale: Some(ScaleDesc::Uniform(rough_f * rough_f)),
                        channel: Some(Channel::R),
                    }),
                )
            }
            None => (ScalarDesc::Value(metallic_f), ScalarDesc::Value(rough_f * rough_f)),
        };
        let mut descs: BTreeMap<String, MaterialDesc> = BTreeMap::new();
        let plastic = format!("{key}/dielectric");
        let metal = format!("{key}/metal");
        let specular = match m.specular() {
            Some(sp) => {
                if sp.specular_texture().is_some() || sp.specular_color_texture().is_some() {
                    self.warnings
                        .insert(format!("{label}: KHR_materials_specular textures are ignored (factors used)"));
                }
                let c = sp.specular_color_factor();
                let f = check(sp.specular_factor(), "specularFactor")?;
                Vec3::new(
                    check(c[0], "specularColorFactor")?,
                    check(c[1], "specularColorFactor")?,
                    check(c[2], "specularColorFactor")?,
                ) * f
            }
            None => Vec3::ONE,
        };
        let dielectric = if specular == Vec3::ZERO {
            MaterialDesc::Lambert { albedo: base.clone(), two_sided }
        } else {
            MaterialDesc::RoughPlastic {
                alpha: alpha.clone(),
                ior: 1.5,
                diffuse: base.clone(),
                specular: ColorDesc::Rgb(specular.to_array()),
                two_sided,
            }
        };
        descs.insert(plastic.clone(), dielectric);
        descs.insert(
            metal.clone(),
            MaterialDesc::RoughConductor {
                alpha: alpha.clone(),
                material: None,
                eta: None,
                k: None,
                reflectance: Some(base.clone()),
                scale: ColorDesc::Rgb([1.0; 3]),
                two_sided,
            },
        );
        let mut top = match metallic {
            ScalarDesc::Value(v) if v <= 0.0 => {
                descs.remove(&metal);
                plastic
            }
            ScalarDesc::Value(v) if v >= 1.0 => {
                descs.remove(&plastic);
                metal
            }
            w => {
                let n = format!("{key}/pbr");
                descs.insert(n.clone(), MaterialDesc::Blend { a: plastic, b: metal, weight: w });
                n
            }
        };
        if let Some(t) = &trans {
            let f = check(t.transmission_factor(), "transmissionFactor")?.min(1.0);
            let weight = match &trans_info {
                Some(i) => {
                    let n = self.named_texture(i, Variant::Raw, res)?.expect("RGB");
                    Some(ScalarDesc::Texture(TextureRef::Map {
                        texture: n,
                        scale: Some(ScaleDesc::Uniform(f)),
                        channel: Some(Channel::R),
                    }))
                }
                None if f > 0.0 => Some(ScalarDesc::Value(f)),
                None => None,
            };
            if let Some(w) = weight {
                let ior = m.ior().unwrap_or(1.5);
                if !(ior.is_finite() && ior >= 1.0) {
                    return Err(PrismError::format(
                        &self.file,
                        format!("{label}: KHR_materials_ior must be >= 1, got {ior}"),
                    ));
                }
                let glass = format!("{key}/transmission");
                descs.insert(
                    glass.clone(),
                    MaterialDesc::RoughDielectric {
                        alpha: alpha.clone(),
                        ior,
                        reflectance: ColorDesc::Rgb([1.0; 3]),
                        transmittance: base.clone(),
                    },
                );
                let n = format!("{key}/transmissive");
                descs.insert(n.clone(), MaterialDesc::Blend { a: top, b: glass, weight: w });
                top = n;
            }
        }
        let mut normal_mapped = false;
        if let Some((i, scale)) = &normal
            && let Some(n) = self.named_texture(i, Variant::Raw, res)?
        {
            let nm = format!("{key}/normal-mapped");
            descs.insert(
                nm.clone(),
                MaterialDesc::NormalMap {
                    material: top,
                    texture: n,
                    strength: check(*scale, "normalTexture.scale")?,
                    flip_green: true,
                },
            );
            top = nm;
            normal_mapped = true;
        }
        let ctx = format!("{}: {label}", self.file.display());
        let entries = crate::material_tables::load_materials(&descs, &self.tex_names, &ctx, res)?;
        let id = entries[&top].id;
        // Emission: factor x texture x strength, as a (textured) area light.
        let ef = m.emissive_factor();
        let strength = check(m.emissive_strength().unwrap_or(1.0), "emissiveStrength")?;
        let radiance = Vec3::new(
            check(ef[0], "emissiveFactor")?,
            check(ef[1], "emissiveFactor")?,
            check(ef[2], "emissiveFactor")?,
        ) * strength;
        let emission = if radiance.max_element() > 0.0 {
            let texture = match &emit_info {
                Some(i) => self.image_map(i, Variant::Srgb)?,
                None => None,
            };
            Some((radiance, two_sided, texture))
        } else {
            None
        };
        let alpha = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => None,
            mode => {
                let factor = bc[3].clamp(0.0, 1.0);
                let texture = match &base_info {
                    Some(i) => self.image_map(i, Variant::Alpha)?,
                    None => None,
                };
                let mode = match mode {
                    gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) },
                    _ => AlphaMode::Blend,
                };
                (texture.is_some() || factor < 1.0 || matches!(mode, AlphaMode::Mask { .. })).then_some(AlphaMask {
                    texture,
                    factor,
                    mode,
                })
            }
        };
        if sets.len() > 1 {
            self.warnings.insert(format!(
                "{label}: textures use several uv sets; TEXCOORD_{} is used for all",
                sets.iter().next().unwrap_or(&0)
            ));
        }
        Ok(Resolved { id, emission, alpha, uv_set: sets.iter().next().copied().unwrap_or(0), normal_mapped })
    }
}

/// A texture reference with its `KHR_texture_transform` (offset, rotation, scale).
struct TexInfo<'a> {
    texture: gltf::Texture<'a>,
    transform: Option<([f32; 2], f32, [f32; 2])>,
}
