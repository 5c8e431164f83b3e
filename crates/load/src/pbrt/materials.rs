//! pbrt materials as Prism's (the table is in `docs/guide/import-pbrt.md`; textures: `textures.rs`). Approximations
//! are reported once each. Roughness is remapped as the file's pbrt version does (`remaproughness`, default true):
//! pbrt-v3's `RoughnessToAlpha` polynomial in `ln r`, pbrt-v4's `sqrt(r)`; Prism's GGX `alpha` is then pbrt's
//! alpha. Parameters that name a texture read its [`TexValue`].

use super::Version;
use super::convert::{Converter, num, quote, tuple3};
use super::params::{FloatParam, Params, SpectrumParam};
use super::spectrum::{MetalPart, NamedSpectrum, blackbody_v3, blackbody_v4, named_spectrum, sampled_to_rgb};
use prism_core::error::{PrismError, Result, SourcePos};

/// A texture as parameters see it: a constant, an image texture of the RON scene times a factor, or a mix of two
/// colours by a RON texture (a checkerboard).
#[derive(Clone, Debug)]
pub enum TexValue {
    Const([f64; 3]),
    Image { ron: String, scale: [f64; 3] },
    Mix { ron: String, a: [f64; 3], b: [f64; 3] },
}

/// The RON name of pbrt's `interface` material: shapes with it bound media only and are left out.
pub const INTERFACE: &str = "#interface";

pub(super) fn bad(pos: &SourcePos, m: String) -> PrismError {
    PrismError::Parse { pos: pos.clone(), message: m }
}

/// A spectrum parameter as linear RGB (constants only; textures are the caller's business).
pub fn spectrum_rgb(c: &mut Converter, s: &SpectrumParam, what: &str, pos: &SourcePos) -> Result<Option<[f64; 3]>> {
    Ok(Some(match s {
        SpectrumParam::Rgb(v) => *v,
        SpectrumParam::Blackbody(v) if v.len() == 1 => blackbody_v4(v[0]),
        SpectrumParam::Blackbody(v) => {
            // pbrt-v3: (temperature, scale) pairs; several pairs add up.
            let mut sum = [0.0; 3];
            for pair in v.chunks_exact(2) {
                let b = blackbody_v3(pair[0], pair[1]);
                (0..3).for_each(|k| sum[k] += b[k]);
            }
            sum
        }
        SpectrumParam::Sampled(pairs) => sampled_to_rgb(pairs),
        SpectrumParam::Named(n) => match named_spectrum(n) {
            Some(NamedSpectrum::Constant(v)) => [v; 3],
            Some(NamedSpectrum::Metal { .. }) => {
                return Err(bad(pos, format!("{what}: the spectrum \"{n}\" is a metal's index, not a colour")));
            }
            None if n.ends_with(".spd") => {
                let path = c.resolve(n);
                let text = c.read_text(&path, "spectrum file")?;
                let v: Vec<f64> = text
                    .split(|ch: char| ch.is_whitespace() || ch == ',')
                    .filter(|t| !t.is_empty() && !t.starts_with('#'))
                    .map(|t| t.parse::<f64>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| PrismError::format(&path, "not a list of (wavelength, value) numbers"))?;
                if v.len() < 4 || !v.len().is_multiple_of(2) {
                    return Err(PrismError::format(&path, "needs (wavelength, value) pairs"));
                }
                sampled_to_rgb(&v)
            }
            None => return Err(bad(pos, format!("{what}: unknown named spectrum \"{n}\""))),
        },
        SpectrumParam::Texture(_) => return Ok(None),
    }))
}

fn check_color(v: [f64; 3], what: &str, pos: &SourcePos) -> Result<[f64; 3]> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(v.map(|x| x.max(0.0)))
    } else {
        Err(bad(pos, format!("{what} is not finite: {v:?}")))
    }
}

/// A colour parameter as RON (`(r, g, b)` or `Map(...)`).
pub fn color(c: &mut Converter, p: &Params, name: &str, default: [f64; 3], pos: &SourcePos) -> Result<String> {
    color_scaled(c, p, name, default, 1.0, pos)
}

