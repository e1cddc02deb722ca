//! Standard output that is closed or fails: a run started with it closed
//! is refused (its results would be lost), a reader that stops early
//! (`| head`) ends the run quietly with exit 0, as ripgrep does, and any
//! other failure to write it is exit 2, after the clean-up
//! ([`super::cleanup`]).

use super::cleanup::clean_up;
use super::CliError;

/// Whether descriptor 1 was closed when the process started, before the
/// Rust runtime's start-up reopened it on /dev/null (which it does so that
/// no file the run opens takes descriptor 1): set by the binary
/// ([`note_stdout_closed_at_start`]), which alone can look that early.
static STDOUT_CLOSED_AT_START: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Called by the binary's start-up hook when descriptor 1 was closed.
pub fn note_stdout_closed_at_start() {
    STDOUT_CLOSED_AT_START.store(true, std::sync::atomic::Ordering::SeqCst);
}

/// Standard output must have been open: started with it closed (`>&-`),
/// every print went to /dev/null and the run ended with exit 0, its
/// output lost. A reader that closed a pipe (`| head`) is another case,
/// a quiet success ([`end_on_closed_stdout`]).
pub fn check_stdout_open() -> Result<(), CliError> {
    if STDOUT_CLOSED_AT_START.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(CliError::input(
            "standard output is closed (`>&-`?): the results would be lost; redirect it to a file or /dev/null instead",
        ));
    }
    Ok(())
}

/// Rust's `println!` panics when stdout cannot be written (a full disk,
/// `> /dev/full`); turn that one panic into the CLI's exit 2 with a
/// message, after the clean-up, or, when the reader closed the pipe, into
/// a quiet end ([`end_on_closed_stdout`]); `eprintln!`'s on stderr into
/// exit 2. Every other panic keeps the default report.
pub fn install_stdout_failure_exit() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(why) = msg.strip_prefix("failed printing to stdout: ") {
            if is_broken_pipe(why) {
                end_on_closed_stdout();
            }
            clean_up();
            eprintln!("swimbot: error: cannot write to standard output: {why}");
            std::process::exit(2);
        }
        // A note on a closed stderr (`2>&1 | head`): the run cannot say
        // what it did, so it fails (exit 2) rather than panic (exit 101).
        if msg.starts_with("failed printing to stderr: ") {
            clean_up();
            std::process::exit(2);
        }
        default(info);
    }));
}

/// The result of a write to stdout: a reader that stopped early (`| head`)
/// ends the run quietly with exit 0 ([`end_on_closed_stdout`]); any other
/// failure (a full disk, a closed device) is the user's to fix: exit 2.
pub fn stdout_written(done: std::io::Result<()>, what: &str) -> Result<(), CliError> {
    done.map_err(|e| stdout_error(e, what))
}

/// [`stdout_written`]'s error: ends the run quietly on a closed pipe.
pub fn stdout_error(e: std::io::Error, what: &str) -> CliError {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        end_on_closed_stdout();
    }
    CliError::input(format!("cannot write {what} to standard output: {e}"))
}

/// `println!`'s panic message after its prefix, e.g. "Broken pipe (os error 32)".
#[cfg(unix)]
fn is_broken_pipe(why: &str) -> bool {
    why.starts_with(&std::io::Error::from_raw_os_error(libc::EPIPE).to_string())
}

#[cfg(not(unix))]
fn is_broken_pipe(_: &str) -> bool {
    false
}

/// The reader of stdout is gone (`swimbot sweep | head`): end as ripgrep
/// does, exit 0 and no message, for every command alike. The process
/// ignores SIGPIPE (Rust's default), so a closed pipe is a write error
/// rather than a death by signal that only the commands with more output
/// than a pipe buffer met (exit 141 in a shell, a failure under
/// `set -o pipefail`). Files already renamed into place stay; a temporary
/// file or an empty new folder does not.
pub fn end_on_closed_stdout() -> ! {
    // A success: what the run recorded (a study's step) stays.
    crate::atomic_file::keep_committed();
    clean_up();
    std::process::exit(0)
}
