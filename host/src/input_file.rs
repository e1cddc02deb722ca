//! Reading an input file whole, bounded by its kind's size cap *while*
//! reading: every file a command reads (dataset, setup file, robot file,
//! remote script, run log, effects file) comes through [`read`], so that
//! `/dev/zero`, a FIFO fed without end or a file that grows while it is
//! read costs at most the cap plus one byte of memory, never the machine.
//!
//! **Kinds of file.** A regular file is read as it is. A pipe or FIFO is
//! meaningful (`--data <(gen)`, `swimbot log /dev/stdin < run.swlog`), so
//! it is read too, through the same cap. A FIFO that no process writes
//! must not hang the run: it is opened with `O_NONBLOCK` (which does not
//! wait for a writer), then given [`FIFO_WRITER_WAIT_MS`] for a writer to
//! appear (a writer started beside the reader, `mkfifo f; gen > f &
//! swimbot log f`, may open it a moment later; reading before it would see
//! end-of-file and refuse a good log as empty), and the flag is then
//! cleared, so reading it returns what its writer sends, or end-of-file
//! when it has none (then refused as empty by the caller's parser). A character device is read
//! through the cap (`/dev/zero` ends at the cap, `/dev/null` is empty). A
//! directory, socket or block device is refused with its kind named.

use std::io::Read;
use std::path::Path;

/// The size caps of each kind of input (bytes). A cap is far above any
/// real file of its kind and far below what would trouble the machine.
pub mod cap {
    /// A dataset (TOML or CSV): 10 000 cases of a few hundred bytes each,
    /// with their trials, fit in a few MB.
    pub const DATASET: u64 = 64 << 20;
    /// A CSV's `# setup_file =` side file: a `[setup]` table of a few keys.
    pub const SETUP_FILE: u64 = 1 << 20;
    /// A robot file: a few tails and constants.
    pub const ROBOT: u64 = 1 << 20;
    /// A remote script: a line per command, a day of commands at most.
    pub const SCRIPT: u64 = 1 << 20;
    /// A run log image: a 10-minute run at 10 Hz is 96 kB; the robot's
    /// flash holds far less than this.
    pub const RUN_LOG: u64 = 16 << 20;
    /// An effects file (see `data::limits::MAX_EFFECT_FILE_BYTES`).
    pub const EFFECTS: u64 = crate::data::limits::MAX_EFFECT_FILE_BYTES;
    /// A study file: a few kB per step with its diagnoses; a thousand
    /// steps fit.
    pub const STUDY: u64 = 16 << 20;
    /// A report's `manifest.json` read back from an output folder.
    pub const MANIFEST: u64 = 16 << 20;
}

/// Why an input could not be read, in words a message can carry after
/// the file's name and a colon.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read the file: {0}")]
    Io(String),
    #[error("the file is {0}, not a file swimbot reads; name a regular file (or a pipe)")]
    Kind(&'static str),
    #[error("the file is larger than {cap} bytes, the limit of {what}; nothing was read past it")]
    TooLarge { cap: u64, what: &'static str },
}

/// The whole of `path`, at most `cap_bytes` of it: more is an error,
/// detected after reading `cap_bytes + 1` bytes (module docs). `what`
/// names the kind in the message ("a dataset").
pub fn read(path: &Path, cap_bytes: u64, what: &'static str) -> Result<Vec<u8>, ReadError> {
    let file = open(path)?;
    let mut bytes = Vec::new();
    file.take(cap_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if bytes.len() as u64 > cap_bytes {
        return Err(ReadError::TooLarge {
            cap: cap_bytes,
            what,
        });
    }
    Ok(bytes)
}

/// [`read`] as UTF-8 text.
pub fn read_text(path: &Path, cap_bytes: u64, what: &'static str) -> Result<String, ReadError> {
    let bytes = read(path, cap_bytes, what)?;
    String::from_utf8(bytes).map_err(|e| ReadError::Io(format!("not UTF-8 text: {e}")))
}

#[cfg(unix)]
fn open(path: &Path) -> Result<std::fs::File, ReadError> {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    use std::os::unix::io::AsRawFd;
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    let kind = file
        .metadata()
        .map_err(|e| ReadError::Io(e.to_string()))?
        .file_type();
    if kind.is_dir() {
        return Err(ReadError::Kind("a directory"));
    }
    if kind.is_block_device() {
        return Err(ReadError::Kind("a block device"));
    }
    if kind.is_socket() {
        return Err(ReadError::Kind("a socket"));
    }
    if kind.is_fifo() {
        wait_for_a_writer(&file);
    }
    // Back to blocking reads: a pipe's writer may be slower than us.
    // SAFETY: fcntl on a descriptor this function owns, with integer flags.
    let fd = file.as_raw_fd();
    let cleared = unsafe {
        let flags = libc::fcntl(fd, libc::F_GETFL);
        flags >= 0 && libc::fcntl(fd, libc::F_SETFL, flags & !libc::O_NONBLOCK) >= 0
    };
    if !cleared {
        return Err(ReadError::Io(std::io::Error::last_os_error().to_string()));
    }
    Ok(file)
}

/// How long a FIFO without a writer is given for one to open it (module
/// docs): far longer than a process started beside the reader takes, short
/// enough that a FIFO nobody writes costs the user a moment, not a hang.
#[cfg(unix)]
pub const FIFO_WRITER_WAIT_MS: i32 = 3000;

/// Waits until the FIFO has data or a writer has come and gone, at most
/// [`FIFO_WRITER_WAIT_MS`]. On Linux `poll` reports neither for a FIFO that
/// has never had a writer, so a FIFO nobody writes waits the whole time and
/// is then read as empty; a FIFO whose writer is already there returns at
/// once.
#[cfg(unix)]
fn wait_for_a_writer(file: &std::fs::File) {
    use std::os::unix::io::AsRawFd;
    let mut p = libc::pollfd {
        fd: file.as_raw_fd(),
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: one pollfd on a descriptor the caller owns; the result only
    // decides how long we waited, so an error (EINTR) is as good as a timeout.
    unsafe {
        libc::poll(&mut p, 1, FIFO_WRITER_WAIT_MS);
    }
}

#[cfg(not(unix))]
fn open(path: &Path) -> Result<std::fs::File, ReadError> {
    let file = std::fs::File::open(path).map_err(|e| ReadError::Io(e.to_string()))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(ReadError::Kind("a directory"));
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_at_the_cap_is_read_and_one_byte_more_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x");
        std::fs::write(&p, b"12345").unwrap();
        assert_eq!(read(&p, 5, "a test").unwrap(), b"12345");
        let e = read(&p, 4, "a test").unwrap_err();
        assert!(e.to_string().contains("larger than 4 bytes"), "{e}");
        assert_eq!(
            read(dir.path(), 5, "a test").unwrap_err(),
            ReadError::Kind("a directory")
        );
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_stops_at_the_cap() {
        let e = read(Path::new("/dev/zero"), 1 << 16, "a test").unwrap_err();
        assert!(matches!(e, ReadError::TooLarge { cap: 65536, .. }), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_without_a_writer_is_empty_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("fifo");
        let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
        // SAFETY: a NUL-terminated path and a mode.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        assert_eq!(read(&p, 100, "a test").unwrap(), b"");
    }
}
