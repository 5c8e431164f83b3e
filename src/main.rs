//! The `prism` binary: parse the command line, run it, print any error as one line and exit non-zero.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = prism::cli::Cli::parse();
    match prism::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", prism::error::printable(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}
