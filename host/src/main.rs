//! The `swimbot` binary: parse, run, map errors to exit codes (2 for bad
//! input, 1 for other failures). All the work lives in the library.
use clap::Parser;
use std::process::ExitCode;
use swimbot::cli::{run, Cli};

fn main() -> ExitCode {
    end_quietly_on_a_closed_pipe();
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("swimbot: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// `swimbot compare --format json | head` must end quietly when `head` stops
/// reading, as `cat` does. Rust ignores SIGPIPE before `main`, so a write to
/// the closed pipe becomes an error, and `println!` panics on it; with the
/// default action restored the kernel ends the process instead. Stable Rust
/// has no switch for this (`-Zon-broken-pipe=kill` is nightly-only), and
/// turning every one of the CLI's prints into a fallible write would only
/// rebuild what the default action already does.
fn end_quietly_on_a_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: first thing in `main`, before any other thread exists, and
    // SIG_DFL is a valid action for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
