//! One file replaced atomically by the library (the study file): what
//! kind of path may be replaced, the temporary file's name, and what a
//! signal or a failed run undoes.
//!
//! - **Kinds**: a regular file or a new name is replaced; a symbolic link
//!   is followed, so the link stays a link and the file it names is the
//!   one replaced; a FIFO, a device, a directory or a socket is refused
//!   (replacing a FIFO or `/dev/null` by a regular file was the defect).
//! - **Temporary file** `.NAME.tmp-PID` beside the target, its name kept
//!   within the file system's 255-byte limit ([`temp_sibling`]), created
//!   and registered under one lock, so that the clean-up of a signal
//!   ([`remove_pending`]) removes it; one left by a killed run (SIGKILL)
//!   is removed by the next write of the same file ([`sweep_stale_temps`]).
//! - **Transactions** (the command line, [`set_transactional`]): each file
//!   replaced keeps its old bytes until the run ends; a run that then fails
//!   (its standard output on a full disk) or is stopped by a signal puts
//!   the old file back ([`remove_pending`]), so that the exit status and
//!   what is recorded agree. [`keep_committed`] ends the transaction.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// A file's name on Linux and macOS is at most 255 bytes.
const NAME_MAX: usize = 255;

/// A replaced file's old state, put back if the run fails.
struct Replaced {
    path: PathBuf,
    /// `None`: there was no file.
    old: Option<Vec<u8>>,
    /// SHA-256 of what this run wrote: a file changed since is left alone.
    new_sha256: String,
}

struct Pending {
    temps: Vec<PathBuf>,
    replaced: Vec<Replaced>,
}

static PENDING: Mutex<Pending> = Mutex::new(Pending {
    temps: Vec::new(),
    replaced: Vec::new(),
});

/// Set by [`remove_pending`]: nothing new is renamed in from then on.
static CLOSING: AtomicBool = AtomicBool::new(false);

static TRANSACTIONAL: AtomicBool = AtomicBool::new(false);

fn pending() -> std::sync::MutexGuard<'static, Pending> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Keep every replaced file's old bytes until [`keep_committed`] or
/// [`remove_pending`] (module docs). Off by default: a library caller
/// (the Python package) owns its own process's outcome.
pub fn set_transactional(on: bool) {
    TRANSACTIONAL.store(on, Ordering::SeqCst);
}

/// The run succeeded: what it replaced stays.
pub fn keep_committed() {
    pending().replaced.clear();
}

/// The run failed or is stopped: temporary files are removed and every
/// file it replaced gets its old bytes back (when no one changed it since).
pub fn remove_pending() {
    let mut p = pending();
    CLOSING.store(true, Ordering::SeqCst);
    for t in p.temps.drain(..) {
        let _ = std::fs::remove_file(t);
    }
    for r in p.replaced.drain(..).rev() {
        let now = std::fs::read(&r.path).ok();
        if now.map(|b| crate::provenance::sha256_hex(&b)).as_deref() != Some(&r.new_sha256) {
            continue;
        }
        match r.old {
            None => {
                let _ = std::fs::remove_file(&r.path);
            }
            Some(bytes) => {
                let tmp = temp_sibling(&r.path);
                let back =
                    std::fs::write(&tmp, &bytes).and_then(|()| std::fs::rename(&tmp, &r.path));
                if back.is_err() {
                    let _ = std::fs::remove_file(&tmp);
                }
            }
        }
    }
}

/// Why `path` cannot be replaced, or the file to replace (a link's target).
pub fn resolve(path: &Path) -> Result<PathBuf, String> {
    let meta = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(path.to_path_buf()),
        Err(e) => return Err(format!("cannot examine it: {e}")),
        Ok(m) => m,
    };
    let (target, meta) = if meta.file_type().is_symlink() {
        let t = std::fs::canonicalize(path).map_err(|e| {
            format!("is a symbolic link whose target cannot be reached ({e}); name the file itself")
        })?;
        let m = std::fs::metadata(&t).map_err(|e| e.to_string())?;
        (t, m)
    } else {
        (path.to_path_buf(), meta)
    };
    let t = meta.file_type();
    if t.is_file() {
        return Ok(target);
    }
    let kind = if t.is_dir() {
        "a directory"
    } else {
        special_kind(&t)
    };
    Err(format!(
        "is {kind}, not a regular file: it cannot be replaced by one; name a file"
    ))
}

#[cfg(unix)]
fn special_kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

/// `NAME` as the temporary names beside it use it: a name so long that
/// `.NAME.tmp-PID` would pass 255 bytes is cut (at a character boundary)
/// and given its hash's first hex digits, so that the temporary file can
/// be made wherever the file itself can.
fn temp_stem(name: &str) -> String {
    // "." + ".tmp-" + a 10-digit PID.
    let room = NAME_MAX - 16;
    if name.len() <= room {
        return name.to_string();
    }
    let hash = &crate::provenance::sha256_hex(name.as_bytes())[..12];
    let mut cut = room - hash.len() - 1;
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!("{}~{hash}", &name[..cut])
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned())
}

