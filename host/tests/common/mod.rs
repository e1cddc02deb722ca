//! Helpers shared by the integration tests that run the real `swimbot`
//! binary (each test file compiles this module and uses what it needs).
#![allow(dead_code)]

use std::process::{Command, Output};

/// Run the binary in a fresh temporary working directory, so that default
/// outputs (`swimbot-out/`, `report/`) never land in the repository.
pub fn swimbot(args: &[&str]) -> Output {
    let cwd = tempfile::tempdir().expect("a temporary directory");
    Command::new(env!("CARGO_BIN_EXE_swimbot"))
        .args(args)
        .current_dir(cwd.path())
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
