//! What a dataset that needs no effect gets: no step and nothing located
//! on many null seeds, and a bad run named as one case rather than read as
//! an effect (src/workbench/diagnose.rs, discovery/screen.rs).

use crate::fixtures;

use fixtures::diagnosed::{run, SEED};
use fixtures::truths;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, VerdictKind};
use swimbot::workbench::synth::{generate, rich_design, SynthSettings};

#[test]
fn the_null_control_needs_nothing_and_locates_nothing() {
    let (d, _data) = run(Model::base());
    assert_eq!(
        d.verdict.kind,
        VerdictKind::NoneNeeded,
        "{}",
        d.verdict.note
    );
    assert!(d.verdict.located.is_empty());
    assert_eq!(d.verdict.effect, None);
}

/// A null never gains a step: base-only data on twenty seeds of the
/// paper's design and four of the rich design.
#[test]
fn a_null_dataset_gains_no_step_on_many_seeds() {
    let paper = swimbot::data::paper();
    let rich = rich_design(&paper);
    let designs = (300..320)
        .map(|s| (s, &paper))
        .chain((320..324).map(|s| (s, &rich)));
    for (seed, design) in designs {
        let settings = SynthSettings {
            seed,
            ..Default::default()
        };
        let data = generate(&Model::base(), design, settings).unwrap();
        let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
        let v = &d.verdict;
        assert!(v.steps.is_empty(), "seed {seed}: {}", v.note);
        assert!(v.located.is_empty(), "seed {seed}: {}", v.note);
    }
}

/// One bad run (a case's U moved by 8 standard errors) on null data of the
/// paper's design: the case is named, and no effect is needed. (On the
/// paper's 12 quantities such a run lifts the chi-square above the floor;
/// on the 84 of the rich design it usually does not, and then the data
/// need nothing anyway: docs/discovery.md.)
#[test]
fn one_bad_run_is_named_and_needs_no_effect() {
    let settings = SynthSettings {
        seed: SEED,
        ..Default::default()
    };
    let mut data = generate(&Model::base(), &swimbot::data::paper(), settings).unwrap();
    let id = truths::spoil_one(&mut data, 2, 8.0);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert_eq!(v.kind, VerdictKind::NoneNeeded, "{}", v.note);
    assert_eq!(
        d.data_quality.bad_runs.as_ref().map(|l| l
            .runs
            .iter()
            .map(|r| r.case.as_str())
            .collect::<Vec<_>>()),
        Some(vec![id.as_str()]),
        "{}",
        v.note
    );
    assert!(
        v.note.contains("one run stands out") && v.note.contains(&id),
        "{}",
        v.note
    );
    assert!(v.located.is_empty() && v.steps.is_empty());
}
