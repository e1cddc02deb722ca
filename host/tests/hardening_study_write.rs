//! The study file is written under the rules every other output follows:
//! never over an input, a FIFO or a device, a symbolic link followed,
//! no temporary file left by a killed run, a name as long as the file
//! system allows, and an exit status that agrees with what was recorded.

use crate::common::{mkfifo, run_in, stderr};
use std::path::{Path, PathBuf};
use std::process::Output;
use swimbot::study::{InitOptions, Study, DEFAULT_FILE};

const PAPER_CSV: &str = include_str!("../data/paper.csv");

/// A folder with the paper's CSV and a study on it (library, no diagnosis).
fn study() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.csv"), PAPER_CSV).unwrap();
    let path = dir.path().join(DEFAULT_FILE);
    let o = InitOptions {
        diagnose: false,
        ..Default::default()
    };
    Study::init(&path, &dir.path().join("paper.csv"), &o).unwrap();
    (dir, path)
}

/// The paper's CSV with its viscosity moved into a setup file `rig.toml`.
pub fn with_setup_file(dir: &Path) -> PathBuf {
    let csv = PAPER_CSV.replacen(
        "# viscosity_pa_s = 3.5\n",
        "# setup_file = \"rig.toml\"\n",
        1,
    );
    assert_ne!(csv, PAPER_CSV, "the paper's CSV states its viscosity");
    std::fs::write(dir.join("rig.toml"), "[setup]\nviscosity_pa_s = 3.5\n").unwrap();
    let path = dir.join("runs.csv");
    std::fs::write(&path, csv).unwrap();
    path
}

fn refused(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "no `{n}` in: {e}");
    }
}

fn steps_recorded(path: &Path) -> usize {
    Study::open(path).unwrap().steps().len()
}

fn temps_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect()
}

#[test]
fn init_force_never_replaces_the_dataset_or_its_setup_file() {
    let dir = tempfile::tempdir().unwrap();
    with_setup_file(dir.path());
    for target in ["runs.csv", "rig.toml"] {
        let before = std::fs::read(dir.path().join(target)).unwrap();
        let o = run_in(
            dir.path(),
            &["--study", target, "init", "--data", "runs.csv", "--force"],
        );
        refused(&o, &[target]);
        assert_eq!(std::fs::read(dir.path().join(target)).unwrap(), before);
    }
    // Nor any other file that is not a study.
    std::fs::write(dir.path().join("notes.txt"), "mine").unwrap();
    let o = run_in(
        dir.path(),
        &[
            "--study",
            "notes.txt",
            "init",
            "--data",
            "runs.csv",
            "--force",
        ],
    );
    refused(&o, &["notes.txt", "not a study file"]);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("notes.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn an_output_naming_the_study_is_refused_as_an_input() {
    let (dir, path) = study();
    let before = std::fs::read(&path).unwrap();
    let o = run_in(dir.path(), &["diagnose", "--write-effect", DEFAULT_FILE]);
    refused(&o, &[DEFAULT_FILE, "input"]);
    assert_eq!(std::fs::read(&path).unwrap(), before);
}

#[test]
fn init_force_on_a_fifo_or_a_device_is_refused_and_leaves_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.csv"), PAPER_CSV).unwrap();
    let fifo = dir.path().join("pipe");
    mkfifo(&fifo);
    let o = run_in(
        dir.path(),
        &["--study", "pipe", "init", "--data", "paper.csv", "--force"],
    );
    refused(&o, &["pipe", "FIFO"]);
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // A link to a device is followed to it, and refused.
    std::os::unix::fs::symlink("/dev/null", dir.path().join("null.toml")).unwrap();
    let o = run_in(
        dir.path(),
        &[
            "--study",
            "null.toml",
            "init",
            "--data",
            "paper.csv",
            "--force",
        ],
    );
    refused(&o, &["null.toml", "character device"]);
}

