//! Textures and materials of a RON scene into the resource tables: images decoded once per (file, raw) and
//! shared, every parameter validated (finite, non-negative colours, roughness in [0, 1], textures of the right
//! kind, names that exist), blends and maps checked for cycles and lobe counts. Errors are one line naming the
//! file and the material or texture.

use super::schema::{ColorDesc, MaterialDesc, ScalarDesc, ScaleDesc, TextureDesc, TextureRef, V3};
use super::transform::compose;
use glam::{Vec2, Vec3};
use prism_core::bsdf::layered::{LayerBase, LayerSpec};
use prism_core::error::{PrismError, Result};
use prism_core::material::{CoatBase, ConductorSpec, Material, MaterialKind, PhongParams, Shading, metals};
use prism_core::texture::{ByteDecoding, ColorParam, ImageMap, ScalarParam, Solid, SolidKind, TexImage, Texture};
use prism_engine::Resources;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A material by name: its index and, for emissive materials, the radiance and sidedness.
pub(crate) struct MaterialEntry {
    pub id: u32,
    pub emission: Option<(Vec3, bool)>,
}

/// Load the named textures. Returns name -> texture index.
pub(super) fn load_textures(
    descs: &BTreeMap<String, TextureDesc>,
    base_dir: &Path,
    file: &str,
    res: &mut Resources,
) -> Result<HashMap<String, u32>> {
    let mut images: HashMap<(PathBuf, bool, Option<u32>), Arc<TexImage>> = HashMap::new();
    let mut out = HashMap::new();
    for (name, d) in descs {
        let ctx = format!("{file}: texture '{name}'");
        let tex = match d {
            TextureDesc::Image { path, raw, wrap, uv_scale, uv_offset, uv_rotation, gamma } => {
                if uv_scale.iter().chain(uv_offset).chain([uv_rotation]).any(|v| !v.is_finite()) {
                    return Err(PrismError::scene(&ctx, "uv_scale, uv_offset and uv_rotation must be finite"));
                }
                let decoding = match (*raw, *gamma) {
                    (false, None) => ByteDecoding::Srgb,
                    (true, None) => ByteDecoding::Raw,
                    (false, Some(g)) if g.is_finite() && g > 0.0 => ByteDecoding::Gamma(g),
                    (false, Some(g)) => {
                        return Err(PrismError::scene(&ctx, format!("gamma must be a positive number, got {g}")));
                    }
                    (true, Some(_)) => {
                        return Err(PrismError::scene(&ctx, "give `raw: true` or a `gamma`, not both"));
                    }
                };
                let full = base_dir.join(path);
                res.inputs.push(full.clone());
                let key = (full.clone(), *raw, gamma.map(f32::to_bits));
                let image = match images.get(&key) {
                    Some(i) => i.clone(),
                    None => {
                        let i = Arc::new(
                            TexImage::load_decoded(&full, decoding)
                                .map_err(|e| PrismError::scene(&ctx, e.to_string()))?,
                        );
                        images.insert(key, i.clone());
                        i
                    }
                };
                Texture::Image(ImageMap {
                    image,
                    wrap: *wrap,
                    uv_scale: Vec2::from(*uv_scale),
                    uv_offset: Vec2::from(*uv_offset),
                    uv_rotation: if *uv_rotation == 0.0 {
                        ImageMap::NO_ROTATION
                    } else {
                        Vec2::new(uv_rotation.to_radians().cos(), uv_rotation.to_radians().sin())
                    },
                })
            }
            TextureDesc::Checker2d { uv_scale, uv_offset } => {
                if uv_scale.iter().chain(uv_offset).any(|v| !v.is_finite()) {
                    return Err(PrismError::scene(&ctx, "uv_scale and uv_offset must be finite"));
                }
                Texture::UvChecker { scale: Vec2::from(*uv_scale), offset: Vec2::from(*uv_offset) }
            }
            TextureDesc::Checker3d { transform } => solid(SolidKind::Checker3d, transform, 0, 1.0, 1.0, &ctx)?,
            TextureDesc::Noise { transform, octaves } => solid(SolidKind::Noise, transform, *octaves, 1.0, 1.0, &ctx)?,
            TextureDesc::Marble { transform, octaves, frequency, amplitude } => {
                solid(SolidKind::Marble, transform, *octaves, *frequency, *amplitude, &ctx)?
            }
            TextureDesc::Wood { transform, octaves, frequency, amplitude } => {
                solid(SolidKind::Wood, transform, *octaves, *frequency, *amplitude, &ctx)?
            }
        };
        out.insert(name.clone(), res.textures.add(tex));
    }
    Ok(out)
}

