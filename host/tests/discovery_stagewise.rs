//! Two missing effects at once: the stagewise search takes one step on top
//! of the last, and backfitting re-locates each step on top of the others
//! (src/workbench/{stagewise,stagewise_backfit}.rs).

use crate::fixtures;

use fixtures::diagnosed::{
    assert_no_repeats, assert_pair_located_at_floor, base_with, data, diagnose_drawn_pair, placed,
    run, BODY_FEATURES,
};
use fixtures::truths;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};

/// Two out-of-catalogue truths at different places (body drag, tail
/// viscosity): the stagewise search takes several steps, each fitted on top
/// of the ones before it (`on_top_of` grows by one effect per step, MARE
/// falls), and the tail's shear-thinning law is among them at its place and
/// feature. (The body law is often taken first by the catalogue's
/// body-correction and its remainder misplaced: docs/discovery.md reports
/// the counts; this test asserts what holds.)
#[test]
fn two_missing_effects_at_once_are_found_in_steps_each_on_top_of_the_last() {
    let truth = base_with(&truths::BODY).with_effect(truths::instance(&truths::SHEAR));
    let (d, _data) = run(truth);
    let v = &d.verdict;
    assert!(v.steps.len() >= 2, "{}", v.note);
    for w in v.steps.windows(2) {
        assert_eq!(w[1].on_top_of.len(), w[0].on_top_of.len() + 1, "{}", v.note);
        assert!(w[1].mare < w[0].mare, "{}", v.note);
    }
    assert!(
        v.located
            .iter()
            .any(|l| l.place == "tail.viscosity" && l.feature.as_deref() == Some("shear_rate")),
        "{}",
        v.note
    );
    // Each located law's own `on_top_of` is its step's.
    let laws: Vec<_> = v.steps.iter().filter(|s| s.kind == "located").collect();
    for (l, s) in v.located.iter().zip(laws) {
        assert_eq!(l.on_top_of, s.on_top_of);
    }
}

/// Two out-of-catalogue effects at once, both drawn (constants and design:
/// tests/fixtures/drawn.rs, seed 31). The catalogue's body-correction
/// takes most of the body law first; backfitting re-locates each step on
/// top of the others, so both laws end up at their places and the set
/// reaches the floor without it.
#[test]
fn two_drawn_effects_at_once_are_both_placed_after_backfitting() {
    let seed = 31;
    let d = diagnose_drawn_pair(seed);
    assert_pair_located_at_floor(&d.verdict);
}

/// Backfitting above the floor, on a synth seed (139)
/// outside the recovery study's: the catalogue's body-correction takes most
/// of the fixed body law first and the rest lands on `tail.c_n` in a body
/// gap; no one-for-one exchange reaches the floor, so backfitting that took
/// only a set at the floor would keep that. A clearly better set above the
/// floor is taken, and the
/// body law is re-located on the body.
#[test]
fn backfitting_above_the_floor_moves_the_body_law_back_to_the_body() {
    let truth = base_with(&truths::BODY).with_effect(truths::instance(&truths::SHEAR));
    let data = data(&truth, 139);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert!(placed(v, "body.D_x", BODY_FEATURES), "{}", v.note);
    assert!(placed(v, "tail.viscosity", &["shear_rate"]), "{}", v.note);
    assert!(
        v.located.iter().all(|l| l.place != "tail.c_n"),
        "{}",
        v.note
    );
    assert_no_repeats(v);
}

/// Backfitting tries the best law at every other place: on seed
/// 203 of the drawn two-effect truth the path took the catalogue's
/// backflow and the shear-rate law (identified, at the floor), and the
/// single best proposal on top of the shear-rate law was never at the
/// body. Refitted jointly, the body law at `body.D_x` beats backflow by
/// more than the clear margin at the floor, and is exchanged for it.
#[test]
fn backfitting_tries_the_best_law_at_each_other_place() {
    let seed = 203;
    let d = diagnose_drawn_pair(seed);
    assert_pair_located_at_floor(&d.verdict);
}
