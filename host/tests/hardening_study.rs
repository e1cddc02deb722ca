//! The study file never loses a step nor fills the machine: a study or its
//! dataset pointed at an endless device or a FIFO is refused at its
//! kind's cap, two commands writing one study at once never lose a
//! recorded step, and a full disk leaves the study as it was.

use crate::common::{mkfifo, stderr, within};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;
use swimbot::study::{AddOptions, Definition, InitOptions, Study, StudyError, DEFAULT_FILE};

/// A study on the paper's CSV in a fresh folder, made by the library
/// without its diagnosis (the commands below do not need it).
fn study() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("paper.csv");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        &data,
    )
    .unwrap();
    let path = dir.path().join(DEFAULT_FILE);
    let o = InitOptions {
        diagnose: false,
        ..Default::default()
    };
    Study::init(&path, &data, &o).unwrap();
    (dir, path)
}

fn refused(o: &Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "no `{n}` in: {e}");
    }
}

#[test]
fn a_study_or_its_dataset_on_an_endless_device_or_a_silent_fifo_is_refused_at_once() {
    let limit = Duration::from_secs(20);
    // The study itself: /dev/zero (was read whole: the machine's memory),
    // a FIFO with no writer (was a hang).
    for make in [
        |p: &Path| std::os::unix::fs::symlink("/dev/zero", p).unwrap(),
        mkfifo as fn(&Path),
    ] {
        let (dir, path) = study();
        std::fs::remove_file(&path).unwrap();
        make(&path);
        let o = within(dir.path(), &["steps"], &[], limit);
        refused(&o, &[DEFAULT_FILE]);
    }
    // Its dataset, edited to point at them (the SHA-256 was computed over
    // an unbounded read before the dataset's own capped one).
    for make in [
        |p: &Path| std::os::unix::fs::symlink("/dev/zero", p).unwrap(),
        mkfifo as fn(&Path),
    ] {
        let (dir, _) = study();
        let data = dir.path().join("paper.csv");
        std::fs::remove_file(&data).unwrap();
        make(&data);
        let o = within(dir.path(), &["steps"], &[], limit);
        refused(&o, &[DEFAULT_FILE, "paper.csv"]);
    }
}

#[test]
fn two_writers_of_one_study_never_lose_a_recorded_step() {
    let (_dir, path) = study();
    let quick = AddOptions {
        diagnose: false,
        force: true,
        ..Default::default()
    };
    let effect = |n: &str| Definition::of_catalogue(swimbot::effects::by_name(n).unwrap());
    // Two commands open the study, as two `add`s started together do.
    let mut a = Study::open(&path).unwrap();
    let mut b = Study::open(&path).unwrap();
    a.add(effect("buoyancy"), &quick).unwrap();
    // The second would have written its step over the first's: refused,
    // naming the file, the first's step kept.
    let e = b.add(effect("backflow"), &quick).unwrap_err();
    assert!(matches!(e, StudyError::Changed { .. }), "{e}");
    assert!(e.to_string().contains(DEFAULT_FILE), "{e}");
    assert!(e.is_input());
    let now = Study::open(&path).unwrap();
    let names: Vec<&str> = now.steps().iter().map(|s| s.effect.name.as_str()).collect();
    assert_eq!(names, ["buoyancy"]);
    // An undo on a view opened before another write is refused too; the
    // object that wrote may write again after its own write.
    let mut c = Study::open(&path).unwrap();
    a.add(effect("backflow"), &quick).unwrap();
    assert!(matches!(c.undo(), Err(StudyError::Changed { .. })));
    a.undo().unwrap();
    assert_eq!(Study::open(&path).unwrap().steps().len(), 1);
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "the full disk is simulated in debug builds only (atomic_dir::fault_injection)"
)]
fn a_full_disk_leaves_the_study_as_it_was_and_is_exit_2() {
    let (dir, path) = study();
    let quick = AddOptions {
        diagnose: false,
        force: true,
        ..Default::default()
    };
    let buoyancy = Definition::of_catalogue(swimbot::effects::by_name("buoyancy").unwrap());
    Study::open(&path).unwrap().add(buoyancy, &quick).unwrap();
    let before = std::fs::read(&path).unwrap();
    // The fault is injected by debug builds only; the test profile is one.
    let o = within(
        dir.path(),
        &["undo"],
        &[("SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES", "100")],
        Duration::from_secs(60),
    );
    refused(&o, &[DEFAULT_FILE, "No space left"]);
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}
