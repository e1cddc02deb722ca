//! The `swimbot` binary: parse, run, map errors to exit codes (2 for bad
//! input, 1 for other failures). All the work lives in the library.
use clap::Parser;
use std::process::ExitCode;
use swimbot::cli::{run, Cli};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("swimbot: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
