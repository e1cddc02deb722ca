//! What a run leaves behind when it fails or is interrupted: nothing of
//! its own. Temporary files, staging folders ([`crate::atomic_dir`]) and
//! the folders a run created are registered here; when the run ends with
//! an error, and on SIGINT, SIGTERM and SIGHUP (a thread of the
//! `signal-hook` crate, which then ends the process by the signal's
//! default action), they are removed, folders only when empty (nothing the
//! user put there is touched). A temporary file `.NAME.tmp-PID` left by a
//! run that was killed outright (SIGKILL, power loss) is removed by the
//! next run writing NAME, when process PID is gone.
//!
//! The registry is process-wide on purpose: a signal handler has no other
//! way to find what to remove. A process that runs many commands (the
//! Python package) settles each output folder when its call ends
//! ([`settle_output_dir`]), so the registry holds only what calls still
//! running have made.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

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

/// Creates `dir` and its missing parents, registering each new one, under
/// the lock [`clean_up`] takes, as [`create_temp`] does: a signal between
/// creating and registering would leave the folders behind (seen in a
/// loaded test run).
///
/// Only folders this call made are registered: each prefix of `dir` is
/// made with `create_dir`, whose "already exists" says it was not ours.
/// Deciding by a missing path instead registered `new/../D`, which does
/// not resolve before `new/` exists, and so removed the user's empty
/// folder `D` when the run failed.
pub fn create_dir_all(dir: &Path) -> std::io::Result<()> {
    let mut pending = pending();
    let mut made = Vec::new();
    let mut at = PathBuf::new();
    let mut result = Ok(());
    for part in dir.components() {
        at.push(part);
        if matches!(
            part,
            std::path::Component::Prefix(_)
                | std::path::Component::RootDir
                | std::path::Component::CurDir
                | std::path::Component::ParentDir
        ) {
            continue;
        }
        match std::fs::create_dir(&at) {
            Ok(()) => made.push(at.clone()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && at.is_dir() => {}
            Err(e) => {
                result = Err(e);
                break;
            }
        }
    }
    // Deepest first, the order they must be removed in; registered even
    // when a deeper one failed, so that the parents made are removed.
    made.reverse();
    pending.new_dirs.extend(made);
    result
}

/// The run succeeded: its folders are outputs now.
pub fn keep_new_dirs() {
    pending().new_dirs.clear();
}

/// One call of the library that wrote into `dir` has ended: the new
/// folders it created for `dir` (`dir` and its new parents) leave the
/// registry, kept when the call `succeeded`, else removed when empty.
/// Other calls' folders stay registered.
pub fn settle_output_dir(dir: &Path, succeeded: bool) {
    let mut p = pending();
    let (mine, others): (Vec<PathBuf>, Vec<PathBuf>) = std::mem::take(&mut p.new_dirs)
        .into_iter()
        .partition(|d| dir.starts_with(d));
    p.new_dirs = others;
    if !succeeded {
        // Deepest first, as registered.
        for d in mine {
            let _ = std::fs::remove_dir(d);
        }
    }
}

/// Removes the registered temporary files, this process's temporary files
/// in new folders (`.NAME.tmp-PID`, written by other writers too) and the
/// new folders that are then empty.
pub fn clean_up() {
    crate::atomic_dir::remove_pending();
    crate::atomic_file::remove_pending();
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

/// SIGINT, SIGTERM and SIGHUP (a closed terminal) clean up, then end the
/// process by the signal's default action (its exit status still says
/// which signal ended it).
#[cfg(unix)]
pub fn install_signal_cleanup() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
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

/// Removes `.NAME.tmp-PID` files next to `dest` left by runs that were
/// killed outright ([`crate::atomic_file::sweep_stale_temps`]).
pub fn sweep_stale_temps(dest: &Path) {
    crate::atomic_file::sweep_stale_temps(dest);
}

#[cfg(test)]
mod tests {
    use super::{create_dir_all, settle_output_dir};

    #[test]
    fn only_the_folders_a_call_made_are_removed_when_it_fails() {
        let root = tempfile::tempdir().unwrap();
        let existing = root.path().join("D");
        std::fs::create_dir(&existing).unwrap();
        // `new/../D` names the user's empty folder D once `new/` exists.
        let through_new = root.path().join("new").join("..").join("D");
        create_dir_all(&through_new).unwrap();
        settle_output_dir(&through_new, false);
        assert!(existing.is_dir(), "the user's folder D was removed");
        assert!(
            !root.path().join("new").exists(),
            "the folder made was kept"
        );
        // A plain new chain is made and removed whole.
        let deep = root.path().join("a").join("b").join("c");
        create_dir_all(&deep).unwrap();
        assert!(deep.is_dir());
        settle_output_dir(&deep, false);
        assert!(!root.path().join("a").exists());
        assert!(existing.is_dir());
    }
}
