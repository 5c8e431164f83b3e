//! The `prism` command line (clap), per DESIGN section 3: `render`, `compare`, `converge`, `bench`, `convert` and `report`,
//! plus `raytracer` (6.837 course command lines).

mod bench_cmd;
mod compare_cmd;
mod converge_cmd;
mod convert_cmd;
mod course_views;
mod merge_cmd;
mod raytracer_cmd;
mod render_cmd;
mod report_cmd;

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
    /// Render a scene (.ron, .obj or 6.837 .txt) to PNG and/or EXR.
    Render(render_cmd::RenderArgs),
    /// Error against a reference as the budget grows: CSV and charts, one curve per integrator.
    Converge(converge_cmd::ConvergeArgs),
    /// Benchmark accelerators on scenes: build time, memory, nodes, Mrays/s (table and chart).
    Bench(bench_cmd::BenchArgs),
    /// Combine the `.prism-film` shards of one render (`render --shard K/N`) into its image, exactly.
    Merge(merge_cmd::MergeArgs),
    /// Convert a 6.837 scene (.txt) to a Prism RON scene.
    Convert(convert_cmd::ConvertArgs),
    /// Run a 6.837 course command line (`-input scene.txt -size 200 200 -output out.tga -grid 5 5 5 ...`).
    Raytracer(raytracer_cmd::RaytracerArgs),
    /// The speed-vs-accuracy and stability atlas of a suite: DIR/index.html with charts, images and CSV.
    Report(report_cmd::ReportArgs),
    /// Compare an image with a reference: RMSE, relMSE, mean absolute error.
    Compare {
        /// The image to test (.exr or .png).
        test: PathBuf,
        /// The reference image (.exr or .png).
        reference: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Run a parsed command line. Errors are returned for `main` to print as one line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render(args) => render_cmd::run(args),
        Command::Converge(args) => converge_cmd::run(args),
        Command::Bench(args) => bench_cmd::run(args),
        Command::Convert(args) => convert_cmd::run(args),
        Command::Merge(args) => merge_cmd::run(args),
        Command::Raytracer(args) => raytracer_cmd::run(args),
        Command::Report(args) => report_cmd::run(args),
        Command::Compare { test, reference, json } => compare_cmd::run(&test, &reference, json),
    }
}
