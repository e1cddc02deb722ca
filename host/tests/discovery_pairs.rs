//! The pair search of backfitting (workbench/stagewise_backfit/
//! pairs.rs), on the drawn two-effect truth (body drag `D_x (1 + a
//! (D_b/D_ch)^q)` and a shear-thinning tail oil, constants and design drawn
//! per seed: tests/fixtures/drawn.rs). The seed is from the fresh range
//! 301-310 of docs/discovery.md's recovery study, where the path before the
//! pair search stopped above the noise floor.

use crate::fixtures::diagnosed::{diagnose_drawn_pair, placed, BODY_FEATURES};
use swimbot::workbench::diagnose::VerdictKind;

/// Seed 308: the first step was a drive slip in the shear rate that took a
/// share of both effects, then `tail.c_t` in a body ratio; no one-for-one
/// exchange reached the floor from there (verdict `unexplained`). The pair
/// search places the body law and the oil from scratch, refits them
/// jointly and backfits them: both at their places, at the floor.
#[test]
fn a_path_stuck_above_the_floor_is_replaced_by_the_pair_at_the_places() {
    let d = diagnose_drawn_pair(308);
    let v = &d.verdict;
    assert_eq!(v.kind, VerdictKind::Located, "{}", v.note);
    assert!(placed(v, "body.D_x", BODY_FEATURES), "{}", v.note);
    assert!(placed(v, "tail.viscosity", &["shear_rate"]), "{}", v.note);
    assert!(
        v.located.iter().all(|l| l.place != "drive.rate"),
        "{}",
        v.note
    );
    let last = v.steps.last().unwrap();
    assert!(last.at_noise_floor, "{}", v.note);
    assert_eq!(v.steps.len(), 2, "{}", v.note);
}
