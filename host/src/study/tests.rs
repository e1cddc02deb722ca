//! The study's library interface on the paper's data: init, add, undo,
//! the file's round trip, a refused rise, a changed dataset.

use super::*;
use std::path::PathBuf;

fn setup() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("lab.csv");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        &data,
    )
    .unwrap();
    let study = dir.path().join(DEFAULT_FILE);
    (dir, data, study)
}

fn quick() -> (InitOptions, AddOptions) {
    (
        InitOptions {
            diagnose: false,
            ..Default::default()
        },
        AddOptions {
            diagnose: false,
            ..Default::default()
        },
    )
}

fn catalogue(name: &str) -> Definition {
    Definition::of_catalogue(crate::effects::by_name(name).unwrap())
}

#[test]
fn a_step_lowers_the_error_and_survives_the_file_round_trip() {
    let (_dir, data, path) = setup();
    let (io, ao) = quick();
    let mut s = Study::init(&path, &data, &io).unwrap();
    let start = s.current().stats.mare;
    s.add(catalogue("backflow"), &ao).unwrap();
    let step = &s.steps()[0];
    assert_eq!(step.before.mare, start);
    assert!(
        step.after.stats.mare < start,
        "{} !< {start}",
        step.after.stats.mare
    );
    // every free parameter has an interval or a reason, never "±?"
    for p in &step.params {
        match p.status.as_str() {
            "fitted" => assert!(
                p.lo.unwrap() <= p.value && p.value <= p.hi.unwrap(),
                "{p:?}"
            ),
            "fixed" => assert!(p.reason.is_some()),
            _ => {}
        }
    }
    let again = Study::open(&path).unwrap();
    assert_eq!(again.file(), s.file());
    // the reopened model predicts what was stored
    let snap = Snapshot::of(&again.model().unwrap(), again.dataset(), &[]).unwrap();
    assert_eq!(snap.stats.mare, step.after.stats.mare);
    assert_eq!(snap.cases, step.after.cases);
}

#[test]
fn undo_restores_the_model_before_the_step() {
    let (_dir, data, path) = setup();
    let (io, ao) = quick();
    let mut s = Study::init(&path, &data, &io).unwrap();
    let before = s.file().clone();
    s.add(catalogue("backflow"), &ao).unwrap();
    assert_eq!(s.undo().unwrap().effect.name, "backflow");
    assert_eq!(Study::open(&path).unwrap().file(), &before);
    assert!(matches!(s.undo(), Err(StudyError::NothingToUndo { .. })));
}

#[test]
fn an_effect_twice_and_an_existing_study_are_refused() {
    let (_dir, data, path) = setup();
    let (io, ao) = quick();
    let mut s = Study::init(&path, &data, &io).unwrap();
    s.add(catalogue("backflow"), &ao).unwrap();
    let e = s.add(catalogue("backflow"), &ao).unwrap_err();
    assert!(
        e.to_string().contains("already in the model (step 1)"),
        "{e}"
    );
    assert!(matches!(
        Study::init(&path, &data, &io),
        Err(StudyError::Exists { .. })
    ));
}

#[test]
fn a_changed_dataset_is_refused_with_both_hashes() {
    let (_dir, data, path) = setup();
    let (io, _) = quick();
    let s = Study::init(&path, &data, &io).unwrap();
    let pinned = s.file().dataset.sha256.clone();
    let text = std::fs::read_to_string(&data).unwrap();
    std::fs::write(&data, text.replacen("0.586", "0.587", 1)).unwrap();
    match Study::open(&path) {
        Err(StudyError::DatasetChanged {
            expected, found, ..
        }) => {
            assert_eq!(expected, pinned);
            assert_ne!(found, pinned);
        }
        other => panic!("{other:?}"),
    }
}

/// A user effect with no free parameter that turns the tail three times
/// faster than recorded: on the paper's data, where plain RFT already
/// over-predicts, it can only raise the error.
fn faster_drive() -> Definition {
    Definition {
        name: "study-test-faster-drive".into(),
        kind: "user".into(),
        statement: "the tail turns three times faster than recorded".into(),
        reference: "a test".into(),
        formula: vec!["drive.rate = 3".into()],
        definition: Some(
            "[[effect]]\nname = \"study-test-faster-drive\"\nstatement = \"s\"\nreference = \"r\"\n\
             [effect.places]\n\"drive.rate\" = \"3\"\n"
                .into(),
        ),
    }
}

#[test]
fn a_step_that_raises_the_error_is_refused_with_the_numbers_unless_forced() {
    let (_dir, data, path) = setup();
    let (io, mut ao) = quick();
    let mut s = Study::init(&path, &data, &io).unwrap();
    let start = s.current().stats;
    match s.add(faster_drive(), &ao) {
        Err(StudyError::ErrorRises {
            before_pct,
            after_pct,
            ..
        }) => {
            assert_eq!(before_pct, 100.0 * start.mare);
            assert!(after_pct > before_pct);
        }
        other => panic!("{other:?}"),
    }
    assert!(s.steps().is_empty());
    assert!(Study::open(&path).unwrap().steps().is_empty());
    ao.force = true;
    let step = s.add(faster_drive(), &ao).unwrap();
    assert!(step.forced && step.after.stats.mare > step.before.mare);
    assert_eq!(Study::open(&path).unwrap().steps().len(), 1);
}

#[test]
fn a_newer_schema_says_so() {
    let e = StudyFile::parse("schema = 99\n", std::path::Path::new("s.toml")).unwrap_err();
    assert!(e.to_string().contains("schema 99"), "{e}");
    let e =
        StudyFile::parse("schema = 1\nbogus = 3\n", std::path::Path::new("s.toml")).unwrap_err();
    assert!(matches!(e, StudyError::Format { .. }), "{e}");
}

#[test]
fn applied_to_its_own_data_the_study_reads_its_own_numbers() {
    let (_dir, data, path) = setup();
    let (io, ao) = quick();
    let mut s = Study::init(&path, &data, &io).unwrap();
    s.add(catalogue("backflow"), &ao).unwrap();
    let app = s.apply_to(s.dataset()).unwrap();
    assert_eq!(app.start.stats.mare, s.file().start.stats.mare);
    assert_eq!(app.steps[0].after.stats.mare, s.steps()[0].after.stats.mare);
    assert_eq!(app.steps[0].after.cases, s.steps()[0].after.cases);
}
