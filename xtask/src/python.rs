//! The Python package's step of `cargo xtask test`: a virtual environment
//! under `target/pyenv` with maturin, numpy, pandas and pytest from PyPI
//! (set up in the background while the host compiles), the extension built
//! once in the dev profile into the workspace's target dir (the `swimbot`
//! library the host tests just built is reused, not rebuilt in release),
//! installed, and the pytest suite run against the CLI binary it compares
//! with (`target/debug/swimbot`).
//!
//! The dev profile: a release build of the library and its dependencies
//! would be a second full build of the workspace; the suite checks that the
//! numbers equal the CLI's, not speed (the README's performance table
//! measures the release wheel).

use crate::background::Background;
use crate::steps::Steps;
use std::path::{Path, PathBuf};
use std::process::Command;

const VENV: &str = "target/pyenv";
const PACKAGES: [&str; 4] = ["maturin>=1.5,<2", "numpy", "pandas", "pytest"];

/// Create the environment and install the packages, in the background.
pub fn start_venv(root: &Path, logs: &Path) -> Background {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let script = format!(
        "{python} -m venv {VENV} && {VENV}/bin/python -m pip install --quiet --disable-pip-version-check {}",
        PACKAGES.map(|p| format!("'{p}'")).join(" ")
    );
    Background::start(
        "Python environment (target/pyenv: maturin, numpy, pandas, pytest from PyPI)",
        root,
        "sh",
        &["-c", &script],
        logs.join("pyenv.log"),
    )
}

/// How the host steps built and linted the workspace's crates: the same
/// settings make the extension's build lint them too and reuse the
/// library those steps compiled instead of compiling it a second time.
pub struct Lint {
    /// Environment (clippy's driver as the workspace wrapper, its flags).
    pub env: Vec<(&'static str, std::ffi::OsString)>,
    /// `--config` settings of a cold build.
    pub configs: Vec<String>,
}

/// Build the extension, install it, run pytest.
pub fn test(root: &Path, steps: &mut Steps, venv: Background, lint: &Lint) -> Result<(), String> {
    steps.begin("Python environment: fetched in the background");
    venv.finish()?;
    steps.begin("Python extension (maturin, dev profile, clippy) and pytest");
    features_agree(root)?;
    let bin = root.join(VENV).join("bin");
    let wheels = root.join("target/wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    let mut maturin = Command::new(bin.join("maturin"));
    maturin
        .args(["build", "--profile", "dev", "-m", "python/Cargo.toml", "-o"])
        .arg(&wheels)
        .arg("-i")
        .arg(bin.join("python"))
        .current_dir(root);
    for (k, v) in &lint.env {
        maturin.env(k, v);
    }
    for c in &lint.configs {
        maturin.args(["--config", c]);
    }
    status(maturin, "maturin build")?;
    let wheel = std::fs::read_dir(&wheels)
        .map_err(|e| format!("{}: {e}", wheels.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .ok_or("maturin wrote no wheel")?;
    let mut pip = Command::new(bin.join("python"));
    pip.args([
        "-m",
        "pip",
        "install",
        "--quiet",
        "--disable-pip-version-check",
        "--force-reinstall",
        "--no-deps",
    ])
    .arg(&wheel)
    .current_dir(root);
    status(pip, "pip install the wheel")?;
    let mut pytest = Command::new(bin.join("python"));
    pytest
        .args(["-m", "pytest", "-q", "python/tests"])
        .env("SWIMBOT_BIN", swimbot_bin(root))
        .current_dir(root);
    status(pytest, "pytest python/tests")
}

fn swimbot_bin(root: &Path) -> PathBuf {
    root.join("target/debug/swimbot")
}

fn status(mut c: Command, what: &str) -> Result<(), String> {
    let s = c
        .status()
        .map_err(|e| format!("cannot start {what}: {e}"))?;
    if s.success() {
        Ok(())
    } else {
        Err(format!("{what} failed ({s})"))
    }
}

/// The extension's dependencies resolve to the features the host test
/// build gave them, so maturin reuses that build (python/Cargo.toml says
/// which features it names for this). A crate that drifts is named here
/// instead of silently compiling half the graph again.
fn features_agree(root: &Path) -> Result<(), String> {
    let host = resolved_features(
        root,
        &[
            "--workspace",
            "--exclude",
            "firmware",
            "--exclude",
            "swimbot-python",
            "-e",
            "normal,build,dev",
        ],
    )?;
    let extension = resolved_features(root, &["-p", "swimbot-python", "-e", "normal,build"])?;
    let drift: Vec<String> = extension
        .iter()
        .filter_map(|(package, features)| {
            let in_host = host.get(package)?;
            (in_host != features).then(|| {
                format!("{package}: host test build [{in_host}], extension alone [{features}]")
            })
        })
        .collect();
    if drift.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "the Python extension's dependencies resolve to other features than the host test \
             build's, so maturin would compile them again; give python/Cargo.toml the host's \
             features:\n  {}",
            drift.join("\n  ")
        ))
    }
}

/// Each package of `cargo tree ARGS` with its resolved features.
fn resolved_features(
    root: &Path,
    args: &[&str],
) -> Result<std::collections::BTreeMap<String, String>, String> {
    let out = Command::new("cargo")
        .args(["tree", "--prefix", "none", "-f", "{p}|{f}"])
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot start `cargo tree`: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "`cargo tree {}` failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|line| {
            let (package, features) = line.split_once('|')?;
            // "name vX.Y.Z (path)" and repeats marked "(*)": the name and version.
            let mut words = package.split_whitespace();
            let id = format!("{} {}", words.next()?, words.next()?);
            Some((id, features.trim_end_matches(" (*)").to_string()))
        })
        .collect())
}
