//! Helpers shared by the integration tests that run the real `swimbot`
//! binary (each test file compiles this module and uses what it needs).
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Run the binary in a fresh temporary working directory, so that default
/// outputs (`swimbot-out/`, `report/`) never land in the repository.
pub fn swimbot(args: &[&str]) -> Output {
    let cwd = tempfile::tempdir().expect("a temporary directory");
    run_in(cwd.path(), args)
}

/// The `swimbot` binary, its non-local cache in this build's test
/// directory. Every child gets the same cache, whatever the test process's
/// own environment says (a test may point `$SWIMBOT_CACHE_DIR` at a fresh
/// directory for its in-process solves, and children would inherit it and
/// solve every tube geometry again), and never the user's cache. The
/// directory outlives the run, so a second run of the suite reads it.
pub fn command() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_swimbot"));
    c.env(
        swimbot::nonlocal::cache::CACHE_DIR_ENV,
        concat!(env!("CARGO_TARGET_TMPDIR"), "/swimbot-cache"),
    );
    c
}

/// Run the binary in `cwd` (kept by the caller, to read what it wrote).
pub fn run_in(cwd: &Path, args: &[&str]) -> Output {
    command()
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the swimbot binary runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Writes a short simulated run log to `path` (rate-controlled 0.6 Hz,
/// On at 0 s, Off at 12 s), the simulation's other outputs in `out`.
pub fn write_simulated_log(path: &std::path::Path, out: &std::path::Path) {
    let o = swimbot(&[
        "sim",
        "--tail",
        "3",
        "--rate-hz",
        "0.6",
        "--script",
        "on@0s,off@12s",
        "--write-log",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The binary in `dir` with `env` added, killed (and the test failed) after
/// `limit`: for inputs that must be refused quickly, never hang.
pub fn within(dir: &Path, args: &[&str], env: &[(&str, &str)], limit: Duration) -> Output {
    let mut child = command()
        .args(args)
        .envs(env.iter().copied())
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// A named pipe at `p`.
#[cfg(unix)]
pub fn mkfifo(p: &Path) {
    let c = std::ffi::CString::new(p.to_str().expect("a UTF-8 path")).unwrap();
    // SAFETY: a NUL-terminated path and a mode.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
}
