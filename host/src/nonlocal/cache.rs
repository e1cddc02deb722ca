//! Memoisation of costly non-local 6x6 resistance matrices, in memory and
//! on disk.
//!
//! A wall-resolved solve (tail or body inside the channel, a dense LU of
//! `3N` = 5 000-14 000 unknowns) costs seconds to a minute, while a fit, a
//! diagnosis or a repeated command-line run asks for the same geometry again
//! and again. Two layers therefore sit in front of the solver:
//!
//! 1. a process-wide map from the key to the matrix (or to the solver's
//!    error message: a deterministic solve that failed fails again). Each
//!    key has its own lock, so a second thread asking for a matrix being
//!    computed waits for it instead of solving it twice, while different
//!    keys are solved in parallel;
//! 2. one small text file per key in [`default_dir`]: `$SWIMBOT_CACHE_DIR`
//!    if set, else `swimbot-cache` in the system's temporary directory (not
//!    the current directory: an installed tool may run anywhere). Files are
//!    written to a temporary name and renamed, so a reader never sees half a
//!    file; a file that cannot be read, does not parse, holds a different
//!    key or a non-finite entry is ignored and overwritten by a fresh solve.
//!
//! The key is the exact bit pattern of every input (as in
//! `crate::nonlocal::memo`), prefixed by a `kind` naming the solve.
//! The matrix is stored as the bit patterns of its 36 entries (hexadecimal),
//! so a cached matrix is identical to the computed one, bit for bit.
//! [`SOLVER_REVISION`] is part of every file: bump it when a change to the
//! solver changes its results, so stale files are ignored.

use super::{NonlocalSettings, TailMethod};
use crate::physics::geometry::{Body, Channel, Handedness, Helix};
use nalgebra::Matrix6;
use std::collections::HashMap;
use std::fs;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Revision of the non-local solvers whose results the files hold.
pub const SOLVER_REVISION: u32 = 1;

/// Environment variable naming the cache directory.
pub const CACHE_DIR_ENV: &str = "SWIMBOT_CACHE_DIR";

const MAGIC: &str = "swimbot-nonlocal-cache";

type Slot = Arc<Mutex<Option<Result<Matrix6<f64>, CacheError>>>>;

/// Why the cache has no matrix for a key.
///
/// A failed solve is remembered in memory (the same key fails again at
/// once) for every caller of that key, whatever the solver's error type:
/// one map holds every kind, so the failure is kept as its message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CacheError {
    /// The solve failed, with its error's message.
    #[error("{0}")]
    Solve(String),
    /// A thread panicked while holding the map of keys.
    #[error("non-local cache poisoned")]
    Poisoned,
    /// A thread panicked while solving this key.
    #[error("non-local cache entry poisoned")]
    EntryPoisoned,
}
type MemoryKey = (&'static str, Vec<u64>);

fn memory() -> &'static Mutex<HashMap<MemoryKey, Slot>> {
    static MEMORY: OnceLock<Mutex<HashMap<MemoryKey, Slot>>> = OnceLock::new();
    MEMORY.get_or_init(|| Mutex::new(HashMap::new()))
}

/// `$SWIMBOT_CACHE_DIR`, or `swimbot-cache` in the temporary directory.
pub fn default_dir() -> PathBuf {
    match std::env::var_os(CACHE_DIR_ENV) {
        Some(d) if !d.is_empty() => PathBuf::from(d),
        _ => std::env::temp_dir().join("swimbot-cache"),
    }
}

/// The on-disk layer alone, in one directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiskCache {
    pub dir: PathBuf,
}

