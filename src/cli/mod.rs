//! The `prism` command line (clap), per DESIGN section 3: `render`, `compare`, `converge`.

mod compare_cmd;
mod converge_cmd;
mod render_cmd;

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
    /// Render a scene (.ron or .obj) to PNG and/or EXR.
    Render(render_cmd::RenderArgs),
    /// Error against a reference as the budget grows: CSV and charts, one curve per integrator.
    Converge(converge_cmd::ConvergeArgs),
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
        Command::Compare { test, reference, json } => compare_cmd::run(&test, &reference, json),
    }
}