/// `.NAME.tmp-PID` next to `path` ([`temp_stem`]).
pub fn temp_sibling(path: &Path) -> PathBuf {
    let stem = temp_stem(&file_name(path));
    path.with_file_name(format!(".{stem}.tmp-{}", std::process::id()))
}

/// Removes `.NAME.tmp-PID` files next to `dest` left by runs that were
/// killed outright (process PID gone; a regular file of ours by name),
/// and `.NAME.PID.tmp`, the name earlier versions gave a study's.
pub fn sweep_stale_temps(dest: &Path) {
    let parent = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = file_name(dest);
    let prefix = format!(".{}.tmp-", temp_stem(&name));
    let old_prefix = format!(".{name}.");
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let pid = file
            .strip_prefix(&prefix)
            .or_else(|| file.strip_prefix(&old_prefix)?.strip_suffix(".tmp"))
            .and_then(|p| p.parse::<u32>().ok());
        let Some(pid) = pid else {
            continue;
        };
        if pid != std::process::id()
            && e.file_type().is_ok_and(|t| t.is_file())
            && !crate::atomic_dir::process_alive(pid)
        {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

fn stopping() -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::Interrupted, "the run is being stopped")
}

/// Replaces `path` ([`resolve`]d) by `bytes`: a temporary file beside it,
/// flushed to disk, renamed over it. The error says what failed; nothing
/// of the run is left on failure.
pub fn replace(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let target = resolve(path)?;
    sweep_stale_temps(&target);
    let tmp = temp_sibling(&target);
    let mut file = {
        let mut p = pending();
        if CLOSING.load(Ordering::SeqCst) {
            return Err(stopping().to_string());
        }
        let f = std::fs::File::create(&tmp).map_err(|e| format!("cannot write it: {e}"))?;
        p.temps.push(tmp.clone());
        f
    };
    let forget = |tmp: &Path| {
        let _ = std::fs::remove_file(tmp);
        pending().temps.retain(|t| t != tmp);
    };
    let written = crate::atomic_dir::fault_injection::write_all(&mut file, bytes)
        .and_then(|()| file.flush())
        .and_then(|()| file.sync_all());
    drop(file);
    if let Err(e) = written {
        forget(&tmp);
        return Err(format!("cannot write it: {e}"));
    }
    let old = if TRANSACTIONAL.load(Ordering::SeqCst) {
        Some(std::fs::read(&target).ok())
    } else {
        None
    };
    // The rename and its record under the lock a signal's clean-up takes:
    // the clean-up sees either no new file or a new file it can undo.
    let mut p = pending();
    p.temps.retain(|t| *t != tmp);
    if CLOSING.load(Ordering::SeqCst) {
        let _ = std::fs::remove_file(&tmp);
        return Err(stopping().to_string());
    }
    if let Err(e) = std::fs::rename(&tmp, &target) {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!("cannot write it: {e}"));
    }
    if let Some(old) = old {
        p.replaced.push(Replaced {
            path: target,
            old,
            new_sha256: crate::provenance::sha256_hex(bytes),
        });
    }
    drop(p);
    pause_after_commit();
    Ok(())
}

/// The moment between a file's commit and the run's end, widened in
/// debug builds only (the integration tests) by
/// `SWIMBOT_FAULT_PAUSE_AFTER_COMMIT_MS=N`, so that a test can signal a
/// run exactly there.
#[cfg(debug_assertions)]
fn pause_after_commit() {
    if let Some(ms) = std::env::var("SWIMBOT_FAULT_PAUSE_AFTER_COMMIT_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
    {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
}

#[cfg(not(debug_assertions))]
fn pause_after_commit() {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_temporary_name_stays_within_the_name_limit_and_is_swept_by_the_same_name() {
        let dir = tempfile::tempdir().unwrap();
        let long = "é".repeat(120) + ".toml";
        let p = dir.path().join(&long);
        let tmp = temp_sibling(&p);
        let n = tmp.file_name().unwrap().len();
        assert!(n <= NAME_MAX, "{n}");
        replace(&p, b"one").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        // A leftover of a killed process (PID 0x7ffffffe is none).
        let stale = p.with_file_name(format!(".{}.tmp-2147483646", temp_stem(&long)));
        std::fs::write(&stale, b"x").unwrap();
        replace(&p, b"two").unwrap();
        assert!(!stale.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_followed_and_a_fifo_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.toml");
        std::fs::write(&real, b"old").unwrap();
        let link = dir.path().join("link.toml");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        replace(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        let e = replace(dir.path(), b"x").unwrap_err();
        assert!(e.contains("directory"), "{e}");
        let e = replace(Path::new("/dev/null"), b"x").unwrap_err();
        assert!(e.contains("character device"), "{e}");
    }
}