/// FNV-1a over the kind and key: a stable file name (std's hasher is not
/// stable across releases). Collisions are harmless: the file holds the
/// full key, which is checked on reading.
fn fnv1a(kind: &str, key: &[u64]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let bytes = kind.bytes().chain(key.iter().flat_map(|k| k.to_le_bytes()));
    for b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn hex_words(words: impl Iterator<Item = u64>) -> String {
    words
        .map(|w| format!("{w:016x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn parse_words(line: &str) -> Option<Vec<u64>> {
    line.split_whitespace()
        .map(|w| u64::from_str_radix(w, 16).ok())
        .collect()
}

impl DiskCache {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        DiskCache { dir: dir.into() }
    }

    /// The cache in [`default_dir`].
    pub fn default_location() -> Self {
        DiskCache::new(default_dir())
    }

    /// The file that holds `kind`/`key`.
    pub fn path(&self, kind: &str, key: &[u64]) -> PathBuf {
        self.dir
            .join(format!("{kind}-{:016x}.txt", fnv1a(kind, key)))
    }

    fn header(kind: &str) -> String {
        format!("{MAGIC} revision {SOLVER_REVISION} {kind}")
    }

    /// The stored matrix, or `None` if absent, unreadable, corrupt, stale,
    /// for another key, or not finite.
    pub fn load(&self, kind: &str, key: &[u64]) -> Option<Matrix6<f64>> {
        let text = fs::read_to_string(self.path(kind, key)).ok()?;
        let mut lines = text.lines();
        if lines.next()? != Self::header(kind) {
            return None;
        }
        if parse_words(lines.next()?)? != key {
            return None;
        }
        let words = parse_words(lines.next()?)?;
        if words.len() != 36 || lines.next() != Some("end") {
            return None;
        }
        let m = Matrix6::from_iterator(words.into_iter().map(f64::from_bits));
        m.iter().all(|v| v.is_finite()).then_some(m)
    }

    /// Store `m` atomically (temporary file, then rename).
    pub fn store(&self, kind: &str, key: &[u64], m: &Matrix6<f64>) -> std::io::Result<()> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        fs::create_dir_all(&self.dir)?;
        let path = self.path(kind, key);
        let text = format!(
            "{}\n{}\n{}\nend\n",
            Self::header(kind),
            hex_words(key.iter().copied()),
            hex_words(m.iter().map(|v| v.to_bits()))
        );
        // Unique per process and call, so concurrent writers never share a
        // temporary file; the rename makes the last complete file win.
        let tmp = path.with_extension(format!(
            "tmp.{}.{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let written = fs::write(&tmp, text).and_then(|()| fs::rename(&tmp, &path));
        if written.is_err() {
            let _ = fs::remove_file(&tmp);
        }
        written
    }

    /// The stored matrix, or `compute`'s, which is then stored. A failed
    /// write only costs the next run a recomputation, so it is ignored.
    ///
    /// Two processes missing the same key (a report and a diagnosis started
    /// together, or parallel test runs) would each spend the solve's seconds
    /// to a minute; the second waits on the key's lock file instead and then
    /// reads the first one's file. The lock is the operating system's
    /// advisory lock on an open file, released when its holder exits or is
    /// killed, so a crashed solver never leaves the key locked. Without a
    /// lock (a read-only directory, a file system without locks) the solve
    /// simply runs unguarded, as it would without the disk layer.
    pub fn get_or_compute<E: ToString>(
        &self,
        kind: &str,
        key: &[u64],
        compute: impl FnOnce() -> Result<Matrix6<f64>, E>,
    ) -> Result<Matrix6<f64>, CacheError> {
        if let Some(m) = self.load(kind, key) {
            return Ok(m);
        }
        let _lock = self.lock(kind, key);
        if let Some(m) = self.load(kind, key) {
            return Ok(m);
        }
        let m = compute().map_err(|e| CacheError::Solve(e.to_string()))?;
        let _ = self.store(kind, key, &m);
        Ok(m)
    }

    /// The key's lock file, held exclusively until the returned file is
    /// dropped; `None` when the directory or the lock cannot be had. The
    /// file is left in place: removing it would let a third process lock a
    /// new file while a second still waits on the old one.
    fn lock(&self, kind: &str, key: &[u64]) -> Option<fs::File> {
        fs::create_dir_all(&self.dir).ok()?;
        let file = fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(self.path(kind, key).with_extension("lock"))
            .ok()?;
        file.lock().ok()?;
        Some(file)
    }
}

/// The matrix for `kind`/`key`: from memory, else from the disk cache in
/// [`default_dir`], else computed (and remembered in both; errors only in
/// memory).
pub fn cached_matrix<E: ToString>(
    kind: &'static str,
    key: &[u64],
    compute: impl FnOnce() -> Result<Matrix6<f64>, E>,
) -> Result<Matrix6<f64>, CacheError> {
    cached_matrix_in(&DiskCache::default_location(), kind, key, compute)
}

/// [`cached_matrix`] with the disk layer in `disk`.
pub fn cached_matrix_in<E: ToString>(
    disk: &DiskCache,
    kind: &'static str,
    key: &[u64],
    compute: impl FnOnce() -> Result<Matrix6<f64>, E>,
) -> Result<Matrix6<f64>, CacheError> {
    let slot = {
        let mut map = memory().lock().map_err(|_| CacheError::Poisoned)?;
        Arc::clone(map.entry((kind, key.to_vec())).or_default())
    };
    // Held while solving: another thread asking for this key waits.
    let mut guard = slot.lock().map_err(|_| CacheError::EntryPoisoned)?;
    if let Some(r) = guard.as_ref() {
        return r.clone();
    }
    let r = disk.get_or_compute(kind, key, compute);
    *guard = Some(r.clone());
    r
}

/// Key words of a helix: every field, bit for bit.
pub fn helix_words(h: &Helix) -> [u64; 7] {
    [
        h.wavelength_m.to_bits(),
        h.amplitude_m.to_bits(),
        h.axial_length_m.to_bits(),
        h.wire_diameter_m.to_bits(),
        u64::from(h.handedness == Handedness::Right),
        h.phase_rad.to_bits(),
        h.joint_x_m.to_bits(),
    ]
}

/// Key words of a channel: every field, including those the wall model
/// does not read (length, orientation), so a future use of them cannot
/// return a stale matrix.
pub fn channel_words(c: &Channel) -> [u64; 4] {
    [
        c.diameter_m.to_bits(),
        c.length_m.to_bits(),
        u64::from(c.closed),
        u64::from(c.vertical),
    ]
}

/// Key words of a body.
pub fn body_words(b: &Body) -> [u64; 2] {
    [b.length_m.to_bits(), b.diameter_m.to_bits()]
}

/// Key words of the solver settings: every field.
pub fn settings_words(s: &NonlocalSettings) -> [u64; 9] {
    [
        u64::from(s.method == TailMethod::SlenderBody),
        s.segments_per_turn as u64,
        s.min_segments as u64,
        s.blob_over_wire_radius.to_bits(),
        u64::from(s.wire_spin),
        s.body_spacing_m.to_bits(),
        s.wall_spacing_m.to_bits(),
        s.surface_blob_over_spacing.to_bits(),
        s.tube_end_margin_over_radius.to_bits(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;
    use std::time::Duration;

    fn matrix(v: f64) -> Matrix6<f64> {
        Matrix6::from_diagonal_element(v)
    }

    /// Two callers of the disk layer alone (no memory map between them, as
    /// two processes are) missing the same key: one solves, the other waits
    /// on the lock and reads its file.
    #[test]
    fn a_key_being_solved_is_solved_once_by_two_callers() {
        let dir = tempfile::tempdir().unwrap();
        let solves = AtomicUsize::new(0);
        let get = || {
            DiskCache::new(dir.path())
                .get_or_compute("test-kind", &[1, 2, 3], || {
                    solves.fetch_add(1, Ordering::SeqCst);
                    std::thread::sleep(Duration::from_millis(300));
                    Ok::<_, String>(matrix(2.5))
                })
                .unwrap()
        };
        let (a, b) = std::thread::scope(|s| {
            let a = s.spawn(get);
            let b = s.spawn(get);
            (a.join().unwrap(), b.join().unwrap())
        });
        assert_eq!(solves.load(Ordering::SeqCst), 1);
        assert_eq!(a, matrix(2.5));
        assert_eq!(b, a);
    }

    /// The lock file stays behind and never blocks a later caller; a key
    /// whose solve fails leaves no matrix and the next caller solves again.
    #[test]
    fn a_lock_left_behind_or_a_failed_solve_does_not_block_the_next_caller() {
        let dir = tempfile::tempdir().unwrap();
        let cache = DiskCache::new(dir.path());
        let failed = cache.get_or_compute("test-kind", &[7], || Err::<Matrix6<f64>, _>("no"));
        assert_eq!(failed, Err(CacheError::Solve("no".into())));
        assert!(cache
            .path("test-kind", &[7])
            .with_extension("lock")
            .exists());
        let m = cache
            .get_or_compute("test-kind", &[7], || Ok::<_, String>(matrix(4.0)))
            .unwrap();
        assert_eq!(m, matrix(4.0));
        assert_eq!(cache.load("test-kind", &[7]), Some(matrix(4.0)));
    }

    /// A directory that cannot be made (a file stands there) still gives the
    /// solve's result, unguarded and unstored.
    #[test]
    fn without_a_directory_the_solve_runs_unguarded() {
        let dir = tempfile::tempdir().unwrap();
        let blocker = dir.path().join("file");
        fs::write(&blocker, "").unwrap();
        let cache = DiskCache::new(blocker.join("cache"));
        let m = cache
            .get_or_compute("test-kind", &[9], || Ok::<_, String>(matrix(1.0)))
            .unwrap();
        assert_eq!(m, matrix(1.0));
        assert_eq!(cache.load("test-kind", &[9]), None);
    }
}
