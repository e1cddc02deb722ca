//! What stands between a run and the user's files: which kind of file an
//! output path names and how it is written, the refusal of an output that
//! is one of the run's inputs, and which command's output a folder holds.
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
//!   regular file); naming one is a deliberate choice of where the bytes go.
//!   A FIFO no reader opens within [`FIFO_READER_WAIT`] is refused
//!   ([`open_write_through`]);
//! - a directory, a block device or a socket: refused (no command writes a
//!   disk image or talks to a socket; a block device would be overwritten).
//!
//! **Inputs are never outputs**: the run's inputs are every existing file
//! named on its command line (`--data X`, `--flag=X`, a positional log)
//! that is not a declared output file, and every file it has read
//! (its [`Inputs`]: a CSV's `# setup_file`, effect files). An output file that is, by device and inode, one of them
//! (`--data X --write-effect X`) is refused, and so is an output folder
//! that holds one, after resolving links (`log --data L/trials.toml -o L`
//! would replace the dataset it just read); the refusal names both.
//!
//! **Which command wrote a folder**: each output folder gets a marker,
//! [`MARKER`], naming the command, written when the run succeeds; a
//! folder whose marker (or report manifest) names another command is
//! refused ([`claim_dir`]).
//!
//! Removing what a failed run wrote is [`super::cleanup`]'s; a closed or
//! failing standard output is [`super::stdout`]'s.

use super::CliError;
use crate::provenance::Inputs;
use std::io::Write;
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
/// the command line or one the command has read (an input). A path that
/// does not exist yet is no input.
pub fn refuse_if_input(path: &Path, inputs: &Inputs) -> Result<(), CliError> {
    // The output itself is named once; a second name is an input.
    refuse_if_named(path, 2, inputs)
}

/// [`refuse_if_input`] for an output the command line does not name (a
/// file of the report's bundle, named by the folder): any name is an input.
pub fn refuse_if_unnamed_input(path: &Path, inputs: &Inputs) -> Result<(), CliError> {
    refuse_if_named(path, 1, inputs)
}

fn refuse_if_named(path: &Path, inputs_from: usize, inputs: &Inputs) -> Result<(), CliError> {
    let Some(id) = identity(path) else {
        return Ok(());
    };
    let named = named_paths(inputs)
        .iter()
        .filter(|a| identity(a) == Some(id))
        .count();
    let read = inputs
        .list()
        .iter()
        .any(|i| identity(Path::new(&i.path)) == Some(id));
    if named >= inputs_from || read {
        return Err(CliError::input(format!(
            "output {}: is also an input of this command (the same file); writing it would destroy the input: name another output",
            path.display()
        )));
    }
    Ok(())
}

/// Every argument of the run's command line that may name a file:
/// `--flag=PATH` as well as `--flag PATH`.
fn named_paths(inputs: &Inputs) -> Vec<PathBuf> {
    inputs
        .command()
        .iter()
        .skip(1)
        .flat_map(|s| {
            let after_eq = s.split_once('=').map(|(_, v)| v.to_string());
            [Some(s.clone()), after_eq]
        })
        .flatten()
        .map(PathBuf::from)
        .collect()
}

/// Output files declared so far ([`declare_output_file`]): named on the
/// command line, but not inputs.
static OUTPUT_FILES: Mutex<Vec<(u64, u64)>> = Mutex::new(Vec::new());

/// `path` is an output file of this run (e.g. `--write-log D/run.swlog`
/// beside `-o D`), so an existing file there is no input.
pub fn declare_output_file(path: &Path) {
    if let Some(id) = identity(path) {
        OUTPUT_FILES
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(id);
    }
}

/// The run's input files (module docs), as given.
fn input_files(inputs: &Inputs) -> Vec<PathBuf> {
    let outputs = OUTPUT_FILES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone();
    let read = inputs.list();
    named_paths(inputs)
        .into_iter()
        .chain(read.into_iter().map(|i| PathBuf::from(i.path)))
        .filter(|p| std::fs::metadata(p).is_ok_and(|m| !m.is_dir()))
        .filter(|p| identity(p).is_none_or(|id| !outputs.contains(&id)))
        .collect()
}