/// [`color`] times `factor` (a material's `scale`).
fn color_scaled(
    c: &mut Converter,
    p: &Params,
    name: &str,
    default: [f64; 3],
    factor: f64,
    pos: &SourcePos,
) -> Result<String> {
    let pos = p.pos_of(name).unwrap_or_else(|| pos.clone());
    let times = |v: [f64; 3]| v.map(|x| x * factor);
    match p.spectrum(name)? {
        None => Ok(tuple3(times(default))),
        Some(SpectrumParam::Texture(t)) => {
            let v = c.tex_values.get(&(false, t.clone())).or_else(|| c.tex_values.get(&(true, t.clone()))).cloned();
            match v {
                Some(TexValue::Const(k)) => Ok(tuple3(times(k))),
                Some(TexValue::Image { ron, scale }) => {
                    Ok(format!("Map(texture: {}, scale: {})", quote(&ron), tuple3(times(scale))))
                }
                Some(TexValue::Mix { ron, a, b }) => {
                    Ok(format!("Mix(texture: {}, a: {}, b: {})", quote(&ron), tuple3(times(a)), tuple3(times(b))))
                }
                None => Err(bad(&pos, format!("parameter \"{name}\": unknown texture \"{t}\""))),
            }
        }
        Some(s) => {
            let v = spectrum_rgb(c, &s, name, &pos)?.expect("not a texture");
            Ok(tuple3(times(check_color(v, name, &pos)?)))
        }
    }
}

/// A scalar parameter as RON (a number or `Map(...)`), with `f` applied to constants.
fn scalar(
    c: &Converter,
    p: &Params,
    name: &str,
    default: f64,
    f: impl Fn(f64) -> f64,
    pos: &SourcePos,
) -> Result<String> {
    let pos = p.pos_of(name).unwrap_or_else(|| pos.clone());
    match p.float_or_texture(name)? {
        None => Ok(num(f(default))),
        Some(FloatParam::Value(v)) if v.is_finite() => Ok(num(f(v))),
        Some(FloatParam::Value(v)) => Err(bad(&pos, format!("parameter \"{name}\" is not finite: {v}"))),
        Some(FloatParam::Texture(t)) => {
            match c.tex_values.get(&(true, t.clone())).or_else(|| c.tex_values.get(&(false, t.clone()))) {
                Some(TexValue::Const(k)) => Ok(num(f((k[0] + k[1] + k[2]) / 3.0))),
                Some(TexValue::Image { ron, scale }) => Ok(format!(
                    "Map(texture: {}, channel: Mean, scale: {})",
                    quote(ron),
                    num((scale[0] + scale[1] + scale[2]) / 3.0)
                )),
                // A scalar checkerboard between 0 and b is the checker times b; otherwise its mean.
                Some(TexValue::Mix { ron, a, b }) if a.iter().all(|&x| x == 0.0) => {
                    Ok(format!("Map(texture: {}, scale: {})", quote(ron), num(f((b[0] + b[1] + b[2]) / 3.0))))
                }
                Some(TexValue::Mix { a, b, .. }) => Ok(num(f((a[0] + a[1] + a[2] + b[0] + b[1] + b[2]) / 6.0))),
                None => Err(bad(&pos, format!("parameter \"{name}\": unknown texture \"{t}\""))),
            }
        }
    }
}

/// pbrt-v3's `TrowbridgeReitzDistribution::RoughnessToAlpha`.
pub fn roughness_to_alpha_v3(r: f64) -> f64 {
    let x = r.max(1e-3).ln();
    1.62142 + 0.819955 * x + 0.1734 * x * x + 0.0171201 * x * x * x + 0.000640711 * x * x * x * x
}

/// The GGX alpha of a material's roughness parameters (`roughness`, or the mean of `uroughness`/`vroughness`).
fn alpha(c: &mut Converter, p: &Params, default: f64, pos: &SourcePos) -> Result<String> {
    let remap = p.bool("remaproughness", true)?;
    let version = c.version;
    let to_alpha = move |r: f64| -> f64 {
        let a = if !remap || r <= 0.0 {
            r
        } else if version == Version::V3 {
            roughness_to_alpha_v3(r)
        } else {
            r.sqrt()
        };
        a.clamp(0.0, 1.0)
    };
    let (u, v) = (p.float_or_texture("uroughness")?, p.float_or_texture("vroughness")?);
    if let (Some(FloatParam::Value(u)), Some(FloatParam::Value(v))) = (&u, &v) {
        if (u - v).abs() > 1e-6 * u.abs().max(v.abs()) {
            c.warn("anisotropic roughness (uroughness != vroughness) is approximated by their mean");
        }
        return Ok(num(to_alpha(0.5 * (u + v))));
    }
    let key = if p.has("roughness") {
        "roughness"
    } else if u.is_some() {
        "uroughness"
    } else {
        "roughness"
    };
    if matches!(p.float_or_texture(key)?, Some(FloatParam::Texture(_))) && remap {
        c.warn("a textured roughness is used as the GGX alpha without pbrt's remapping");
        return scalar(c, p, key, default, |x| x, pos);
    }
    scalar(c, p, key, default, to_alpha, pos)
}

