//! An output folder replaced all-or-none (the report's bundle: a page,
//! its figures, tables and manifest, which only make sense together).
//!
//! The new folder is built in a sibling *staging* folder,
//! `.NAME.swimbot-staging-PID`, holding a marker file
//! ([`STAGING_MARKER`]); the user's own files in the old folder (anything
//! the new bundle does not replace) are carried over as hard links (a
//! copy where links are not possible). Then one rename swaps it in:
//! on Linux `renameat2(RENAME_EXCHANGE)` exchanges the two folders
//! atomically and the old one, now under the staging name, is removed;
//! elsewhere (or on a file system without the exchange) the old folder is
//! renamed aside (`.NAME.swimbot-old-PID`), the new one renamed in, the
//! old one removed. An interrupt, a kill or a full disk at any moment
//! leaves the old folder or the new one whole under the folder's name,
//! never a mix: the worst is a leftover staging or aside folder, which
//! [`sweep_stale`] (run by the next writer of the same folder) removes, or
//! for an aside folder whose swap was cut between its two renames, puts
//! back. Leftovers are recognised by name and by their process being gone,
//! and a staging-named folder is removed only when nothing in it can be
//! lost: it holds the marker, or it is empty (cut between its creation
//! and its marker), or everything in it is in the folder under the same
//! name (the old folder after an exchange cut before it was marked: its
//! files were carried over or replaced). Nothing else is touched.
//!
//! Staging folders of this process are registered, so that the CLI's
//! clean-up on an error or a signal removes them ([`remove_pending`]).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The marker file inside a staging folder.
pub const STAGING_MARKER: &str = ".swimbot-staging";

static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Set by [`remove_pending`] (a signal's clean-up): from then on nothing
/// new is staged or swapped, so the clean-up cannot race the writer. Every
/// change to a staging folder happens under [`PENDING`]'s lock.
static CLOSING: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn closing() -> std::io::Result<()> {
    if CLOSING.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "the run is being stopped",
        ));
    }
    Ok(())
}

fn pending() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// A folder being built to replace `target`.
pub struct Staging {
    target: PathBuf,
    stage: PathBuf,
    /// The old folder's permissions, given to the new one as it is swapped
    /// in (not before: a read-only folder could not be filled).
    permissions: Option<std::fs::Permissions>,
}

fn sibling(target: &Path, tag: &str, pid: u32) -> PathBuf {
    let name = target
        .file_name()
        .map_or("output".into(), |n| n.to_string_lossy().into_owned());
    target.with_file_name(format!(".{name}.swimbot-{tag}-{pid}"))
}

