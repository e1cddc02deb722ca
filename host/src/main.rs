//! The `swimbot` binary: parse, run, map errors to exit codes (2 for bad
//! input, 1 for other failures). All the work lives in the library.
use clap::Parser;
use std::process::ExitCode;
use swimbot::cli::{run, Cli};

fn main() -> ExitCode {
    // A reader that stops early (`| head`) is handled in the CLI
    // (`cli::output_guard::end_on_closed_stdout`): exit 0, as ripgrep does.
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Not `eprintln!`: it panics when stderr is a closed pipe, and
            // the exit code must still say why the run failed.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "swimbot: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
