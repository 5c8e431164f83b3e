//! `prism convert IN.txt -o OUT.ron`: a 6.837 scene written as the equivalent Prism RON scene (mesh paths
//! relative to the output file). The result is parsed back before it is written, so a written file always loads.

use crate::error::PrismError;
use crate::load::{mit6837, parse_scene};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Debug, Clone)]
pub struct ConvertArgs {
    /// A 6.837 scene file (.txt).
    pub input: PathBuf,
    /// The RON scene to write (.ron).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write assignment 8's meshes as the exact surfaces of their spline files (`tessellation: None`).
    #[arg(long)]
    pub exact_curves: bool,
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    let ext = |p: &Path| p.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    if ext(&args.input) != "txt" {
        return Err(PrismError::invalid(format!("{}: expected a 6.837 scene (.txt)", args.input.display())).into());
    }
    if ext(&args.output) != "ron" {
        return Err(PrismError::invalid(format!("{}: the output must be a .ron file", args.output.display())).into());
    }
    let out_dir = match args.output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let text = mit6837::convert_file(&args.input, &out_dir, args.exact_curves)?.ron;
    parse_scene(&text, &args.output)?;
    std::fs::write(&args.output, text).map_err(|e| PrismError::io(&args.output, e))?;
    Ok(())
}