#[test]
fn a_study_that_is_a_link_stays_a_link_and_its_target_gets_the_step() {
    let (dir, path) = study();
    let real = dir.path().join("real-study.toml");
    std::fs::rename(&path, &real).unwrap();
    std::os::unix::fs::symlink("real-study.toml", &path).unwrap();
    let o = run_in(dir.path(), &["add", "buoyancy", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&path)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(steps_recorded(&real), 1);
    assert!(temps_in(dir.path()).is_empty());
}

#[test]
fn a_temporary_study_left_by_a_killed_run_is_swept_by_the_next_write() {
    let (dir, _path) = study();
    // PID 2147483646 runs nowhere; both the current and the old naming.
    let left = [
        format!(".{DEFAULT_FILE}.tmp-2147483646"),
        format!(".{DEFAULT_FILE}.2147483646.tmp"),
    ];
    for l in &left {
        std::fs::write(dir.path().join(l), "half a study").unwrap();
    }
    let o = run_in(dir.path(), &["add", "buoyancy", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        temps_in(dir.path()).is_empty(),
        "{:?}",
        temps_in(dir.path())
    );
}

#[test]
fn a_full_stdout_after_add_leaves_no_step_recorded() {
    let (dir, path) = study();
    let before = std::fs::read(&path).unwrap();
    let out = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let o = crate::common::command()
        .args(["add", "buoyancy", "--force"])
        .current_dir(dir.path())
        .stdout(out)
        .output()
        .unwrap();
    refused(&o, &["No space left"]);
    // Exit 2 and the step recorded disagreed; now the study is as it was,
    // and the retry is not told the effect is "already in the model".
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert!(temps_in(dir.path()).is_empty());
    let o = run_in(dir.path(), &["add", "buoyancy", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(steps_recorded(&path), 1);
}

#[test]
fn a_signal_during_add_leaves_no_temporary_and_the_exit_agrees_with_the_study() {
    use std::os::unix::process::ExitStatusExt;
    // Signals sent at spread moments of an `add` (its calibration, its
    // write, its printing): whatever the moment, success means the step
    // is there, a death by the signal (or 130/143) means it is not.
    for (i, delay_ms) in [5u64, 40, 80, 120, 160, 200, 260, 320].iter().enumerate() {
        let (dir, path) = study();
        let mut child = crate::common::command()
            .args(["add", "buoyancy", "--force"])
            .current_dir(dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(*delay_ms));
        let sig = if i % 2 == 0 {
            libc::SIGINT
        } else {
            libc::SIGTERM
        };
        // SAFETY: a signal to the child this test started.
        unsafe { libc::kill(child.id() as i32, sig) };
        let status = child.wait().unwrap();
        let recorded = steps_recorded(&path);
        let succeeded = status.success();
        let stopped = status.signal() == Some(sig) || status.code() == Some(128 + sig);
        assert!(succeeded || stopped, "{status:?}");
        assert_eq!(
            recorded,
            usize::from(succeeded),
            "{status:?} after {delay_ms} ms"
        );
        assert!(
            temps_in(dir.path()).is_empty(),
            "{:?}",
            temps_in(dir.path())
        );
    }
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "the pause after the commit exists in debug builds only (atomic_file)"
)]
fn a_signal_just_after_the_study_is_written_puts_the_old_study_back() {
    // Exactly the moment the exit status and the study disagreed: the
    // step renamed in, the run not yet ended (here held open 3 s).
    let (dir, path) = study();
    let before = std::fs::read(&path).unwrap();
    let mut child = crate::common::command()
        .args(["add", "buoyancy", "--force"])
        .env("SWIMBOT_FAULT_PAUSE_AFTER_COMMIT_MS", "3000")
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while std::fs::read(&path).unwrap() == before {
        assert!(start.elapsed().as_secs() < 30, "the step was never written");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    // SAFETY: a signal to the child this test started.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let status = child.wait().unwrap();
    assert!(!status.success(), "{status:?}");
    assert_eq!(std::fs::read(&path).unwrap(), before, "{status:?}");
    assert!(
        temps_in(dir.path()).is_empty(),
        "{:?}",
        temps_in(dir.path())
    );
}

#[test]
fn a_study_name_near_the_file_name_limit_is_written() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("paper.csv"), PAPER_CSV).unwrap();
    let name = format!("{}.toml", "s".repeat(240));
    assert_eq!(name.len(), 245);
    let o = run_in(
        dir.path(),
        &["--study", &name, "init", "--data", "paper.csv"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(steps_recorded(&dir.path().join(&name)), 0);
    assert!(temps_in(dir.path()).is_empty());
    // sweep -o with the longest name that fits: the temporary one was
    // longer and the error named it.
    let out = format!("{}.csv", "w".repeat(246));
    let o = run_in(
        dir.path(),
        &[
            "sweep",
            "--wavelength-mm",
            "10",
            "--amplitude-mm",
            "2",
            "--tail-length-mm",
            "20",
            "-o",
            &out,
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join(&out).is_file());
}