/// The index of refraction (`eta`, or v3's `index`), a number or a named glass.
fn ior(c: &mut Converter, p: &Params, default: f64, pos: &SourcePos) -> Result<f64> {
    let key = if p.has("eta") { "eta" } else { "index" };
    let v = match p.spectrum(key)? {
        None => default,
        Some(SpectrumParam::Rgb(v)) => {
            if (v[0] - v[1]).abs() > 1e-6 || (v[1] - v[2]).abs() > 1e-6 {
                c.warn("a dispersive index of refraction is approximated by its green value");
            }
            v[1]
        }
        Some(SpectrumParam::Named(n)) => match named_spectrum(&n) {
            Some(NamedSpectrum::Constant(v)) => v,
            _ => return Err(bad(pos, format!("eta: unknown spectrum \"{n}\""))),
        },
        Some(_) => {
            c.warn("a spectral or textured index of refraction is approximated by 1.5");
            1.5
        }
    };
    if !(v.is_finite() && v > 0.0) {
        return Err(bad(
            &p.pos_of(key).unwrap_or(pos.clone()),
            format!("index of refraction must be positive, got {v}"),
        ));
    }
    Ok(v)
}

/// A conductor's Fresnel parameters as RON fields (`material: "Cu"`, `eta: .., k: ..` or `reflectance: ..`).
fn conductor_fresnel(c: &mut Converter, p: &Params, prefix: &str, pos: &SourcePos) -> Result<String> {
    let (ke, kk, kr) = (format!("{prefix}eta"), format!("{prefix}k"), format!("{prefix}reflectance"));
    if p.has(&kr) {
        return Ok(format!("reflectance: {}", color(c, p, &kr, [1.0; 3], pos)?));
    }
    let named = |s: &Option<SpectrumParam>| match s {
        Some(SpectrumParam::Named(n)) => named_spectrum(n),
        _ => None,
    };
    let (eta, k) = (p.spectrum(&ke)?, p.spectrum(&kk)?);
    match (&eta, &k) {
        (None, None) => Ok("material: \"Cu\"".into()),
        _ => {
            if let (
                Some(NamedSpectrum::Metal { metal: a, part: MetalPart::Eta }),
                Some(NamedSpectrum::Metal { metal: b, part: MetalPart::K }),
            ) = (named(&eta), named(&k))
                && a == b
            {
                return Ok(format!("material: {}", quote(a)));
            }
            let mut part = |s: &Option<SpectrumParam>, what: &str, default: &str| -> Result<[f64; 3]> {
                match s {
                    None => Ok(prism_core::material::metals::metal(default)
                        .map(|(e, k)| if what == "eta" { e } else { k })
                        .expect("Cu")
                        .to_array()
                        .map(|x| x as f64)),
                    Some(SpectrumParam::Named(n)) => match named_spectrum(n) {
                        Some(NamedSpectrum::Metal { metal, part }) => {
                            let (e, k) = prism_core::material::metals::metal(metal).expect("known metal");
                            Ok(if part == MetalPart::Eta { e } else { k }.to_array().map(|x| x as f64))
                        }
                        _ => Err(bad(
                            pos,
                            format!("{what}: unknown metal spectrum \"{n}\" (known: metal-Au/Ag/Al/Cu-eta/k)"),
                        )),
                    },
                    Some(SpectrumParam::Texture(_)) => {
                        Err(bad(pos, format!("{what}: a textured index is not supported")))
                    }
                    Some(s) => Ok(spectrum_rgb(c, s, what, pos)?.expect("constant")),
                }
            };
            let e = part(&eta, "eta", "Cu")?;
            let k = part(&k, "k", "Cu")?;
            Ok(format!("eta: {}, k: {}", tuple3(e.map(|x| x.max(0.0))), tuple3(k.map(|x| x.max(0.0)))))
        }
    }
}