fn solid(
    kind: SolidKind,
    ops: &[super::schema::TransformOp],
    octaves: u32,
    frequency: f32,
    amplitude: f32,
    ctx: &str,
) -> Result<Texture> {
    if !(frequency.is_finite() && amplitude.is_finite()) {
        return Err(PrismError::scene(ctx, "frequency and amplitude must be finite numbers"));
    }
    if octaves > 16 {
        return Err(PrismError::scene(ctx, format!("octaves must be at most 16, got {octaves}")));
    }
    // The transform maps world points into texture space.
    let transform = compose(ops, ctx)?;
    Ok(Texture::Solid(Solid { kind, transform, octaves, frequency, amplitude }))
}

/// Resolves names and validates parameters of one material.
struct Ctx<'a> {
    ctx: String,
    textures: &'a HashMap<String, u32>,
    ids: &'a HashMap<String, u32>,
    res: &'a Resources,
}

impl Ctx<'_> {
    fn err(&self, msg: impl Into<String>) -> PrismError {
        PrismError::scene(&self.ctx, msg.into())
    }

    fn texture(&self, name: &str, what: &str) -> Result<u32> {
        self.textures.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = self.textures.keys().map(String::as_str).collect();
            known.sort();
            self.err(format!(
                "{what}: unknown texture '{name}' (defined: {})",
                if known.is_empty() { "none".into() } else { known.join(", ") }
            ))
        })
    }

    fn material(&self, name: &str, what: &str) -> Result<u32> {
        self.ids.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = self.ids.keys().map(String::as_str).collect();
            known.sort();
            self.err(format!("{what}: unknown material '{name}' (defined: {})", known.join(", ")))
        })
    }

    fn color(&self, c: &ColorDesc, what: &str) -> Result<ColorParam> {
        let check = |v: Vec3| -> Result<Vec3> {
            if !v.is_finite() || v.min_element() < 0.0 {
                return Err(self.err(format!("{what} must be finite and non-negative, got {:?}", v.to_array())));
            }
            Ok(v)
        };
        Ok(match c {
            ColorDesc::Rgb(v) => ColorParam::Const(check(Vec3::from(*v))?),
            ColorDesc::Gray(g) => ColorParam::Const(check(Vec3::splat(*g))?),
            ColorDesc::Texture(TextureRef::Mix { texture, a, b }) => {
                let tex = self.texture(texture, what)?;
                ColorParam::Mix { tex, a: check(Vec3::from(*a))?, b: check(Vec3::from(*b))? }
            }
            ColorDesc::Texture(r) => {
                let (name, scale, channel) = split_ref(r);
                let tex = self.texture(name, what)?;
                if self.res.textures.get(tex).scalar_only() {
                    return Err(self.err(format!(
                        "{what}: texture '{name}' is a solid (scalar) texture and cannot be a colour; use it as a \
                         Blend weight"
                    )));
                }
                if channel.is_some() {
                    return Err(self.err(format!("{what} is a colour: `channel` applies to scalar parameters only")));
                }
                let scale = match scale {
                    None => Vec3::ONE,
                    Some(ScaleDesc::Uniform(s)) => Vec3::splat(s),
                    Some(ScaleDesc::Rgb(v)) => Vec3::from(v),
                };
                ColorParam::Map { tex, scale: check(scale)? }
            }
        })
    }

    fn scalar(&self, s: &ScalarDesc, what: &str, range: (f32, f32)) -> Result<ScalarParam> {
        match s {
            ScalarDesc::Value(v) => {
                if !(v.is_finite() && *v >= range.0 && *v <= range.1) {
                    let r = if range.1.is_finite() {
                        format!("in [{}, {}]", range.0, range.1)
                    } else {
                        format!(">= {}", range.0)
                    };
                    return Err(self.err(format!("{what} must be a number {r}, got {v}")));
                }
                Ok(ScalarParam::Const(*v))
            }
            ScalarDesc::Texture(TextureRef::Mix { .. }) => {
                Err(self.err(format!("{what} is a scalar: `Mix` makes colours (use `Map` with a `scale`)")))
            }
            ScalarDesc::Texture(r) => {
                let (name, scale, channel) = split_ref(r);
                let tex = self.texture(name, what)?;
                let t = self.res.textures.get(tex);
                if channel.is_none() && !t.is_scalar() {
                    return Err(self.err(format!(
                        "{what} is a scalar but texture '{name}' is a colour image: pick a channel with \
                         Map(texture: \"{name}\", channel: R) (R, G, B or Mean)"
                    )));
                }
                let scale = match scale {
                    None => 1.0,
                    Some(ScaleDesc::Uniform(s)) => s,
                    Some(ScaleDesc::Rgb(_)) => {
                        return Err(self.err(format!("{what} is a scalar: its scale is one number")));
                    }
                };
                if !scale.is_finite() {
                    return Err(self.err(format!("{what}: scale must be finite, got {scale}")));
                }
                Ok(ScalarParam::Map { tex, channel: channel.unwrap_or_default(), scale })
            }
        }
    }
}

