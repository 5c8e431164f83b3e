//! pbrt parameter lists: `"type name" value` or `"type name" [ values ]`, read with typed getters that check the
//! type and the number of values and name the parameter's position on error. Parameters nobody asked for are
//! reported once (pbrt itself rejects them; Prism warns, since the rest of the scene may still render).

use super::lexer::{Tok, Token};
use prism_core::error::{PrismError, Result, SourcePos};
use std::cell::Cell;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Nums(Vec<f64>),
    Strs(Vec<String>),
    Bools(Vec<bool>),
}

#[derive(Clone, Debug)]
pub struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub pos: SourcePos,
    used: Cell<bool>,
}

/// The parameters of one directive.
#[derive(Clone, Debug, Default)]
pub struct Params {
    pub list: Vec<Param>,
    pub file: PathBuf,
}

/// A spectrum-valued parameter as written.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumParam {
    Rgb([f64; 3]),
    /// `blackbody`: one temperature (pbrt-v4) or (temperature, scale) (pbrt-v3).
    Blackbody(Vec<f64>),
    /// `spectrum` as (wavelength, value) pairs.
    Sampled(Vec<f64>),
    /// `spectrum "name"`: a named spectrum or an `.spd` file.
    Named(String),
    /// `texture`: a texture by name.
    Texture(String),
}

/// A float-valued parameter: a number or a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum FloatParam {
    Value(f64),
    Texture(String),
}

fn err(pos: &SourcePos, message: String) -> PrismError {
    PrismError::Parse { pos: pos.clone(), message }
}

/// Parse the parameter list starting at `tokens[*i]` (stops at the next bare word: the next directive).
pub fn parse_params(tokens: &[Token], i: &mut usize, file: &Path) -> Result<Params> {
    let mut list = Vec::new();
    while let Some(t) = tokens.get(*i) {
        let Tok::Str(decl) = &t.tok else { break };
        let pos = SourcePos { file: file.to_path_buf(), line: t.line, col: t.col };
        let mut words = decl.split_whitespace();
        let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
            return Err(err(&pos, format!("expected a parameter declaration \"type name\", got \"{decl}\"")));
        };
        *i += 1;
        let mut raw: Vec<&Token> = Vec::new();
        match tokens.get(*i).map(|t| &t.tok) {
            Some(Tok::Open) => {
                *i += 1;
                loop {
                    match tokens.get(*i) {
                        None => return Err(err(&pos, format!("parameter \"{decl}\": missing `]`"))),
                        Some(t) if t.tok == Tok::Close => {
                            *i += 1;
                            break;
                        }
                        Some(t) if t.tok == Tok::Open => {
                            return Err(err(
                                &SourcePos { line: t.line, col: t.col, ..pos.clone() },
                                format!("parameter \"{decl}\": nested `[`"),
                            ));
                        }
                        Some(t) => {
                            raw.push(t);
                            *i += 1;
                        }
                    }
                }
            }
            Some(Tok::Num(_) | Tok::Str(_)) => {
                raw.push(&tokens[*i]);
                *i += 1;
            }
            Some(Tok::Word(w)) if w == "true" || w == "false" => {
                raw.push(&tokens[*i]);
                *i += 1;
            }
            _ => return Err(err(&pos, format!("parameter \"{decl}\" has no value"))),
        }
        let values = values_of(ty, &raw, decl, &pos)?;
        list.push(Param { ty: ty.to_string(), name: name.to_string(), values, pos, used: Cell::new(false) });
    }
    Ok(Params { list, file: file.to_path_buf() })
}

fn values_of(ty: &str, raw: &[&Token], decl: &str, pos: &SourcePos) -> Result<Values> {
    let at = |t: &Token| SourcePos { line: t.line, col: t.col, ..pos.clone() };
    match ty {
        "bool" => raw
            .iter()
            .map(|t| match &t.tok {
                Tok::Word(w) | Tok::Str(w) if w == "true" => Ok(true),
                Tok::Word(w) | Tok::Str(w) if w == "false" => Ok(false),
                _ => Err(err(&at(t), format!("parameter \"{decl}\": {} is not true or false", t.describe()))),
            })
            .collect::<Result<_>>()
            .map(Values::Bools),
        "string" | "texture" => raw
            .iter()
            .map(|t| match &t.tok {
                Tok::Str(s) => Ok(s.clone()),
                _ => Err(err(&at(t), format!("parameter \"{decl}\": expected a quoted string, got {}", t.describe()))),
            })
            .collect::<Result<_>>()
            .map(Values::Strs),
        "spectrum" if raw.iter().all(|t| matches!(t.tok, Tok::Str(_))) => raw
            .iter()
            .map(|t| match &t.tok {
                Tok::Str(s) => Ok(s.clone()),
                _ => unreachable!(),
            })
            .collect::<Result<_>>()
            .map(Values::Strs),
        "float" | "integer" | "point" | "point2" | "point3" | "vector" | "vector2" | "vector3" | "normal"
        | "normal3" | "rgb" | "color" | "xyz" | "blackbody" | "spectrum" => raw
            .iter()
            .map(|t| match &t.tok {
                Tok::Num(v) => Ok(*v),
                _ => Err(err(&at(t), format!("parameter \"{decl}\": expected a number, got {}", t.describe()))),
            })
            .collect::<Result<_>>()
            .map(Values::Nums),
        other => Err(err(pos, format!("parameter \"{decl}\": unknown parameter type `{other}`"))),
    }
}