/// Add a material to the RON table; returns its name.
fn add_material(c: &mut Converter, text: String, named: Option<&str>) -> String {
    match named {
        Some(n) => {
            let key = format!("named:{n}");
            c.materials.insert(key.clone(), text);
            key
        }
        None => {
            if let Some(k) = c.material_dedupe.get(&text) {
                return k.clone();
            }
            let key = format!("m{}", c.next_id());
            c.material_dedupe.insert(text.clone(), key.clone());
            c.materials.insert(key.clone(), text);
            key
        }
    }
}

/// `Material "type" ...` or `MakeNamedMaterial`: the RON name of the material.
pub fn material(c: &mut Converter, ty: &str, p: &Params, pos: &SourcePos, named: Option<&str>) -> Result<String> {
    let approx = |c: &mut Converter, what: &str| c.warn(format!("material \"{ty}\" is approximated by {what}"));
    let text = match ty {
        "matte" => {
            if !matches!(p.float_or_texture("sigma")?, None | Some(FloatParam::Value(0.0))) {
                approx(c, "Lambert (Oren-Nayar roughness ignored)");
            }
            format!("Lambert(albedo: {})", color(c, p, "Kd", [0.5; 3], pos)?)
        }
        "diffuse" => format!("Lambert(albedo: {})", color(c, p, "reflectance", [0.5; 3], pos)?),
        "mirror" => format!("Mirror(reflectance: {})", color(c, p, "Kr", [0.9; 3], pos)?),
        "thindielectric" => format!("ThinDielectric(ior: {})", num(ior(c, p, 1.5, pos)?)),
        "diffusetransmission" => {
            let scale = p.float("scale", 1.0)?;
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(bad(&p.pos_of("scale").unwrap_or(pos.clone()), format!("scale must be >= 0, got {scale}")));
            }
            let r = color_scaled(c, p, "reflectance", [0.25; 3], scale, pos)?;
            let t = color_scaled(c, p, "transmittance", [0.25; 3], scale, pos)?;
            format!("DiffuseTransmission(reflectance: {r}, transmittance: {t})")
        }
        "glass" | "dielectric" => {
            let eta = ior(c, p, 1.5, pos)?;
            let a = alpha(c, p, 0.0, pos)?;
            let (kr, kt) = if ty == "glass" {
                (color(c, p, "Kr", [1.0; 3], pos)?, color(c, p, "Kt", [1.0; 3], pos)?)
            } else {
                (tuple3([1.0; 3]), tuple3([1.0; 3]))
            };
            format!("RoughDielectric(alpha: {a}, ior: {}, reflectance: {kr}, transmittance: {kt})", num(eta))
        }
        "metal" | "conductor" => {
            let a = alpha(c, p, if ty == "metal" { 0.01 } else { 0.0 }, pos)?;
            let f = conductor_fresnel(c, p, "", pos)?;
            format!("RoughConductor(alpha: {a}, {f})")
        }
        "coatedconductor" => {
            let coat = prefixed(p, "interface.", &["roughness", "uroughness", "vroughness", "eta"]);
            let a = alpha(c, &coat, 0.0, pos)?;
            let eta = ior(c, &coat, 1.5, pos)?;
            let ca = alpha_prefixed(c, p, "conductor.", pos)?;
            let f = if p.has("reflectance") {
                format!("reflectance: {}", color(c, p, "reflectance", [1.0; 3], pos)?)
            } else {
                conductor_fresnel(c, p, "conductor.", pos)?
            };
            let layer = layer_fields(c, p, pos)?;
            format!("CoatedConductor(alpha: {a}, ior: {}, conductor_alpha: {ca}, {f}, {layer})", num(eta))
        }
        "coateddiffuse" => {
            let r = color(c, p, "reflectance", [0.5; 3], pos)?;
            let a = alpha(c, p, 0.0, pos)?;
            let eta = ior(c, p, 1.5, pos)?;
            let layer = layer_fields(c, p, pos)?;
            format!("CoatedDiffuse(reflectance: {r}, alpha: {a}, ior: {}, {layer})", num(eta))
        }
        "plastic" | "substrate" | "uber" => {
            let (kd_name, kd, ks_name, ks, rough, eta) = match ty {
                "plastic" => ("Kd", 0.25, "Ks", 0.25, 0.1, 1.5),
                "substrate" => ("Kd", 0.5, "Ks", 0.5, 0.1, 1.5),
                "uber" => ("Kd", 0.25, "Ks", 0.25, 0.1, 1.5),
                _ => unreachable!("the plastic family"),
            };
            let diffuse = color(c, p, kd_name, [kd; 3], pos)?;
            let specular = if ks_name.is_empty() { tuple3([1.0; 3]) } else { color(c, p, ks_name, [ks; 3], pos)? };
            let eta = ior(c, p, eta, pos)?;
            let a = alpha(c, p, rough, pos)?;
            if ty == "uber" {
                for q in ["Kr", "Kt"] {
                    if p.spectrum(q)?.is_some_and(|s| s != SpectrumParam::Rgb([0.0; 3])) {
                        c.warn(format!("material \"uber\": \"{q}\" (mirror/transmission layer) is ignored"));
                    }
                }
                if p.spectrum("opacity")?.is_some_and(|s| s != SpectrumParam::Rgb([1.0; 3])) {
                    c.warn("material \"uber\": \"opacity\" is ignored (opaque)");
                }
            }
            // A coat of index 1 reflects nothing (Fresnel 0): pbrt's uber with index 1 is its diffuse layer.
            if (eta - 1.0).abs() < 1e-6 || specular == tuple3([0.0; 3]) {
                approx(c, "Lambert (its specular layer reflects nothing: index 1 or Ks = 0)");
                format!("Lambert(albedo: {diffuse})")
            } else {
                if ty != "plastic" {
                    approx(c, "RoughPlastic (a diffuse base under a GGX dielectric coat)");
                }
                format!("RoughPlastic(alpha: {a}, ior: {}, diffuse: {diffuse}, specular: {specular})", num(eta))
            }
        }
        "mix" => {
            let names = match p.strings("materials")? {
                Some(v) if v.len() == 2 => v,
                Some(v) => {
                    return Err(bad(pos, format!("material \"mix\": \"materials\" needs 2 names, got {}", v.len())));
                }
                None => {
                    let a = p
                        .string("namedmaterial1")?
                        .ok_or_else(|| bad(pos, "material \"mix\": no \"namedmaterial1\"".into()))?;
                    let b = p
                        .string("namedmaterial2")?
                        .ok_or_else(|| bad(pos, "material \"mix\": no \"namedmaterial2\"".into()))?;
                    vec![a, b]
                }
            };
            let mut ron = Vec::new();
            for n in &names {
                let m = c
                    .named_materials
                    .get(n)
                    .cloned()
                    .ok_or_else(|| bad(pos, format!("material \"mix\": unknown material \"{n}\"")))?;
                // Blends hold plain materials: a bump-mapped component keeps its base.
                let base = c
                    .materials
                    .get(&m)
                    .and_then(|t| t.strip_prefix("Bump(material: "))
                    .and_then(|t| t.split('"').nth(1))
                    .map(str::to_string);
                if base.is_some() {
                    c.warn("material \"mix\": a bump map of a mixed material is left out");
                }
                ron.push(base.unwrap_or(m));
            }
            let w = scalar(c, p, "amount", 0.5, |x| x.clamp(0.0, 1.0), pos)?;
            format!("Blend(a: {}, b: {}, weight: {w})", quote(&ron[0]), quote(&ron[1]))
        }
        "interface" | "" | "none" => return Ok(INTERFACE.into()),
        other => {
            approx(c, "Lambert");
            let key = if p.has("reflectance") { "reflectance" } else { "Kd" };
            for q in p.list.iter().map(|q| q.name.clone()).collect::<Vec<_>>() {
                p.has(&q);
            }
            let _ = other;
            format!("Lambert(albedo: {})", color(c, p, key, [0.5; 3], pos)?)
        }
    };
    p.has("type");
    let bump_key = if p.has("bumpmap") { "bumpmap" } else { "displacement" };
    let bump = matches!(p.float_or_texture(bump_key)?, Some(FloatParam::Texture(_)));
    let normal_map = p.string("normalmap")?;
    let base = add_material(c, text, if bump || normal_map.is_some() { None } else { named });
    // Bump and normal maps wrap the material (a constant bump height changes nothing).
    if bump {
        let h = scalar(c, p, bump_key, 0.0, |x| x, pos)?;
        return Ok(add_material(c, format!("Bump(material: {}, height: {h})", quote(&base)), named));
    }
    if let Some(f) = normal_map {
        let path = c.resolve(&f);
        if !path.is_file() {
            return Err(bad(
                &p.pos_of("normalmap").unwrap_or(pos.clone()),
                format!("normal map not found: {}", path.display()),
            ));
        }
        let tex = format!("normalmap:{f}");
        c.textures.insert(tex.clone(), format!("Image(path: {}, raw: true)", quote(&c.ron_path(&path))));
        let text = format!("NormalMap(material: {}, texture: {}, flip_green: true)", quote(&base), quote(&tex));
        return Ok(add_material(c, text, named));
    }
    Ok(base)
}