impl Staging {
    /// Starts the staging folder for `target` (an existing folder or a
    /// new name; a symbolic link is followed, so the link stays). Files of
    /// the old folder for which `replaced(relative path)` is false are
    /// carried over.
    pub fn begin(target: &Path, replaced: &dyn Fn(&Path) -> bool) -> std::io::Result<Staging> {
        let target = match std::fs::canonicalize(target) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => target.to_path_buf(),
            Err(e) => return Err(e),
        };
        sweep_stale(&target);
        let stage = sibling(&target, "staging", std::process::id());
        if stage.exists() {
            // Ours from an earlier staging of this process: never a user's.
            remove_staging(&stage);
        }
        let mut p = pending();
        closing()?;
        std::fs::create_dir(&stage)?;
        p.push(stage.clone());
        let permissions = std::fs::metadata(&target).ok().map(|m| m.permissions());
        let staging = Staging {
            target,
            stage,
            permissions,
        };
        mark(&staging.stage, &staging.target)?;
        if staging.permissions.is_some() {
            carry_over(&staging.target, &staging.stage, Path::new(""), replaced)?;
        }
        Ok(staging)
    }

    /// Where to write the new folder's files.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Writes `bytes` to `rel` in the staging folder, flushed to disk.
    pub fn write(&self, rel: &str, bytes: &[u8]) -> std::io::Result<()> {
        let _p = pending();
        closing()?;
        let path = self.stage.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let _ = std::fs::remove_file(&path);
        let mut f = std::fs::File::create(&path)?;
        fault_injection::write_all(&mut f, bytes)?;
        f.sync_all()
    }

    /// Swaps the new folder in (module docs) and removes the old one.
    /// The whole swap holds the lock a signal's clean-up takes: the
    /// clean-up comes before it (and it is refused) or after it.
    pub fn commit(self) -> std::io::Result<()> {
        let mut p = pending();
        closing()?;
        let swapped = std::fs::remove_file(self.stage.join(STAGING_MARKER))
            .and_then(|()| match &self.permissions {
                Some(p) => std::fs::set_permissions(&self.stage, p.clone()),
                None => Ok(()),
            })
            .and_then(|()| {
                sync_dir(&self.stage);
                if self.target.exists() {
                    swap_in(&self.stage, &self.target)
                } else {
                    std::fs::rename(&self.stage, &self.target).map(|()| None)
                }
            });
        match swapped {
            Ok(old) => {
                if let Some(parent) = self.target.parent() {
                    sync_dir(parent);
                }
                if let Some(old) = old {
                    // Marked first: a kill while it is removed leaves a
                    // leftover the next run recognises.
                    let _ = mark(&old, &self.target);
                    let _ = std::fs::remove_dir_all(old);
                }
                p.retain(|s| s != &self.stage);
                drop(p);
                std::mem::forget(self);
                Ok(())
            }
            Err(e) => {
                // Writable and marked again, so that dropping it removes
                // it and a kill now leaves a folder the next run recognises.
                #[cfg(unix)]
                {
                    use std::os::unix::fs::PermissionsExt;
                    let writable = std::fs::Permissions::from_mode(0o700);
                    let _ = std::fs::set_permissions(&self.stage, writable);
                }
                let _ = mark(&self.stage, &self.target);
                Err(e)
            }
        }
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        let mut p = pending();
        remove_staging(&self.stage);
        p.retain(|s| s != &self.stage);
    }
}

/// Writes the staging marker into `dir`, a staging folder of `target`.
fn mark(dir: &Path, target: &Path) -> std::io::Result<()> {
    let mut marker = std::fs::File::create(dir.join(STAGING_MARKER))?;
    writeln!(
        marker,
        "swimbot staging folder of {} (process {}); safe to remove when that process has ended",
        target.display(),
        std::process::id()
    )
}

/// Exchanges `stage` and `target`; returns where the old folder now is.
fn swap_in(stage: &Path, target: &Path) -> std::io::Result<Option<PathBuf>> {
    match exchange(stage, target) {
        Ok(()) => return Ok(Some(stage.to_path_buf())),
        Err(e) if !exchange_unsupported(&e) => return Err(e),
        Err(_) => {}
    }
    let aside = sibling(target, "old", std::process::id());
    std::fs::rename(target, &aside)?;
    if let Err(e) = std::fs::rename(stage, target) {
        let _ = std::fs::rename(&aside, target);
        return Err(e);
    }
    Ok(Some(aside))
}

