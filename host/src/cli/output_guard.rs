//! What stands between a run and the user's files: which kind of file an
//! output path names and how it is written, the refusal of an output that
//! is one of the run's inputs, and the removal of temporary files and new
//! folders when the run fails or is interrupted (SIGINT, SIGTERM).
//!
//! **Kinds of output path** ([`resolve`]):
//! - a regular file, or a name that does not exist yet: written to a
//!   temporary sibling and renamed over it (readers see the old file or
//!   the whole new one);
//! - a symbolic link: followed to its target, which is then treated as
//!   above (the link stays a link; replacing the link itself would cut it
//!   off from the file the user keeps it for); a dangling link is refused;
//! - a character device or a FIFO (`/dev/null`, `/dev/stdout`, a terminal,
//!   a named pipe): **written through**, as a shell redirection does. It
//!   cannot be replaced atomically, and replacing it was the defect (run as
//!   root, `--write-effect /dev/null` turned the system's /dev/null into a
//!   regular file); naming one is a deliberate choice of where the bytes go;
//! - a directory, a block device or a socket: refused (no command writes a
//!   disk image or talks to a socket; a block device would be overwritten).
//!
//! **Same file as an input**: an output that is, by device and inode, a
//! file named elsewhere on the command line (`--data X --write-effect X`)
//! is refused before any work: every input file of every command is named
//! on its command line, so this needs no list of each command's inputs.
//!
//! **Clean-up**: temporary files and the folders a run created are
//! registered here; when the run ends with an error, and on SIGINT and
//! SIGTERM (a thread of the `signal-hook` crate, which then ends the
//! process by the signal's default action), they are removed, folders only
//! when empty (nothing the user put there is touched).

use super::CliError;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// How an output path is written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A regular file (existing or new) at this resolved path: temp + rename.
    Replace(PathBuf),
    /// A character device or FIFO: opened and written in place.
    WriteThrough(PathBuf),
}

/// What kind of output `path` names (module docs).
pub fn resolve(path: &Path) -> Result<Target, CliError> {
    let refuse = |why: String| CliError::input(format!("output {}: {why}", path.display()));
    let meta = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Ok(Target::Replace(path.to_path_buf()))
        }
        Err(e) => return Err(refuse(format!("cannot examine it: {e}"))),
        Ok(m) => m,
    };
    let (resolved, meta) = if meta.file_type().is_symlink() {
        let target = std::fs::canonicalize(path).map_err(|e| {
            refuse(format!(
                "is a symbolic link whose target cannot be reached ({e}); name the file itself"
            ))
        })?;
        let m = std::fs::metadata(&target).map_err(|e| refuse(format!("{e}")))?;
        (target, m)
    } else {
        (path.to_path_buf(), meta)
    };
    let t = meta.file_type();
    if t.is_file() {
        return Ok(Target::Replace(resolved));
    }
    if t.is_dir() {
        return Err(refuse("is a directory, expected a file name".into()));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() || t.is_fifo() {
            return Ok(Target::WriteThrough(resolved));
        }
        if t.is_block_device() {
            return Err(refuse(
                "is a block device; swimbot writes files, never a disk".into(),
            ));
        }
    }
    Err(refuse(
        "is neither a regular file, a character device nor a FIFO (a socket?); name a file".into(),
    ))
}

/// Refuses `path` when it is, by device and inode, another file named on
/// the command line (an input). A path that does not exist yet is no input.
pub fn refuse_if_input(path: &Path) -> Result<(), CliError> {
    // The output itself is named once; a second name is an input.
    refuse_if_named(path, 2)
}

/// [`refuse_if_input`] for an output the command line does not name (a
/// file of the report's bundle, named by the folder): any name is an input.
pub fn refuse_if_unnamed_input(path: &Path) -> Result<(), CliError> {
    refuse_if_named(path, 1)
}

fn refuse_if_named(path: &Path, inputs_from: usize) -> Result<(), CliError> {
    let Some(id) = identity(path) else {
        return Ok(());
    };
    let named = std::env::args_os()
        .skip(1)
        .flat_map(|a| {
            // `--flag=PATH` as well as `--flag PATH`.
            let s = a.to_string_lossy().into_owned();
            let after_eq = s.split_once('=').map(|(_, v)| v.to_string());
            [Some(s), after_eq]
        })
        .flatten()
        .filter(|a| identity(Path::new(a)) == Some(id))
        .count();
    if named >= inputs_from {
        return Err(CliError::input(format!(
            "output {}: is also an input of this command (the same file); writing it would destroy the input: name another output",
            path.display()
        )));
    }
    Ok(())
}

#[cfg(unix)]
fn identity(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let m = std::fs::metadata(path).ok()?;
    Some((m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn identity(_: &Path) -> Option<(u64, u64)> {
    None
}

/// Temporary files and new folders to remove if the run does not succeed.
struct Pending {
    temps: Vec<PathBuf>,
    new_dirs: Vec<PathBuf>,
}

static PENDING: Mutex<Pending> = Mutex::new(Pending {
    temps: Vec::new(),
    new_dirs: Vec::new(),
});

fn pending() -> std::sync::MutexGuard<'static, Pending> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Creates the temporary file `p` and registers it, both under the lock
/// that [`clean_up`] takes: a signal that arrives between the two would
/// otherwise leave the file behind (seen once in a loaded test run).
pub fn create_temp(p: &Path) -> std::io::Result<std::fs::File> {
    let mut pending = pending();
    let file = std::fs::File::create(p)?;
    pending.temps.push(p.to_path_buf());
    Ok(file)
}

pub fn forget_temp(p: &Path) {
    pending().temps.retain(|t| t != p);
}

/// Creates `dir` and its missing parents, registering each new one.
pub fn create_dir_all(dir: &Path) -> std::io::Result<()> {
    let mut missing = Vec::new();
    let mut at = Some(dir);
    while let Some(d) = at.filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
        missing.push(d.to_path_buf());
        at = d.parent();
    }
    std::fs::create_dir_all(dir)?;
    // Deepest first, the order they must be removed in.
    pending().new_dirs.extend(missing);
    Ok(())
}

/// The run succeeded: its folders are outputs now.
pub fn keep_new_dirs() {
    pending().new_dirs.clear();
}

/// Removes the registered temporary files, this process's temporary files
/// in new folders (`.NAME.tmp-PID`, written by other writers too) and the
/// new folders that are then empty.
pub fn clean_up() {
    let p = pending();
    for t in &p.temps {
        let _ = std::fs::remove_file(t);
    }
    let suffix = format!(".tmp-{}", std::process::id());
    for d in &p.new_dirs {
        if let Ok(entries) = std::fs::read_dir(d) {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                if name.starts_with('.') && name.ends_with(&suffix) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        let _ = std::fs::remove_dir(d);
    }
}

/// SIGINT and SIGTERM clean up, then end the process by the signal's
/// default action (its exit status still says which signal ended it).
#[cfg(unix)]
pub fn install_signal_cleanup() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            clean_up();
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
}

#[cfg(not(unix))]
pub fn install_signal_cleanup() {}

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
    clean_up();
    std::process::exit(0)
}
