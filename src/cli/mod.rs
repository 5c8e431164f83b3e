//! The `prism` command line (clap), per DESIGN section 3: `render`, `watch`, `compare`, `converge`, `bench`, `convert`,
//! `tessellate` and `report`, plus `raytracer` and `curve_editor` (6.837 course command lines).

mod bench_cmd;
mod compare_cmd;
mod converge_cmd;
mod convert_cmd;
mod course_views;
mod merge_cmd;
mod raytracer_cmd;
mod render_cmd;
mod report_cmd;
mod tessellate_cmd;
mod watch;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(name = "prism", version, about = "Prism: a physically based CPU ray tracer")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (.ron, .obj, .ply, .gltf/.glb, .pbrt or a 6.837 .txt) to PNG, EXR, TGA and/or a film.
    Render(render_cmd::RenderArgs),
    /// Render progressively into a viewer page on 127.0.0.1, again whenever the scene or a file it reads changes.
    Watch(watch::WatchArgs),
    /// Error against a reference as the budget grows: CSV and charts, one curve per integrator.
    Converge(converge_cmd::ConvergeArgs),
    /// Benchmark accelerators on scenes: build time, memory, nodes, Mrays/s (table and chart).
    Bench(bench_cmd::BenchArgs),
    /// Combine the `.prism-film` shards of one render (`render --shard K/N`) into its image, exactly.
    Merge(merge_cmd::MergeArgs),
    /// Convert a 6.837 (.txt) or pbrt (.pbrt) scene to the equivalent Prism RON scene.
    Convert(convert_cmd::ConvertArgs),
    /// Run a 6.837 course command line (`-input scene.txt -size 200 200 -output out.tga -grid 5 5 5 ...`).
    Raytracer(raytracer_cmd::RaytracerArgs),
    /// The speed-vs-accuracy and stability atlas of a suite: DIR/index.html with charts, images and CSV.
    Report(report_cmd::ReportArgs),
    /// Tessellate a 6.837 spline file (surfaces of revolution, Bézier patches) into an OBJ mesh.
    Tessellate(tessellate_cmd::TessellateArgs),
    /// Run a 6.837 curve editor command line (`-input spline.txt -curve_tessellation 30 -output out.obj ...`).
    #[command(name = "curve_editor")]
    CurveEditor(tessellate_cmd::CurveEditorArgs),
    /// Compare an image with a reference: RMSE, relMSE, mean absolute error.
    Compare {
        /// The image to test (.exr, .hdr or .png).
        test: PathBuf,
        /// The reference image (.exr, .hdr or .png).
        reference: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Write `text` to stdout. A closed stdout (`prism compare a b | head -1`) ends the output quietly: broken pipes
/// are not errors, and nothing panics; other write errors are reported.
pub(crate) fn print_stdout(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(prism_core::error::PrismError::io("standard output", e).into()),
    }
}

/// Run a parsed command line. Errors are returned for `main` to print as one line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render(args) => render_cmd::run(args),
        Command::Watch(args) => watch::run(args),
        Command::Converge(args) => converge_cmd::run(args),
        Command::Bench(args) => bench_cmd::run(args),
        Command::Convert(args) => convert_cmd::run(args),
        Command::Merge(args) => merge_cmd::run(args),
        Command::Raytracer(args) => raytracer_cmd::run(args),
        Command::Report(args) => report_cmd::run(args),
        Command::Tessellate(args) => tessellate_cmd::run(args),
        Command::CurveEditor(args) => tessellate_cmd::run_curve_editor(args),
        Command::Compare { test, reference, json } => compare_cmd::run(&test, &reference, json),
    }
}