#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let a = std::ffi::CString::new(a.as_os_str().as_bytes())?;
    let b = std::ffi::CString::new(b.as_os_str().as_bytes())?;
    // SAFETY: two NUL-terminated paths, relative to the working directory.
    let r = unsafe {
        libc::syscall(
            libc::SYS_renameat2,
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if r == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<()> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// The kernel or file system has no exchange: fall back to two renames.
fn exchange_unsupported(e: &std::io::Error) -> bool {
    #[cfg(unix)]
    if matches!(
        e.raw_os_error(),
        Some(libc::EINVAL | libc::ENOSYS | libc::ENOTSUP)
    ) {
        return true;
    }
    e.kind() == std::io::ErrorKind::Unsupported
}

/// Hard-links (or copies) the old folder's files not `replaced` into the
/// staging folder, recreating sub-folders and symbolic links.
fn carry_over(
    from: &Path,
    to: &Path,
    rel: &Path,
    replaced: &dyn Fn(&Path) -> bool,
) -> std::io::Result<()> {
    for entry in std::fs::read_dir(from.join(rel))? {
        let entry = entry?;
        let rel = rel.join(entry.file_name());
        if replaced(&rel) {
            continue;
        }
        let kind = entry.file_type()?;
        let (src, dst) = (from.join(&rel), to.join(&rel));
        if kind.is_dir() {
            std::fs::create_dir(&dst)?;
            carry_over(from, to, &rel, replaced)?;
        } else if kind.is_symlink() {
            copy_link(&src, &dst)?;
        } else if std::fs::hard_link(&src, &dst).is_err() {
            std::fs::copy(&src, &dst)?;
        }
    }
    Ok(())
}

#[cfg(unix)]
fn copy_link(src: &Path, dst: &Path) -> std::io::Result<()> {
    std::os::unix::fs::symlink(std::fs::read_link(src)?, dst)
}

#[cfg(not(unix))]
fn copy_link(src: &Path, dst: &Path) -> std::io::Result<()> {
    std::fs::copy(src, dst).map(|_| ())
}

#[cfg(unix)]
fn sync_dir(dir: &Path) {
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

#[cfg(not(unix))]
fn sync_dir(_: &Path) {}

/// Removes a staging folder, only when it carries the marker.
fn remove_staging(stage: &Path) {
    if stage.join(STAGING_MARKER).is_file() {
        let _ = std::fs::remove_dir_all(stage);
    }
}

/// Removes this process's staging folders (the run failed or was
/// interrupted); nothing is staged after it.
pub fn remove_pending() {
    let p = pending();
    CLOSING.store(true, std::sync::atomic::Ordering::SeqCst);
    for stage in p.iter() {
        remove_staging(stage);
    }
}

/// Leftovers of killed runs next to `target` (module docs): staging
/// folders with the marker whose process is gone are removed; an aside
/// folder whose process is gone is put back when the folder's name is
/// free (the swap was cut between its renames), else removed.
pub fn sweep_stale(target: &Path) {
    let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else {
        return;
    };
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let prefix = format!(".{}.swimbot-", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some((tag, pid)) = file.strip_prefix(&prefix).and_then(|r| r.split_once('-')) else {
            continue;
        };
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        if !e.file_type().is_ok_and(|t| t.is_dir()) || process_alive(pid) {
            continue;
        }
        match tag {
            "staging" if leftover_is_ours(&e.path(), target) => {
                let _ = std::fs::remove_dir_all(e.path());
            }
            "old" if !target.exists() => {
                let _ = std::fs::rename(e.path(), target);
            }
            "old" => {
                let _ = std::fs::remove_dir_all(e.path());
            }
            _ => {}
        }
    }
}

/// Whether a staging-named folder of a gone process holds nothing that
/// could be lost (module docs).
fn leftover_is_ours(leftover: &Path, target: &Path) -> bool {
    leftover.join(STAGING_MARKER).is_file() || all_in(leftover, target, Path::new(""))
}

/// Whether every entry under `from/rel` is also under `to/rel` (an empty
/// folder trivially is).
fn all_in(from: &Path, to: &Path, rel: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir(from.join(rel)) else {
        return false;
    };
    entries.into_iter().all(|e| {
        let Ok(e) = e else { return false };
        let rel = rel.join(e.file_name());
        if std::fs::symlink_metadata(to.join(&rel)).is_err() {
            return false;
        }
        !e.file_type().is_ok_and(|t| t.is_dir()) || all_in(from, to, &rel)
    })
}

/// Whether process `pid` may still be running (a leftover of a running
/// process is not a leftover). Unknown is "alive": nothing is removed.
#[cfg(unix)]
pub fn process_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    // SAFETY: signal 0 only checks that the process exists.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

#[cfg(not(unix))]
pub fn process_alive(_: u32) -> bool {
    true
}

/// A full disk, simulated in debug builds only (the integration tests):
/// `SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES=N` makes a staging write fail
/// with "No space left on device" once N bytes were written in all.
pub(crate) mod fault_injection {
    use std::io::Write;

    #[cfg(debug_assertions)]
    pub fn write_all(f: &mut std::fs::File, bytes: &[u8]) -> std::io::Result<()> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static WRITTEN: AtomicU64 = AtomicU64::new(0);
        if let Some(limit) = std::env::var("SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES")
            .ok()
            .and_then(|v| v.parse::<u64>().ok())
        {
            let before = WRITTEN.fetch_add(bytes.len() as u64, Ordering::SeqCst);
            if before + bytes.len() as u64 > limit {
                let room = limit.saturating_sub(before) as usize;
                f.write_all(&bytes[..room.min(bytes.len())])?;
                return Err(std::io::Error::from_raw_os_error(28));
            }
        }
        f.write_all(bytes)
    }

    #[cfg(not(debug_assertions))]
    pub fn write_all(f: &mut std::fs::File, bytes: &[u8]) -> std::io::Result<()> {
        f.write_all(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn the_new_folder_replaces_the_old_keeping_the_users_files() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        std::fs::create_dir_all(out.join("figures")).unwrap();
        std::fs::write(out.join("index.html"), "old").unwrap();
        std::fs::write(out.join("figures/a.svg"), "old").unwrap();
        std::fs::write(out.join("figures/notes.txt"), "mine").unwrap();
        std::fs::write(out.join("mine.txt"), "mine").unwrap();
        let s = Staging::begin(&out, &|rel| {
            rel == Path::new("index.html") || rel == Path::new("figures/a.svg")
        })
        .unwrap();
        s.write("index.html", b"new").unwrap();
        s.write("figures/b.svg", b"new").unwrap();
        // Before the swap the old folder is whole.
        assert_eq!(std::fs::read(out.join("index.html")).unwrap(), b"old");
        s.commit().unwrap();
        assert_eq!(names(&out), ["figures", "index.html", "mine.txt"]);
        assert_eq!(names(&out.join("figures")), ["b.svg", "notes.txt"]);
        assert_eq!(std::fs::read(out.join("index.html")).unwrap(), b"new");
        assert_eq!(names(root.path()), ["out"], "no staging or old folder left");
    }

    #[test]
    fn a_dropped_staging_leaves_the_old_folder_and_no_trace() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("index.html"), "old").unwrap();
        let s = Staging::begin(&out, &|_| true).unwrap();
        s.write("index.html", b"new").unwrap();
        drop(s);
        assert_eq!(names(root.path()), ["out"]);
        assert_eq!(std::fs::read(out.join("index.html")).unwrap(), b"old");
    }

    #[test]
    fn leftovers_of_a_dead_process_are_swept_and_an_aside_folder_put_back() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        // A pid that cannot be running (above Linux's pid_max limit).
        let dead = 1 << 23;
        let stage = sibling(&out, "staging", dead);
        std::fs::create_dir(&stage).unwrap();
        std::fs::write(stage.join(STAGING_MARKER), "").unwrap();
        let not_ours = sibling(&out, "staging", dead + 1);
        std::fs::create_dir(&not_ours).unwrap();
        std::fs::write(not_ours.join("notes.txt"), "mine").unwrap();
        let aside = sibling(&out, "old", dead);
        std::fs::create_dir(&aside).unwrap();
        std::fs::write(aside.join("index.html"), "old").unwrap();
        sweep_stale(&out);
        let left = names(root.path());
        assert_eq!(left.len(), 2, "{left:?}");
        assert!(
            not_ours.join("notes.txt").exists(),
            "no marker and a file the folder lacks: not ours to remove"
        );
        assert_eq!(std::fs::read(out.join("index.html")).unwrap(), b"old");
    }

    /// A kill between a staging folder's creation and its marker leaves it
    /// empty; one right after the exchange leaves the old folder unmarked
    /// under the staging name, holding only what the new folder holds.
    #[test]
    fn unmarked_leftovers_are_swept_only_when_nothing_in_them_can_be_lost() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        std::fs::create_dir_all(out.join("figures")).unwrap();
        std::fs::write(out.join("index.html"), "new").unwrap();
        std::fs::write(out.join("figures/notes.txt"), "mine").unwrap();
        let dead = 1 << 23;
        let empty = sibling(&out, "staging", dead);
        std::fs::create_dir(&empty).unwrap();
        let old = sibling(&out, "staging", dead + 1);
        std::fs::create_dir_all(old.join("figures")).unwrap();
        std::fs::write(old.join("index.html"), "old").unwrap();
        std::fs::hard_link(out.join("figures/notes.txt"), old.join("figures/notes.txt")).unwrap();
        let other = sibling(&out, "staging", dead + 2);
        std::fs::create_dir_all(other.join("figures")).unwrap();
        std::fs::write(other.join("figures/only-here.txt"), "mine").unwrap();
        sweep_stale(&out);
        assert_eq!(
            names(root.path()),
            [&*other.file_name().unwrap().to_string_lossy(), "out"]
        );
        assert_eq!(
            std::fs::read(out.join("figures/notes.txt")).unwrap(),
            b"mine"
        );
    }
}
