//! The `prism` binary: parse the command line, run it, print any error as one line and exit non-zero.

use clap::Parser;
use clap::error::ErrorKind;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = match prism::cli::Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version go to stdout as usual (a closed stdout is not an error).
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        // No subcommand: the help, then the error line every failure ends with.
        Err(e) if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            eprintln!("error: no command given (see the list above, or `prism render --help`)");
            return ExitCode::FAILURE;
        }
        // A usage error as one line: clap's message up to its usage notes.
        Err(e) => {
            let text = e.to_string();
            let message: Vec<&str> =
                text.lines().take_while(|l| !l.trim().is_empty() && !l.starts_with("Usage:")).map(str::trim).collect();
            eprintln!("{}", prism::error::printable(&message.join(" ")));
            return ExitCode::FAILURE;
        }
    };
    match prism::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", prism::error::printable(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}