fn split_ref(r: &TextureRef) -> (&str, Option<ScaleDesc>, Option<prism_core::texture::Channel>) {
    match r {
        TextureRef::Texture(n) => (n.as_str(), None, None),
        TextureRef::Map { texture, scale, channel } => (texture.as_str(), *scale, *channel),
        TextureRef::Mix { texture, .. } => (texture.as_str(), None, None),
    }
}

fn check_ior(ior: f32, c: &Ctx) -> Result<f32> {
    if ior.is_finite() && ior > 0.0 { Ok(ior) } else { Err(c.err(format!("ior must be positive, got {ior}"))) }
}

const NON_NEG: (f32, f32) = (0.0, f32::INFINITY);
const UNIT: (f32, f32) = (0.0, 1.0);

/// Add the scene's materials (after the ones already in the table). Returns name -> entry.
pub(crate) fn load_materials(
    descs: &BTreeMap<String, MaterialDesc>,
    textures: &HashMap<String, u32>,
    file: &str,
    res: &mut Resources,
) -> Result<HashMap<String, MaterialEntry>> {
    let first = res.materials.len() as u32;
    let ids: HashMap<String, u32> = descs.keys().enumerate().map(|(i, n)| (n.clone(), first + i as u32)).collect();
    let mut made = Vec::with_capacity(descs.len());
    let mut entries = HashMap::new();
    for (name, d) in descs {
        let c = Ctx { ctx: format!("{file}: material '{name}'"), textures, ids: &ids, res };
        let (m, emission) = material(name, d, &c)?;
        entries.insert(name.clone(), MaterialEntry { id: ids[name], emission });
        made.push(m);
    }
    res.materials.extend(made);
    prism_core::material::validate(&res.materials).map_err(|e| PrismError::scene(file, e))?;
    Ok(entries)
}

fn phong(
    name: &str,
    c: &Ctx,
    colors: [&ColorDesc; 5],
    exponent: &ScalarDesc,
    ior: f32,
    shading: Shading,
) -> Result<Material> {
    let [ambient, diffuse, specular, reflective, transparent] = colors;
    Ok(Material::phong(
        name,
        PhongParams {
            ambient: c.color(ambient, "ambient")?,
            diffuse: c.color(diffuse, "diffuse")?,
            specular: c.color(specular, "specular")?,
            exponent: c.scalar(exponent, "exponent", NON_NEG)?,
            reflective: c.color(reflective, "reflective")?,
            transparent: c.color(transparent, "transparent")?,
            ior: check_ior(ior, c)?,
            shading,
        },
    ))
}