/// The parameters of `p` named `prefix` + one of `names`, without the prefix (`interface.eta` as `eta`), each
/// marked as used.
fn prefixed(p: &Params, prefix: &str, names: &[&str]) -> Params {
    let mut q = Params { list: Vec::new(), file: p.file.clone() };
    for item in &p.list {
        if let Some(rest) = item.name.strip_prefix(prefix)
            && names.contains(&rest)
        {
            p.has(&item.name);
            let mut it = item.clone();
            it.name = rest.to_string();
            q.list.push(it);
        } else if item.name == "remaproughness" {
            p.has(&item.name);
            q.list.push(item.clone());
        }
    }
    q
}

/// The layer's RON fields of a coated material (pbrt-v4's `thickness`, `albedo`, `g`, `maxdepth`, `nsamples`),
/// checked here so that an error points at the pbrt line.
fn layer_fields(c: &mut Converter, p: &Params, pos: &SourcePos) -> Result<String> {
    for key in ["thickness", "g"] {
        if matches!(p.float_or_texture(key)?, Some(FloatParam::Texture(_))) {
            c.warn(format!("a textured \"{key}\" of a coated material is approximated by pbrt's default"));
        }
    }
    let float = |key: &str, default: f64| -> Result<f64> {
        Ok(match p.float_or_texture(key)? {
            Some(FloatParam::Value(v)) => v,
            _ => default,
        })
    };
    let (thickness, g) = (float("thickness", 0.01)?, float("g", 0.0)?);
    let at = |key: &str| p.pos_of(key).unwrap_or(pos.clone());
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(bad(&at("thickness"), format!("thickness must be positive, got {thickness}")));
    }
    if !(-1.0..=1.0).contains(&g) {
        return Err(bad(&at("g"), format!("g must be in [-1, 1], got {g}")));
    }
    let (depth, samples) = (p.int("maxdepth", 10)?, p.int("nsamples", 1)?);
    if !(1..=100).contains(&depth) {
        return Err(bad(&at("maxdepth"), format!("maxdepth must be in 1..=100, got {depth}")));
    }
    if !(1..=64).contains(&samples) {
        return Err(bad(&at("nsamples"), format!("nsamples must be in 1..=64, got {samples}")));
    }
    let albedo = color(c, p, "albedo", [0.0; 3], pos)?;
    Ok(format!(
        "thickness: {}, albedo: {albedo}, g: {}, max_depth: {depth}, samples: {samples}",
        num(thickness),
        num(g)
    ))
}

fn alpha_prefixed(c: &mut Converter, p: &Params, prefix: &str, pos: &SourcePos) -> Result<String> {
    let mut q = Params { list: Vec::new(), file: p.file.clone() };
    for item in &p.list {
        if let Some(rest) = item.name.strip_prefix(prefix)
            && matches!(rest, "roughness" | "uroughness" | "vroughness")
        {
            p.has(&item.name);
            let mut it = item.clone();
            it.name = rest.to_string();
            q.list.push(it);
        }
    }
    if p.has("remaproughness") {
        q.list.extend(p.list.iter().filter(|i| i.name == "remaproughness").cloned());
    }
    alpha(c, &q, 0.0, pos)
}