/// Refuses an output folder that holds one of the run's input files
/// (module docs), naming both.
pub fn refuse_dir_holding_input(dir: &Path, inputs: &Inputs) -> Result<(), CliError> {
    let Ok(dir_real) = std::fs::canonicalize(dir) else {
        return Ok(());
    };
    for input in input_files(inputs) {
        let Ok(real) = std::fs::canonicalize(&input) else {
            continue;
        };
        if real.starts_with(&dir_real) {
            return Err(CliError::input(format!(
                "output directory {}: holds {}, which is also an input of this command; writing there could replace or mix with it: name another output directory (or move the input out)",
                dir.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

/// The marker file naming the command that wrote an output folder.
pub const MARKER: &str = ".swimbot-output";

/// Refuses `dir` when its marker, or a report's `manifest.json`, names
/// another command than `command`; else registers it to be marked as
/// `command`'s when the run succeeds ([`mark_claimed_dirs`]). The claim
/// lives in the run's record, so a process that runs many commands (the
/// Python package) keeps no list of them.
pub fn claim_dir(dir: &Path, command: &str, inputs: &Inputs) -> Result<(), CliError> {
    let marker = crate::input_file::read_text(&dir.join(MARKER), 4096, "a marker").ok();
    let manifest = crate::input_file::read_text(&dir.join("manifest.json"), 16 << 20, "a manifest")
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v.get("command")?.as_str().map(str::to_string));
    let marked = marker.as_deref().and_then(marker_command);
    for other in [marked, manifest].into_iter().flatten() {
        if other != command {
            return Err(CliError::input(format!(
                "output directory {}: holds the output of `swimbot {other}`; give this `swimbot {command}` another folder with -o, or remove that one",
                dir.display()
            )));
        }
    }
    inputs.claim(dir, command);
    Ok(())
}

/// The command a marker's text names (`written by: swimbot NAME`).
fn marker_command(text: &str) -> Option<String> {
    text.lines()
        .find_map(|l| l.strip_prefix("written by: swimbot "))
        .map(|c| c.trim().to_string())
}

/// The run succeeded: mark each folder it claimed with its command.
pub fn mark_claimed_dirs(inputs: &Inputs) {
    for (dir, command) in inputs.take_claims() {
        let path = dir.join(MARKER);
        let text = format!(
            "written by: swimbot {command}\n\
             swimbot refuses to write another command's output into this folder.\n"
        );
        // A run killed outright between writing and renaming its marker
        // left the temporary one.
        super::cleanup::sweep_stale_temps(&path);
        if std::fs::read_to_string(&path).is_ok_and(|t| t == text) {
            continue;
        }
        let tmp = dir.join(format!(".{MARKER}.tmp-{}", std::process::id()));
        let written = std::fs::write(&tmp, &text).and_then(|()| std::fs::rename(&tmp, &path));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&tmp);
            let _ = writeln!(
                std::io::stderr(),
                "swimbot: warning: {}: cannot write the marker {MARKER}: {e}",
                dir.display()
            );
        }
    }
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

/// How long a write-through output that is a FIFO waits for its reader
/// (`mkfifo f; swimbot ... -o f & reader < f` may start the reader a
/// moment later) before the run is refused instead of hanging.
pub const FIFO_READER_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// Opens a write-through output ([`Target::WriteThrough`]). A FIFO opened
/// for writing blocks until a reader opens it, for ever when none comes
/// (`plan -o fifo` hung); opened non-blocking it fails at once with ENXIO
/// instead (fifo(7)), so the open is retried until [`FIFO_READER_WAIT`]
/// has passed. Once open the descriptor is made blocking again: a slow
/// reader then slows the writes instead of failing them with EAGAIN.
#[cfg(unix)]
pub fn open_write_through(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::fd::AsRawFd;
    use std::os::unix::fs::OpenOptionsExt;
    let start = std::time::Instant::now();
    let file = loop {
        match std::fs::OpenOptions::new()
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(path)
        {
            Ok(f) => break f,
            Err(e) if e.raw_os_error() == Some(libc::ENXIO) => {
                if start.elapsed() >= FIFO_READER_WAIT {
                    return Err(std::io::Error::new(
                        e.kind(),
                        format!(
                            "a FIFO that no reader opened within {} s; start its reader first",
                            FIFO_READER_WAIT.as_secs()
                        ),
                    ));
                }
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
            Err(e) => return Err(e),
        }
    };
    let fd = file.as_raw_fd();
    // SAFETY: F_GETFL and F_SETFL on the descriptor `file` owns.
    let flags = unsafe { libc::fcntl(fd, libc::F_GETFL) };
    if flags < 0 || unsafe { libc::fcntl(fd, libc::F_SETFL, flags & !libc::O_NONBLOCK) } < 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(file)
}

#[cfg(not(unix))]
pub fn open_write_through(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new().write(true).open(path)
}
