//! pbrt lights as Prism's (each with the current transform):
//!
//! | pbrt | Prism |
//! |---|---|
//! | `point` `I`, `scale`, `from`; v4 `power` | `Point(intensity: I scale, position: from)`; with `power`: `I = power / (4 pi)` times the colour |
//! | `spot` `I`, `scale`, `from`, `to`, `coneangle` (30), `conedeltaangle` (5); v4 `power` | `Spot(intensity, position: from, target: to, cone_angle, falloff: conedeltaangle, profile: quartic` (v3) `/ smoothstep` (v4)`)` |
//! | `distant` `L`, `scale`, `from` (0 0 0), `to` (0 0 1) | `Directional(irradiance: L scale, direction: to - from)` |
//! | `infinite` `L`, `scale` | `Environment(radiance: L scale)` |
//! | v3 `infinite` `mapname` (equirect, +z up, u = phi / 2 pi from +x) | `Environment(map, layout: Equirect, radiance: L scale)`, the transform times the fixed rotation from pbrt's map frame to Prism's |
//! | v4 `infinite` `filename` (equal-area octahedral square, +z at the centre), `scale` | `Environment(map, layout: EqualArea, radiance: scale)`, the same rotation; `illuminance` is ignored with a warning |
//! | `AreaLightSource "diffuse"` (v3 also `"area"`) `L`, `scale`, `twosided`; v4 `filename` | `Area(radiance: L scale, two_sided, texture)` on the following shapes of the scope |
//!
//! Colours: `rgb`/`color` as they are, `blackbody` (v3 `[T scale]`: peak-normalised Planck spectrum; v4 `T`:
//! normalised to luminance 1, as pbrt-v4 normalises light spectra), sampled spectra through the CIE curves.

use super::Version;
use super::convert::{AreaSpec, Converter, matrix_op, num, quote, short, tuple3};
use super::materials::spectrum_rgb;
use super::params::{Params, SpectrumParam};
use glam::{DMat4, DVec3};
use prism_core::error::{PrismError, Result, SourcePos};
use std::fmt::Write as _;

fn bad(pos: &SourcePos, m: String) -> PrismError {
    PrismError::Parse { pos: pos.clone(), message: m }
}

