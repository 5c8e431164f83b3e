//! `prism convert IN.txt|IN.pbrt|IN.gltf|IN.glb -o OUT.ron`: a 6.837 or pbrt scene written as the equivalent Prism
//! RON scene (mesh and texture paths relative to the output file), or a glTF file as a RON scene placing it as one
//! `Gltf` entity with its camera and light written out. The result is parsed back before it is written, so a
//! written file always parses.

use clap::Args;
use prism_core::error::PrismError;
use prism_load::{mit6837, parse_scene, pbrt};
use std::path::{Path, PathBuf};

#[derive(Args, Debug, Clone)]
pub struct ConvertArgs {
    /// A 6.837 scene file (.txt), a pbrt-v3/v4 scene (.pbrt) or a glTF file (.gltf, .glb).
    pub input: PathBuf,
    /// The RON scene to write (.ron).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write assignment 8's meshes as the exact surfaces of their spline files (`tessellation: None`).
    #[arg(long)]
    pub exact_curves: bool,
    /// The glTF camera to write, by name or index (default: the first, or one framing the model).
    #[arg(long, value_name = "NAME|INDEX")]
    pub camera: Option<String>,
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    let ext = |p: &Path| p.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let input_ext = ext(&args.input);
    if !["txt", "pbrt", "gltf", "glb"].contains(&input_ext.as_str()) {
        return Err(PrismError::invalid(format!(
            "{}: expected a 6.837 scene (.txt), a pbrt scene (.pbrt) or a glTF file (.gltf, .glb)",
            args.input.display()
        ))
        .into());
    }
    if ext(&args.output) != "ron" {
        return Err(PrismError::invalid(format!("{}: the output must be a .ron file", args.output.display())).into());
    }
    prism_core::io::check_outputs(std::slice::from_ref(&args.output), std::slice::from_ref(&args.input))?;
    let out_dir = match args.output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let text = prism_load::with_loader_stack(|| {
        let text = if input_ext == "gltf" || input_ext == "glb" {
            prism_load::gltf::gltf_to_ron(&args.input, &out_dir, args.camera.as_deref())?
        } else if input_ext == "pbrt" {
            let c = pbrt::convert_file(&args.input, &out_dir)?;
            for w in &c.warnings {
                eprintln!("warning: {w}");
            }
            c.ron
        } else {
            mit6837::convert_file(&args.input, &out_dir, args.exact_curves)?.ron
        };
        parse_scene(&text, &args.output)?;
        Ok(text)
    })?;
    std::fs::write(&args.output, text).map_err(|e| PrismError::io(&args.output, e))?;
    Ok(())
}
