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
