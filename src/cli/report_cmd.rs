//! `prism report SUITE.ron -o DIR [--threads N] [--note TEXT]`: render and measure a suite and write the atlas
//! page `DIR/index.html` with its pictures and CSV files (see `report/`). Exits non-zero when an item of the suite
//! could not be measured (the page names it; everything else is written).

use clap::Args;
use prism_core::error::PrismError;
use prism_lab::report::{ReportOptions, run as run_report};
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct ReportArgs {
    /// The suite (RON): scenes with references, methods and budgets; accelerators; stability cases.
    pub suite: PathBuf,
    /// Output directory for index.html, img/ and the CSV files.
    #[arg(short, long = "output")]
    pub output: PathBuf,
    /// Render threads (default: the suite's, else every core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// A line for the page's footnote (e.g. how the machine was shared while measuring).
    #[arg(long)]
    pub note: Option<String>,
}

pub fn run(a: ReportArgs) -> anyhow::Result<()> {
    let command = std::iter::once("prism".to_string())
        .chain(std::env::args().skip(1).map(|s| if s.contains(' ') { format!("'{s}'") } else { s }))
        .collect::<Vec<_>>()
        .join(" ");
    let opts = ReportOptions { threads: a.threads, note: a.note, command };
    let outcome = run_report(&a.suite, &a.output, &opts, &crate::DefaultPlugins)?;
    eprintln!("report: wrote {} in {:.0} s", outcome.index.display(), outcome.seconds);
    match outcome.problems.first() {
        None => Ok(()),
        Some(p) => Err(PrismError::invalid(format!(
            "{} item(s) could not be measured (listed in {}); first: {} / {}: {}",
            outcome.problems.len(),
            outcome.index.display(),
            p.section,
            p.item,
            p.message
        ))
        .into()),
    }
}
