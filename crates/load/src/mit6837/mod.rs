//! MIT 6.837 (Fall 2004) scene files, assignments 1-5 and 8: `prism render scene.txt` loads them directly and
//! `prism convert IN.txt -o OUT.ron` writes the equivalent RON scene. Loading goes through that very RON text, so a
//! converted scene spawns exactly what the `.txt` does.
//!
//! - `lexer.rs`: words and braces with their line and column;
//! - `parser.rs`: the course grammar into `ast.rs`, with one-line `file:line:col` errors;
//! - `convert.rs`: the course's conventions in Prism's units, written as RON;
//! - `spline.rs`: assignment 8's spline files (curves, surfaces of revolution, Bézier patches);
//! - `course_meshes.rs`: the meshes assignment 8's scenes name, made from the spline files they came from.

mod ast;
mod convert;
pub mod course_meshes;
mod lexer;
mod parser;
mod solid_parser;
pub mod spline;

pub use ast::{CameraTxt, LightTxt, MaterialTxt, ObjectTxt, OpTxt, PhongTxt, SceneTxt, SolidTxt, SolidTxtKind};
pub use convert::{Converted, DEFAULT_SIZE, relative_path, to_ron};
pub use lexer::{Token, tokenize};
pub use parser::parse_txt;

use prism_core::error::Result;
use std::path::Path;

/// Parse a 6.837 scene file.
pub fn parse_file(path: &Path) -> Result<SceneTxt> {
    let text = prism_core::io::read_regular_text(path, "scene file")?;
    parse_txt(&text, path, path.parent().unwrap_or(Path::new(".")))
}

/// The RON scene equivalent to a 6.837 scene file, with mesh paths relative to `ron_dir`. With `exact_curves`,
/// meshes an assignment 8 scene names are replaced by the exact surfaces of the spline file they were made from.
pub fn convert_file(path: &Path, ron_dir: &Path, exact_curves: bool) -> Result<Converted> {
    to_ron(&parse_file(path)?, path, ron_dir, exact_curves)
}