fn material(name: &str, d: &MaterialDesc, c: &Ctx) -> Result<(Material, Option<(Vec3, bool)>)> {
    let sided = |mut m: Material, two_sided: bool| {
        m.two_sided = two_sided;
        m
    };
    let kind = |kind: MaterialKind, two_sided: bool| Material { name: name.to_string(), kind, two_sided };
    Ok(match d {
        MaterialDesc::Lambert { albedo, two_sided } => {
            let p = PhongParams { diffuse: c.color(albedo, "albedo")?, ..PhongParams::default() };
            (sided(Material::phong(name, p), *two_sided), None)
        }
        MaterialDesc::Phong { ambient, diffuse, specular, exponent, reflective, transparent, ior, two_sided } => {
            let colors = [ambient, diffuse, specular, reflective, transparent];
            (sided(phong(name, c, colors, exponent, *ior, Shading::Physical)?, *two_sided), None)
        }
        // The course's ambient term is ambientLight times the diffuse colour.
        MaterialDesc::Mit6837 { diffuse, specular, exponent, reflective, transparent, ior, two_sided } => {
            let colors = [diffuse, diffuse, specular, reflective, transparent];
            (sided(phong(name, c, colors, exponent, *ior, Shading::Mit6837)?, *two_sided), None)
        }
        MaterialDesc::Mirror { reflectance } => {
            let p = PhongParams { reflective: c.color(reflectance, "reflectance")?, ..PhongParams::default() };
            (Material::phong(name, p), None)
        }
        MaterialDesc::Glass { ior, transmittance } => {
            let p = PhongParams {
                transparent: c.color(transmittance, "transmittance")?,
                ior: check_ior(*ior, c)?,
                ..PhongParams::default()
            };
            (Material::phong(name, p), None)
        }
        MaterialDesc::Emissive { radiance, two_sided } => {
            let r = Vec3::from(*radiance);
            if !r.is_finite() || r.min_element() < 0.0 {
                return Err(c.err(format!("radiance must be finite and non-negative, got {radiance:?}")));
            }
            (Material::black(name), Some((r, *two_sided)))
        }
        MaterialDesc::RoughConductor { alpha, material, eta, k, reflectance, scale, two_sided } => {
            let fresnel = conductor_spec(material, eta, k, reflectance, ConductorSpec::Schlick(ColorParam::ONE), c)?;
            let k = MaterialKind::Conductor {
                alpha: c.scalar(alpha, "alpha (roughness)", UNIT)?,
                fresnel,
                scale: c.color(scale, "scale")?,
            };
            (kind(k, *two_sided), None)
        }
        MaterialDesc::RoughDielectric { alpha, ior, reflectance, transmittance } => {
            let k = MaterialKind::Dielectric {
                alpha: c.scalar(alpha, "alpha (roughness)", UNIT)?,
                ior: check_ior(*ior, c)?,
                reflectance: c.color(reflectance, "reflectance")?,
                transmittance: c.color(transmittance, "transmittance")?,
            };
            (kind(k, true), None)
        }
        MaterialDesc::RoughPlastic { alpha, ior, diffuse, specular, two_sided } => {
            let ior = check_ior(*ior, c)?;
            let alpha = c.scalar(alpha, "alpha (roughness)", UNIT)?;
            let constant = match alpha {
                prism_core::texture::ScalarParam::Const(a) => Some(a),
                _ => None,
            };
            let k = MaterialKind::Plastic {
                alpha,
                ior,
                diffuse: c.color(diffuse, "diffuse")?,
                specular: c.color(specular, "specular")?,
                interface: prism_core::bsdf::rough_interface::RoughInterface::get(ior, constant),
            };
            (kind(k, *two_sided), None)
        }
        MaterialDesc::DiffuseTransmission { reflectance, transmittance } => {
            let k = MaterialKind::DiffuseTransmission {
                reflectance: c.color(reflectance, "reflectance")?,
                transmittance: c.color(transmittance, "transmittance")?,
            };
            (kind(k, true), None)
        }
        MaterialDesc::ThinDielectric { ior, reflectance, transmittance } => {
            let k = MaterialKind::ThinDielectric {
                ior: check_ior(*ior, c)?,
                reflectance: c.color(reflectance, "reflectance")?,
                transmittance: c.color(transmittance, "transmittance")?,
            };
            (kind(k, true), None)
        }
        MaterialDesc::CoatedDiffuse { reflectance, alpha, ior, thickness, albedo, g, max_depth, samples } => {
            let spec = layer_spec(LayerBase::Diffuse, *ior, *thickness, *g, *max_depth, *samples, c)?;
            let k = MaterialKind::Coated {
                coat_alpha: c.scalar(alpha, "alpha (the coat's roughness)", UNIT)?,
                base: CoatBase::Diffuse(c.color(reflectance, "reflectance")?),
                albedo: c.color(albedo, "albedo")?,
                spec,
            };
            (kind(k, true), None)
        }
        MaterialDesc::CoatedConductor {
            alpha,
            ior,
            conductor_alpha,
            material,
            eta,
            k,
            reflectance,
            thickness,
            albedo,
            g,
            max_depth,
            samples,
        } => {
            let spec = layer_spec(LayerBase::Conductor, *ior, *thickness, *g, *max_depth, *samples, c)?;
            let (cu_eta, cu_k) = metals::metal("Cu").unwrap_or((Vec3::ONE, Vec3::ZERO));
            let fresnel =
                conductor_spec(material, eta, k, reflectance, ConductorSpec::Complex { eta: cu_eta, k: cu_k }, c)?;
            let k = MaterialKind::Coated {
                coat_alpha: c.scalar(alpha, "alpha (the coat's roughness)", UNIT)?,
                base: CoatBase::Conductor {
                    alpha: c.scalar(conductor_alpha, "conductor_alpha (the conductor's roughness)", UNIT)?,
                    fresnel,
                },
                albedo: c.color(albedo, "albedo")?,
                spec,
            };
            (kind(k, true), None)
        }
        MaterialDesc::Blend { a, b, weight } => {
            let k = MaterialKind::Blend {
                a: c.material(a, "a")?,
                b: c.material(b, "b")?,
                weight: c.scalar(weight, "weight", UNIT)?,
            };
            (kind(k, true), None)
        }
        MaterialDesc::NormalMap { material, texture, strength, flip_green } => {
            if !(strength.is_finite() && *strength >= 0.0) {
                return Err(c.err(format!("strength must be a number >= 0, got {strength}")));
            }
            let tex = c.texture(texture, "texture")?;
            let Texture::Image(map) = c.res.textures.get(tex) else {
                return Err(c.err(format!("texture '{texture}' is not an image: a normal map must be one")));
            };
            check_normal_map(&map.image, texture, c)?;
            let k = MaterialKind::NormalMap {
                base: c.material(material, "material")?,
                texture: tex,
                strength: *strength,
                flip_green: *flip_green,
            };
            (kind(k, true), None)
        }
        MaterialDesc::Bump { material, height } => {
            let k = MaterialKind::Bump {
                base: c.material(material, "material")?,
                height: c.scalar(height, "height", (f32::NEG_INFINITY, f32::INFINITY))?,
            };
            (kind(k, true), None)
        }
    })
}

