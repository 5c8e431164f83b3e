//! pbrt textures as Prism's: `imagemap` as an image texture (pbrt's orientation kept: meshes' uvs become
//! `(u, 1 - v)`, so `uscale`/`vscale`/`udelta`/`vdelta` become `uv_scale: (su, sv)`, `uv_offset: (du, 1 - sv - dv)`),
//! `constant` and `scale` folded into the value or the image's factor; the procedural textures are approximated
//! (one warning each). Materials read a texture's [`TexValue`].

use super::Version;
use super::convert::{Converter, num, quote};
use super::materials::{TexValue, bad};
use super::params::{FloatParam, Params, SpectrumParam};
use prism_core::error::{Result, SourcePos};

/// `Texture "name" "float"|"spectrum" "class" ...`.
pub fn texture(c: &mut Converter, name: &str, kind: &str, class: &str, p: &Params, pos: &SourcePos) -> Result<()> {
    let float = match kind {
        "float" => true,
        "spectrum" | "color" | "rgb" => false,
        other => {
            return Err(bad(pos, format!("Texture \"{name}\": unknown texture type \"{other}\" (float or spectrum)")));
        }
    };
    let lookup = |c: &Converter, key: &str, default: [f64; 3]| -> Result<TexValue> {
        Ok(match (p.spectrum(key)?, p.float_or_texture(key).ok().flatten()) {
            (Some(SpectrumParam::Texture(t)), _) | (_, Some(FloatParam::Texture(t))) => c
                .tex_values
                .get(&(float, t.clone()))
                .or_else(|| c.tex_values.get(&(!float, t.clone())))
                .cloned()
                .ok_or_else(|| bad(pos, format!("Texture \"{name}\": unknown texture \"{t}\"")))?,
            (Some(SpectrumParam::Rgb(v)), _) => TexValue::Const(v),
            (_, Some(FloatParam::Value(v))) => TexValue::Const([v; 3]),
            _ => TexValue::Const(default),
        })
    };
    let value = match class {
        "imagemap" => {
            let f = p
                .string("filename")?
                .ok_or_else(|| bad(pos, format!("Texture \"{name}\": imagemap needs \"string filename\"")))?;
            let path = c.resolve(&f);
            if !path.is_file() {
                return Err(bad(
                    &p.pos_of("filename").unwrap_or(pos.clone()),
                    format!("Texture \"{name}\": image not found: {}", path.display()),
                ));
            }
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            let eight_bit = matches!(ext.as_str(), "png" | "tga" | "jpg" | "jpeg" | "bmp");
            // pbrt-v4's `encoding`: "sRGB", "linear" or "gamma g" (8- and 16-bit images; float ones are linear).
            let (srgb, gamma) = match (c.version, p.string("encoding")?) {
                (_, Some(e)) if e == "sRGB" => (true, None),
                (_, Some(e)) if e == "linear" => (false, None),
                (_, Some(e)) => match e.strip_prefix("gamma ").map(|g| g.trim().parse::<f64>()) {
                    Some(Ok(g)) if g.is_finite() && g > 0.0 => (false, Some(g)),
                    _ => {
                        return Err(bad(
                            &p.pos_of("encoding").unwrap_or(pos.clone()),
                            format!("Texture \"{name}\": unknown encoding \"{e}\" (sRGB, linear or \"gamma g\")"),
                        ));
                    }
                },
                (Version::V3, None) => (p.bool("gamma", eight_bit)?, None),
                (Version::V4, None) => (eight_bit, None),
            };
            p.has("gamma");
            let (su, sv) = (p.float("uscale", 1.0)?, p.float("vscale", 1.0)?);
            let (du, dv) = (p.float("udelta", 0.0)?, p.float("vdelta", 0.0)?);
            let wrap = match p.string("wrap")?.as_deref() {
                None | Some("repeat") => "repeat",
                Some("clamp") => "clamp",
                Some("black") => {
                    c.warn("texture wrap \"black\" is approximated by \"clamp\"");
                    "clamp"
                }
                Some(other) => return Err(bad(pos, format!("Texture \"{name}\": unknown wrap mode \"{other}\""))),
            };
            if p.bool("invert", false)? {
                c.warn("texture \"invert\" is ignored");
            }
            if let Some(m) = p.string("mapping")?
                && m != "uv"
            {
                c.warn(format!("texture mapping \"{m}\" is approximated by the uv mapping"));
            }
            for q in ["filter", "maxanisotropy", "trilinear"] {
                p.has(q);
            }
            let scale = p.float("scale", 1.0)?;
            let ron = format!("{}:{name}", if float { "f" } else { "s" });
            c.textures.insert(
                ron.clone(),
                format!(
                    "Image(path: {}, raw: {}, wrap: {wrap}, uv_scale: ({}, {}), uv_offset: ({}, {}){})",
                    quote(&c.ron_path(&path)),
                    !srgb && gamma.is_none(),
                    num(su),
                    num(sv),
                    num(du),
                    num(1.0 - sv - dv),
                    gamma.map_or(String::new(), |g| format!(", gamma: Some({})", num(g)))
                ),
            );
            TexValue::Image { ron, scale: [scale.max(0.0); 3] }
        }
        "constant" => lookup(c, "value", [1.0; 3])?,
        "scale" => {
            let (a, b) = if p.has("tex1") { ("tex1", "tex2") } else { ("tex", "scale") };
            match (lookup(c, a, [1.0; 3])?, lookup(c, b, [1.0; 3])?) {
                (TexValue::Const(x), TexValue::Const(y)) => TexValue::Const([x[0] * y[0], x[1] * y[1], x[2] * y[2]]),
                (TexValue::Image { ron, scale }, TexValue::Const(k))
                | (TexValue::Const(k), TexValue::Image { ron, scale }) => {
                    TexValue::Image { ron, scale: [scale[0] * k[0], scale[1] * k[1], scale[2] * k[2]] }
                }
                (TexValue::Mix { ron, a, b }, TexValue::Const(k))
                | (TexValue::Const(k), TexValue::Mix { ron, a, b }) => {
                    TexValue::Mix { ron, a: [0, 1, 2].map(|i| a[i] * k[i]), b: [0, 1, 2].map(|i| b[i] * k[i]) }
                }
                (img, _) => {
                    c.warn("a \"scale\" texture of two image textures keeps the first only");
                    img
                }
            }
        }
        "checkerboard"
            if matches!(
                (lookup(c, "tex1", [1.0; 3])?, lookup(c, "tex2", [0.0; 3])?),
                (TexValue::Const(_), TexValue::Const(_))
            ) =>
        {
            // pbrt: tex1 where floor(s) + floor(t) (+ floor(z)) is even, tex2 elsewhere; point-sampled here.
            let (TexValue::Const(x), TexValue::Const(y)) = (lookup(c, "tex1", [1.0; 3])?, lookup(c, "tex2", [0.0; 3])?)
            else {
                unreachable!("matched above")
            };
            let ron = format!("{}:{name}", if float { "f" } else { "s" });
            let text = match p.int("dimension", 2)? {
                2 => {
                    if let Some(m) = p.string("mapping")?
                        && m != "uv"
                    {
                        c.warn(format!("texture mapping \"{m}\" is approximated by the uv mapping"));
                    }
                    let (su, sv) = (p.float("uscale", 1.0)?, p.float("vscale", 1.0)?);
                    let (du, dv) = (p.float("udelta", 0.0)?, p.float("vdelta", 0.0)?);
                    // Prism's v is pbrt's 1 - v: sv v + dv = -sv v' + (sv + dv).
                    format!(
                        "Checker2d(uv_scale: ({}, {}), uv_offset: ({}, {}))",
                        num(su),
                        num(-sv),
                        num(du),
                        num(sv + dv)
                    )
                }
                3 => format!("Checker3d(transform: [{}])", super::convert::matrix_op(&c.ctm.inverse())),
                d => {
                    return Err(bad(
                        &p.pos_of("dimension").unwrap_or(pos.clone()),
                        format!("Texture \"{name}\": checkerboard dimension must be 2 or 3, got {d}"),
                    ));
                }
            };
            p.has("aamode");
            c.textures.insert(ron.clone(), text);
            TexValue::Mix { ron, a: x, b: y }
        }
        "mix" if matches!(p.float_or_texture("amount")?, Some(FloatParam::Texture(_))) => {
            let (x, y) = (lookup(c, "tex1", [0.0; 3])?, lookup(c, "tex2", [1.0; 3])?);
            let amount = lookup(c, "amount", [0.5; 3])?;
            match (x, y, amount) {
                (TexValue::Const(x), TexValue::Const(y), TexValue::Mix { ron, a, b })
                    if a == [0.0; 3] && b == [1.0; 3] =>
                {
                    TexValue::Mix { ron, a: x, b: y }
                }
                (TexValue::Const(x), TexValue::Const(y), TexValue::Image { ron, scale }) if scale == [1.0; 3] => {
                    TexValue::Mix { ron, a: x, b: y }
                }
                (x, _, _) => {
                    c.warn("texture \"mix\" by a texture of image textures or a scaled amount keeps its first texture");
                    x
                }
            }
        }
        "mix" | "directionmix" | "checkerboard" => {
            let (a, b) = ("tex1", "tex2");
            let defaults = if class == "checkerboard" { ([1.0; 3], [0.0; 3]) } else { ([0.0; 3], [1.0; 3]) };
            let (x, y) = (lookup(c, a, defaults.0)?, lookup(c, b, defaults.1)?);
            let t = if class == "checkerboard" { 0.5 } else { p.float("amount", 0.5).unwrap_or(0.5) };
            for q in p.list.iter().map(|q| q.name.clone()).collect::<Vec<_>>() {
                p.has(&q);
            }
            match (x, y) {
                (TexValue::Const(x), TexValue::Const(y)) => {
                    if class != "mix" {
                        c.warn(format!("texture \"{class}\" is approximated by the mean of its two values"));
                    }
                    TexValue::Const([0, 1, 2].map(|k| (1.0 - t) * x[k] + t * y[k]))
                }
                (img @ (TexValue::Image { .. } | TexValue::Mix { .. }), _)
                | (_, img @ (TexValue::Image { .. } | TexValue::Mix { .. })) => {
                    c.warn(format!("texture \"{class}\" of an image texture keeps that image only"));
                    img
                }
            }
        }
        other => {
            c.warn(format!("texture \"{other}\" is approximated by a constant 0.5"));
            for q in p.list.iter().map(|q| q.name.clone()).collect::<Vec<_>>() {
                p.has(&q);
            }
            TexValue::Const([0.5; 3])
        }
    };
    c.tex_values.insert((float, name.to_string()), value);
    Ok(())
}