impl Params {
    fn find(&self, name: &str) -> Option<&Param> {
        let p = self.list.iter().rev().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Parameters no getter asked for: (name, position).
    pub fn unused(&self) -> Vec<(&str, &SourcePos)> {
        self.list.iter().filter(|p| !p.used.get()).map(|p| (p.name.as_str(), &p.pos)).collect()
    }

    /// True when the parameter is given (whatever its type); marks it used.
    pub fn has(&self, name: &str) -> bool {
        self.find(name).is_some()
    }

    fn type_err(p: &Param, expected: &str) -> PrismError {
        err(&p.pos, format!("parameter \"{} {}\" should be of type {expected}", p.ty, p.name))
    }

    fn nums(&self, name: &str, types: &[&str], expected: &str) -> Result<Option<(&Param, &[f64])>> {
        match self.find(name) {
            None => Ok(None),
            Some(p) if types.contains(&p.ty.as_str()) => match &p.values {
                Values::Nums(v) => Ok(Some((p, v))),
                _ => Err(Self::type_err(p, expected)),
            },
            Some(p) => Err(Self::type_err(p, expected)),
        }
    }

    /// One float (or integer) value.
    pub fn float(&self, name: &str, default: f64) -> Result<f64> {
        match self.nums(name, &["float", "integer"], "float")? {
            None => Ok(default),
            Some((_, [v])) => Ok(*v),
            Some((p, v)) => Err(err(&p.pos, format!("parameter \"{}\": expected 1 value, got {}", p.name, v.len()))),
        }
    }

    /// One integer value.
    pub fn int(&self, name: &str, default: i64) -> Result<i64> {
        match self.nums(name, &["integer"], "integer")? {
            None => Ok(default),
            Some((_, [v])) if v.fract() == 0.0 && v.abs() < 9e15 => Ok(*v as i64),
            Some((p, v)) => Err(err(&p.pos, format!("parameter \"{}\": expected one integer, got {v:?}", p.name))),
        }
    }

    /// All values of a float/integer array parameter.
    pub fn floats(&self, name: &str) -> Result<Option<Vec<f64>>> {
        Ok(self.nums(name, &["float", "integer"], "float")?.map(|(_, v)| v.to_vec()))
    }

    /// Integer array (indices): every value a non-negative integer below 2^32.
    pub fn indices(&self, name: &str) -> Result<Option<Vec<u32>>> {
        match self.nums(name, &["integer"], "integer")? {
            None => Ok(None),
            Some((p, v)) => v
                .iter()
                .enumerate()
                .map(|(k, &x)| {
                    if x.fract() == 0.0 && (0.0..4294967296.0).contains(&x) {
                        Ok(x as u32)
                    } else {
                        Err(err(&p.pos, format!("parameter \"{}\": value {k} ({x}) is not a valid index", p.name)))
                    }
                })
                .collect::<Result<_>>()
                .map(Some),
        }
    }

    /// 3-vectors (point, normal, vector in v3 and v4 spellings), or `None`.
    pub fn vec3s(&self, name: &str) -> Result<Option<Vec<[f64; 3]>>> {
        let types = ["point", "point3", "normal", "normal3", "vector", "vector3"];
        match self.nums(name, &types, "point3")? {
            None => Ok(None),
            Some((p, v)) if v.len() % 3 != 0 => {
                Err(err(&p.pos, format!("parameter \"{}\": {} values is not a multiple of 3", p.name, v.len())))
            }
            Some((_, v)) => Ok(Some(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())),
        }
    }

    /// One 3-vector with a default.
    pub fn vec3(&self, name: &str, default: [f64; 3]) -> Result<[f64; 3]> {
        match self.vec3s(name)? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(v) => {
                let p = self.find(name).expect("present");
                Err(err(&p.pos, format!("parameter \"{}\": expected 3 values, got {}", p.name, 3 * v.len())))
            }
        }
    }