/// A conductor's Fresnel term from a named metal, `eta` with `k`, or a reflectance (`default` when none is given).
fn conductor_spec(
    material: &Option<String>,
    eta: &Option<V3>,
    k: &Option<V3>,
    reflectance: &Option<ColorDesc>,
    default: ConductorSpec,
    c: &Ctx,
) -> Result<ConductorSpec> {
    Ok(match (material, eta, k, reflectance) {
        (Some(m), None, None, None) => {
            let (eta, k) = metals::metal(m)
                .ok_or_else(|| c.err(format!("unknown metal '{m}' (known: {})", metals::metal_names())))?;
            ConductorSpec::Complex { eta, k }
        }
        (None, Some(eta), Some(k), None) => {
            ConductorSpec::Complex { eta: finite3(*eta, "eta", c)?, k: finite3(*k, "k", c)? }
        }
        (None, None, None, Some(r)) => ConductorSpec::Schlick(c.color(r, "reflectance")?),
        (None, None, None, None) => default,
        _ => return Err(c.err("give one of `material`, `eta` with `k`, or `reflectance`")),
    })
}

/// Most events per layered walk and walks per estimate a material may ask for (each costs every shading point).
const MAX_LAYER_DEPTH: u32 = 100;
const MAX_LAYER_SAMPLES: u32 = 64;

/// The checked constant parameters of a coated material.
fn layer_spec(
    base: LayerBase,
    ior: f32,
    thickness: f32,
    g: f32,
    max_depth: u32,
    samples: u32,
    c: &Ctx,
) -> Result<&'static LayerSpec> {
    let eta = check_ior(ior, c)?;
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(c.err(format!("thickness must be a positive number (mean free paths), got {thickness}")));
    }
    if !(-1.0..=1.0).contains(&g) {
        return Err(c.err(format!("g (the medium's Henyey-Greenstein asymmetry) must be in [-1, 1], got {g}")));
    }
    if !(1..=MAX_LAYER_DEPTH).contains(&max_depth) {
        return Err(c.err(format!("max_depth must be in 1..={MAX_LAYER_DEPTH}, got {max_depth}")));
    }
    if !(1..=MAX_LAYER_SAMPLES).contains(&samples) {
        return Err(c.err(format!("samples must be in 1..={MAX_LAYER_SAMPLES}, got {samples}")));
    }
    Ok(LayerSpec { base, eta, thickness, g, max_depth, samples }.intern())
}

fn finite3(v: V3, what: &str, c: &Ctx) -> Result<Vec3> {
    let v = Vec3::from(v);
    if !v.is_finite() || v.min_element() < 0.0 {
        return Err(c.err(format!("{what} must be finite and non-negative, got {:?}", v.to_array())));
    }
    Ok(v)
}

/// A normal map whose texels decode (`2 c - 1`) to vectors of (nearly) zero length has no direction there.
fn check_normal_map(img: &TexImage, texture: &str, c: &Ctx) -> Result<()> {
    if let Some(i) = img.iter().position(|t| (2.0 * t - Vec3::ONE).length() < 0.05) {
        let (row, col) = (i as u32 / img.width, i as u32 % img.width);
        let t = img.texel_at(i);
        return Err(c.err(format!(
            "normal map '{texture}': texel (row {row}, column {col}) = {:?} decodes to a zero-length normal (is \
             this a colour image, or saved with sRGB decoding? normal maps need `raw: true`)",
            t.to_array()
        )));
    }
    Ok(())
}
