//! The `swimbot` binary: parse, run, map errors to exit codes (2 for bad
//! input, 1 for other failures). All the work lives in the library.
use clap::Parser;
use std::process::ExitCode;
use swimbot::cli::{run, Cli};

/// Whether descriptor 1 is open, looked at before the Rust runtime starts
/// (an ELF constructor): the runtime reopens a closed descriptor 1 on
/// /dev/null, after which `>&-` looks like `>/dev/null`.
#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array"]
static NOTE_CLOSED_STDOUT: extern "C" fn() = note_closed_stdout;

#[cfg(target_os = "linux")]
extern "C" fn note_closed_stdout() {
    // SAFETY: F_GETFD only queries descriptor 1's flags.
    if unsafe { libc::fcntl(1, libc::F_GETFD) } < 0 {
        swimbot::cli::note_stdout_closed_at_start();
    }
}

/// A command line clap refuses: `--help` and `--version` print as clap
/// prints them; a mistake gets the prefix every other refusal has
/// (`swimbot: error:`), so that one rule finds every message, and exit 2.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    use std::io::Write;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit();
    }
    let text = e.render().to_string();
    let text = text.strip_prefix("error: ").unwrap_or(&text);
    let _ = write!(std::io::stderr(), "swimbot: error: {text}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    // A reader that stops early (`| head`) is handled in the CLI
    // (`cli::stdout::end_on_closed_stdout`): exit 0, as ripgrep does.
    // The command line is read once, here: the library takes it as a value
    // (the provenance's text), clap the arguments as given.
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let command = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    match run(cli, command) {
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