    /// 2-vectors (`point2 uv`, or v3's `float uv`/`float st` as a flat list).
    pub fn vec2s(&self, name: &str) -> Result<Option<Vec<[f64; 2]>>> {
        match self.nums(name, &["point2", "float", "vector2"], "point2")? {
            None => Ok(None),
            Some((p, v)) if v.len() % 2 != 0 => {
                Err(err(&p.pos, format!("parameter \"{}\": {} values is not a multiple of 2", p.name, v.len())))
            }
            Some((_, v)) => Ok(Some(v.chunks_exact(2).map(|c| [c[0], c[1]]).collect())),
        }
    }

    /// One string.
    pub fn string(&self, name: &str) -> Result<Option<String>> {
        match self.find(name) {
            None => Ok(None),
            Some(p) => match (&p.values, p.ty.as_str()) {
                (Values::Strs(v), "string" | "texture") if v.len() == 1 => Ok(Some(v[0].clone())),
                (Values::Strs(v), _) if p.ty == "string" => {
                    Err(err(&p.pos, format!("parameter \"{}\": expected 1 string, got {}", p.name, v.len())))
                }
                _ => Err(Self::type_err(p, "string")),
            },
        }
    }

    /// All strings of a string array.
    pub fn strings(&self, name: &str) -> Result<Option<Vec<String>>> {
        match self.find(name) {
            None => Ok(None),
            Some(p) => match &p.values {
                Values::Strs(v) if p.ty == "string" => Ok(Some(v.clone())),
                _ => Err(Self::type_err(p, "string")),
            },
        }
    }

    /// One bool (`"bool x" true`, `"bool x" "true"` or `[ "true" ]`).
    pub fn bool(&self, name: &str, default: bool) -> Result<bool> {
        match self.find(name) {
            None => Ok(default),
            Some(p) => match &p.values {
                Values::Bools(v) if v.len() == 1 => Ok(v[0]),
                _ => Err(Self::type_err(p, "bool")),
            },
        }
    }

    /// A spectrum: `rgb`/`color`, `blackbody`, `spectrum` (pairs or a name), or a `texture`.
    pub fn spectrum(&self, name: &str) -> Result<Option<SpectrumParam>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        let n = |v: &[f64], k: usize| -> Result<()> {
            if v.len() == k {
                Ok(())
            } else {
                Err(err(&p.pos, format!("parameter \"{} {}\": expected {k} values, got {}", p.ty, p.name, v.len())))
            }
        };
        Ok(Some(match (p.ty.as_str(), &p.values) {
            ("rgb" | "color", Values::Nums(v)) => {
                n(v, 3)?;
                SpectrumParam::Rgb([v[0], v[1], v[2]])
            }
            ("blackbody", Values::Nums(v)) => {
                if v.is_empty() || (v.len() > 1 && v.len() % 2 != 0) {
                    return Err(err(&p.pos, format!("parameter \"blackbody {}\": give a temperature", p.name)));
                }
                // A temperature (every value for pbrt-v4, the first of each pair for pbrt-v3) is in kelvin: above 0.
                let temperatures = v.iter().step_by(if v.len() == 1 { 1 } else { 2 });
                if let Some(t) = temperatures.copied().find(|t| !(t.is_finite() && *t > 0.0)) {
                    return Err(err(
                        &p.pos,
                        format!("parameter \"blackbody {}\": the temperature {t} K is not above 0", p.name),
                    ));
                }
                SpectrumParam::Blackbody(v.clone())
            }
            ("spectrum", Values::Nums(v)) => {
                if v.len() < 4 || v.len() % 2 != 0 {
                    return Err(err(
                        &p.pos,
                        format!("parameter \"spectrum {}\": expected (wavelength, value) pairs", p.name),
                    ));
                }
                SpectrumParam::Sampled(v.clone())
            }
            ("spectrum", Values::Strs(v)) if v.len() == 1 => SpectrumParam::Named(v[0].clone()),
            ("texture", Values::Strs(v)) if v.len() == 1 => SpectrumParam::Texture(v[0].clone()),
            ("float", Values::Nums(v)) if v.len() == 1 => SpectrumParam::Rgb([v[0]; 3]),
            _ => return Err(Self::type_err(p, "rgb, spectrum, blackbody or texture")),
        }))
    }

    /// A float or a float texture.
    pub fn float_or_texture(&self, name: &str) -> Result<Option<FloatParam>> {
        let Some(p) = self.find(name) else { return Ok(None) };
        match (p.ty.as_str(), &p.values) {
            ("float", Values::Nums(v)) if v.len() == 1 => Ok(Some(FloatParam::Value(v[0]))),
            ("texture", Values::Strs(v)) if v.len() == 1 => Ok(Some(FloatParam::Texture(v[0].clone()))),
            _ => Err(Self::type_err(p, "float or texture")),
        }
    }

    /// Position of a parameter (for messages about its value).
    pub fn pos_of(&self, name: &str) -> Option<SourcePos> {
        self.list.iter().rev().find(|p| p.name == name).map(|p| p.pos.clone())
    }
}
