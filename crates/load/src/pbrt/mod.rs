//! pbrt-v3 and pbrt-v4 scenes (the subset real scenes use): `prism render scene.pbrt` loads them and `prism
//! convert scene.pbrt -o scene.ron` writes the equivalent RON scene. As for 6.837 scenes, loading goes through
//! that very RON text (PLY meshes stay files that the RON refers to; inline meshes go to its `meshes` table).
//!
//! - `lexer.rs`: words, strings, numbers and brackets with their line and column;
//! - `params.rs`: typed parameter lists;
//! - `convert.rs`: the directives and pbrt's graphics state (transforms, attribute scopes, named coordinate
//!   systems, objects and instances, `Include`/`Import`); `scene_wide.rs`: camera, film, sampler, integrator;
//!   `shapes.rs`, `lights.rs`, `materials.rs`: the world's contents; `spectrum.rs`: spectra to RGB.
//!
//! **Version.** Where pbrt-v3 and pbrt-v4 read the same words differently (spot fall-off, roughness remapping,
//! blackbody normalisation, default film size, alpha), the file's version is guessed from the words only one of
//! them uses (v3: `WorldEnd`, `Film "image"`, materials `matte`/`uber`/`plastic`/`glass`/`metal`/`substrate`,
//! parameter types `color`/`point`/`normal`; v4: `Film "rgb"`, materials `diffuse`/`dielectric`/`conductor`/
//! `coateddiffuse`, types `point3`/`normal3`/`point2`, `ColorSpace`, `Import`, `Attribute`); ties read as v4.
//!
//! Errors are one line, `file:line:column: message` (unknown directives, unbalanced `AttributeEnd`, bad
//! parameter types and counts, out-of-range indices, missing files); what Prism approximates or leaves out is
//! printed once as a warning.

mod convert;
mod curves;
mod lexer;
mod lights;
mod materials;
mod params;
mod scene_wide;
mod shapes;
pub mod spectrum;
mod textures;

pub use materials::roughness_to_alpha_v3;

use lexer::{Tok, tokenize};
use prism_core::error::{PrismError, Result};
use std::path::Path;

/// The pbrt version a file is read as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    V3,
    V4,
}

/// A pbrt scene as RON text, with the warnings of the conversion.
#[derive(Clone, Debug)]
pub struct Converted {
    pub ron: String,
    /// The files read besides the main one (included files, spectra).
    pub files: Vec<std::path::PathBuf>,
    pub warnings: Vec<String>,
    pub version: Version,
}

/// Guess the version from the words of the main file.
fn detect_version(text: &str, file: &Path) -> Result<Version> {
    let tokens = tokenize(text, file)?;
    let (mut v3, mut v4) = (0, 0);
    let mut prev_word = String::new();
    for t in &tokens {
        match &t.tok {
            Tok::Word(w) => {
                match w.as_str() {
                    "WorldEnd" | "TransformBegin" | "TransformEnd" => v3 += 1,
                    "ColorSpace" | "Import" | "Attribute" | "Option" => v4 += 1,
                    _ => {}
                }
                prev_word = w.clone();
            }
            Tok::Str(s) => {
                if let Some(ty) = s.split_whitespace().next().filter(|_| s.contains(' ')) {
                    match ty {
                        "color" | "point" | "normal" | "vector" => v3 += 1,
                        "point3" | "normal3" | "point2" | "vector3" => v4 += 1,
                        _ => {}
                    }
                }
                match (prev_word.as_str(), s.as_str()) {
                    ("Film", "image") => v3 += 1,
                    ("Film", "rgb" | "gbuffer" | "spectral") => v4 += 1,
                    ("Material", "matte" | "uber" | "plastic" | "glass" | "metal" | "substrate" | "translucent") => {
                        v3 += 1
                    }
                    ("Material", "diffuse" | "dielectric" | "conductor" | "coateddiffuse" | "coatedconductor") => {
                        v4 += 1
                    }
                    _ => {}
                }
                if s == "string type" {
                    prev_word = "Material".into();
                }
            }
            _ => {}
        }
    }
    Ok(if v3 > v4 { Version::V3 } else { Version::V4 })
}

/// Convert a pbrt file to RON; paths in the RON are written relative to `ron_dir`.
pub fn convert_file(path: &Path, ron_dir: &Path) -> Result<Converted> {
    if !path.is_file() {
        return Err(PrismError::io(path, std::io::Error::new(std::io::ErrorKind::NotFound, "scene file not found")));
    }
    let text = prism_core::io::read_regular_text(path, "pbrt file")?;
    let search_dir = path.parent().unwrap_or(Path::new("."));
    convert_text(&text, path, Some(search_dir), ron_dir)
}

/// Convert pbrt scene text to RON; `path` names it in errors. Relative paths resolve against `search_dir`; with
/// `None`, no file the scene names is read (`Include`, `Import` and `.spd` spectra are reported missing): scene
/// text converted in memory.
pub fn convert_text(text: &str, path: &Path, search_dir: Option<&Path>, ron_dir: &Path) -> Result<Converted> {
    let version = detect_version(text, path)?;
    let mut c = convert::Converter::new(version, search_dir.unwrap_or(ron_dir), ron_dir);
    c.read_files = search_dir.is_some();
    c.run_text(text, path)?;
    c.finish()?;
    if !c.in_world {
        return Err(PrismError::format(path, "no WorldBegin: the file describes no scene"));
    }
    if c.wide.camera_from_world.is_none() {
        c.warn("no Camera directive: a perspective camera (fov 90) at the origin looking along +z");
    }
    let ron = c.to_ron();
    let name = path.display().to_string();
    let files = c.files_read.take();
    Ok(Converted { ron, files, warnings: c.warnings.iter().map(|w| format!("{name}: {w}")).collect(), version })
}