/// The environment light collected from `infinite` lights (Prism has one).
#[derive(Clone, Debug)]
pub struct EnvSpec {
    pub radiance: [f64; 3],
    /// The map's path and its layout's RON name (`Equirect` for pbrt-v3 `mapname`, `EqualArea` for v4 `filename`).
    pub map: Option<(String, &'static str)>,
    pub transform: DMat4,
    pub label: String,
}

impl EnvSpec {
    pub fn ron(&self) -> String {
        let mut s = format!(
            "(name: {}, transform: [{}], light: Environment(radiance: {}",
            quote(&self.label),
            matrix_op(&self.transform),
            tuple3(self.radiance)
        );
        if let Some((m, layout)) = &self.map {
            let _ = write!(s, ", map: Some({}), layout: Some({layout})", quote(m));
        }
        s.push_str("))");
        s
    }
}

/// A light colour parameter times `scale` (textures are not allowed).
fn light_rgb(c: &mut Converter, p: &Params, name: &str, pos: &SourcePos) -> Result<[f64; 3]> {
    let scale = p.float("scale", 1.0)?;
    let v = match p.spectrum(name)? {
        None => [1.0; 3],
        Some(SpectrumParam::Texture(_)) => return Err(bad(pos, format!("light \"{name}\" cannot be a texture"))),
        Some(s) => spectrum_rgb(c, &s, name, &p.pos_of(name).unwrap_or(pos.clone()))?.expect("constant"),
    };
    let v = v.map(|x| x * scale);
    if !v.iter().all(|x| x.is_finite()) {
        return Err(bad(pos, format!("light \"{name}\" x scale is not finite: {v:?}")));
    }
    Ok(v.map(|x| x.max(0.0)))
}

/// pbrt's map frame to Prism's: pbrt looks an equirect map up by `phi = atan2(y, x)`, `theta = acos(z)` (+z the
/// top row); Prism by `u = 0.5 + atan2(x, -z) / 2 pi`, `v = acos(y) / pi`. The direction `d` in pbrt's frame is
/// `A d` in Prism's with `A: x -> z, y -> -x, z -> y`.
fn pbrt_to_prism_map() -> DMat4 {
    DMat4::from_cols(DVec3::Z.extend(0.0), DVec3::NEG_X.extend(0.0), DVec3::Y.extend(0.0), glam::DVec4::W)
}

/// A `LightSource` directive.
pub fn light_source(c: &mut Converter, ty: &str, p: &Params, pos: &SourcePos) -> Result<()> {
    let label = format!("{}:{} LightSource \"{ty}\"", short(&pos.file), pos.line);
    let det = c.ctm.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(bad(pos, format!("LightSource \"{ty}\": the current transform is singular")));
    }
    let light = match ty {
        "point" => {
            let mut i = light_rgb(c, p, "I", pos)?;
            let power = p.float("power", -1.0)?;
            if power > 0.0 {
                i = i.map(|x| x * power / (4.0 * std::f64::consts::PI));
            }
            let from = p.vec3("from", [0.0; 3])?;
            format!("Point(intensity: {}, position: {})", tuple3(i), tuple3(from))
        }
        "spot" => {
            let mut i = light_rgb(c, p, "I", pos)?;
            let from = p.vec3("from", [0.0; 3])?;
            let to = p.vec3("to", [0.0, 0.0, 1.0])?;
            if from == to {
                return Err(bad(pos, "LightSource \"spot\": \"from\" and \"to\" are the same point".into()));
            }
            let cone = p.float("coneangle", 30.0)?;
            let delta = p.float("conedeltaangle", 5.0)?;
            if !(cone > 0.0 && cone <= 180.0 && delta >= 0.0) {
                return Err(bad(
                    pos,
                    format!(
                        "LightSource \"spot\": coneangle must be in (0, 180] and conedeltaangle >= 0, got {cone} and {delta}"
                    ),
                ));
            }
            let profile = if c.version == Version::V3 { "quartic" } else { "smoothstep" };
            let power = p.float("power", -1.0)?;
            if power > 0.0 {
                let (cs, ce) = ((cone - delta).max(0.0).to_radians().cos(), cone.to_radians().cos());
                let k = 2.0 * std::f64::consts::PI * ((1.0 - cs) + (cs - ce) / 2.0);
                i = i.map(|x| x * power / k);
            }
            format!(
                "Spot(intensity: {}, position: {}, target: Some({}), cone_angle: {}, falloff: {}, profile: {profile})",
                tuple3(i),
                tuple3(from),
                tuple3(to),
                num(cone),
                num(delta.min(cone))
            )
        }
        "distant" => {
            let l = light_rgb(c, p, "L", pos)?;
            let from = p.vec3("from", [0.0; 3])?;
            let to = p.vec3("to", [0.0, 0.0, 1.0])?;
            let d = DVec3::from_array(to) - DVec3::from_array(from);
            if d == DVec3::ZERO {
                return Err(bad(pos, "LightSource \"distant\": \"from\" and \"to\" are the same point".into()));
            }
            if p.has("illuminance") {
                c.warn("distant light \"illuminance\" is ignored (L x scale is the irradiance)");
            }
            format!("Directional(irradiance: {}, direction: {})", tuple3(l), tuple3(d.to_array()))
        }
        "infinite" => {
            let l = light_rgb(c, p, "L", pos)?;
            // pbrt-v3's `mapname` is an equirect panorama, pbrt-v4's `filename` an equal-area octahedral square.
            let map = match (p.string("mapname")?, p.string("filename")?) {
                (Some(m), _) => Some((m, "Equirect")),
                (None, Some(f)) => Some((f, "EqualArea")),
                (None, None) => None,
            };
            let map = match map {
                Some((m, layout)) => {
                    let path = c.resolve(&m);
                    if !path.is_file() {
                        return Err(bad(pos, format!("infinite light: map not found: {}", path.display())));
                    }
                    Some((c.ron_path(&path), layout))
                }
                None => None,
            };
            for q in ["samples", "portal"] {
                p.has(q);
            }
            if p.has("illuminance") {
                c.warn("infinite light \"illuminance\" is ignored (the map's values times \"scale\" are the radiance)");
            }
            let transform = c.ctm * pbrt_to_prism_map().inverse();
            match &mut c.environment {
                None => c.environment = Some(EnvSpec { radiance: l, map, transform, label: label.clone() }),
                Some(env) if env.map.is_none() && map.is_none() => {
                    env.radiance = [0, 1, 2].map(|k| env.radiance[k] + l[k]);
                }
                Some(_) => {
                    c.warn("several infinite lights with maps: only the first is used");
                }
            }
            return Ok(());
        }
        other => {
            for q in &p.list {
                p.has(&q.name);
            }
            c.warn(format!("LightSource \"{other}\" is not supported and is left out"));
            return Ok(());
        }
    };
    let text = format!("(name: {}, transform: [{}], light: {light})", quote(&label), matrix_op(&c.ctm));
    c.push_entity(text);
    Ok(())
}

/// An `AreaLightSource` directive: the emitter of the following shapes in the scope.
pub fn area_light_source(c: &mut Converter, ty: &str, p: &Params, pos: &SourcePos) -> Result<()> {
    // pbrt-v3 also accepts "area", its older name of the diffuse area light.
    if ty != "diffuse" && ty != "area" {
        return Err(bad(pos, format!("AreaLightSource \"{ty}\": only \"diffuse\" (or \"area\") area lights exist")));
    }
    let radiance = light_rgb(c, p, "L", pos)?;
    let two_sided = p.bool("twosided", false)?;
    let texture = match p.string("filename")? {
        None => None,
        Some(f) => {
            let path = c.resolve(&f);
            if !path.is_file() {
                return Err(bad(pos, format!("AreaLightSource: image not found: {}", path.display())));
            }
            let name = format!("emission:{f}");
            c.textures.insert(name.clone(), format!("Image(path: {})", quote(&c.ron_path(&path))));
            Some(name)
        }
    };
    if p.has("power") {
        c.warn("area light \"power\" is ignored (L x scale is the radiance)");
    }
    c.area = Some(AreaSpec { radiance, two_sided, texture });
    Ok(())
}
