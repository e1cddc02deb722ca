//! Which calibration a new step keeps: the earlier steps held at their
//! values, or every step refitted jointly with the new one.
//!
//! Holding the earlier steps makes the order of `add` decide the physics:
//! an effect added first absorbs what a later one would explain (a body
//! drag factor fitted without the closed channel's backflow takes the
//! backflow in), and the later effect then raises the error, or is
//! calibrated to a value that compensates the earlier one's. So `add` fits
//! both ways whenever an earlier step has a free parameter, and keeps the
//! joint refit when
//!
//! 1. the held fit makes the error (MARE) rise and the joint one gives a
//!    lower error than it: the earlier values were standing in for the
//!    new effect (when the joint one raises the error too, the step is
//!    refused with both numbers, and `--force` records the better); or
//! 2. the joint refit is clearly better by the F test for nested models at
//!    the 5 % level, `F = (chi2_held - chi2_joint) / dk / (chi2_joint /
//!    (n - k_joint))`, with `dk` the parameters the joint refit frees in
//!    addition; the chi-square drop is measured against the scatter the
//!    joint model leaves (its reduced chi-square), not against the error
//!    bars alone, so that a model that misses the data everywhere (reduced
//!    chi-square in the hundreds) does not call every refit significant;
//!    and the joint refit needed no parameter fixed for want of
//!    information and left none on a bound (a refit that only slides an
//!    earlier parameter to its bound, or along a combination the data
//!    cannot fix, is not a better physics).
//!
//! Otherwise the held fit is kept. Both fits' numbers are recorded with
//! the step, with the reason, so that the choice can be checked.
//!
//! Reference: P. R. Bevington & D. K. Robinson, *Data Reduction and Error
//! Analysis for the Physical Sciences*, 3rd ed. (2003), §11.4, the F test
//! for an additional term.

use super::calibrate::Calibrated;
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::model::ModelError;
use crate::workbench::compare::{carried_free_params, compare};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

/// The significance level of the F test that keeps a joint refit.
pub const F_TEST_LEVEL: f64 = 0.05;

/// One way of calibrating the step, judged on the study's data.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Trial {
    pub mare: f64,
    pub chi2: f64,
    /// Parameters fitted in this calibration.
    pub fitted: usize,
    /// A parameter was fixed because the data could not fix it.
    pub reduced: bool,
    /// A parameter ended on its bound.
    pub at_bound: bool,
}

/// Both calibrations of a step and which one it keeps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefitChoice {
    /// `held` or `joint`.
    pub kept: String,
    /// Why, in words.
    pub reason: String,
    pub held: Trial,
    pub joint: Trial,
    /// The F statistic of the joint refit against the held fit, and its
    /// p-value (absent when the test has no degrees of freedom).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub f: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p: Option<f64>,
}

impl Trial {
    pub fn of(c: &Calibrated, data: &Dataset) -> Result<Trial, ModelError> {
        let cmp = compare(&c.model, data, carried_free_params(&c.model))?;
        Ok(Trial {
            mare: cmp.summary.mare,
            chi2: cmp.summary.chi2,
            fitted: c.fitted.len(),
            reduced: c.reduced,
            at_bound: c.params.iter().chain(&c.refitted).any(|p| p.at_bound),
        })
    }
}

/// Choose between the held and the joint calibration (module docs);
/// `mare_before` is the model's error before the step, `n` the measured
/// quantities. Returns whether the joint one is kept and the record.
pub fn choose(held: Trial, joint: Trial, mare_before: f64, n: usize) -> (bool, RefitChoice) {
    let (f, p) = f_test(held, joint, n).unzip();
    let held_rises = held.mare > mare_before;
    let joint_rises = joint.mare > mare_before;
    let clean = !joint.reduced && !joint.at_bound;
    let pct = |v: f64| format!("{:.2} %", 100.0 * v);
    let (keep_joint, reason) = if held_rises && joint.mare < held.mare {
        (
            true,
            format!(
                "with the earlier steps held the error rises (MARE {} -> {}); refitted jointly it is {}: the earlier values were standing in for this effect",
                pct(mare_before),
                pct(held.mare),
                pct(joint.mare)
            ),
        )
    } else if !joint_rises && clean && p.is_some_and(|p| p < F_TEST_LEVEL) {
        (
            true,
            format!(
                "the joint refit is clearly better: chi-square {} -> {}, F = {:.3}, p = {:.2e} < {F_TEST_LEVEL} (MARE {} held, {} joint)",
                fmt_sig(held.chi2, 4),
                fmt_sig(joint.chi2, 4),
                f.unwrap_or(f64::NAN),
                p.unwrap_or(f64::NAN),
                pct(held.mare),
                pct(joint.mare)
            ),
        )
    } else {
        let why = if joint.reduced {
            "jointly, the data cannot fix every parameter".to_string()
        } else if joint.at_bound {
            "jointly, a parameter ends on its bound".to_string()
        } else {
            match (f, p) {
                (Some(f), Some(p)) => format!("F = {f:.3}, p = {p:.2} >= {F_TEST_LEVEL}"),
                _ => "the data leave no degree of freedom to test it".into(),
            }
        };
        (
            false,
            format!(
                "a joint refit of every step was tried and is not clearly better ({why}; MARE {} held, {} joint; chi-square {} held, {} joint)",
                pct(held.mare),
                pct(joint.mare),
                fmt_sig(held.chi2, 4),
                fmt_sig(joint.chi2, 4)
            ),
        )
    };
    let choice = RefitChoice {
        kept: if keep_joint { "joint" } else { "held" }.into(),
        reason,
        held,
        joint,
        f,
        p,
    };
    (keep_joint, choice)
}

/// The F statistic of the nested comparison and its p-value, when the
/// joint refit frees more parameters and leaves degrees of freedom.
fn f_test(held: Trial, joint: Trial, n: usize) -> Option<(f64, f64)> {
    let dk = joint.fitted.checked_sub(held.fitted).filter(|&d| d > 0)?;
    let dof = n.checked_sub(joint.fitted).filter(|&d| d > 0)?;
    let scatter = joint.chi2 / dof as f64;
    if !(scatter > 0.0 && scatter.is_finite()) {
        return None;
    }
    let f = ((held.chi2 - joint.chi2) / dk as f64 / scatter).max(0.0);
    let dist = FisherSnedecor::new(dk as f64, dof as f64).ok()?;
    Some((f, dist.sf(f)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trial(mare: f64, chi2: f64, fitted: usize) -> Trial {
        Trial {
            mare,
            chi2,
            fitted,
            reduced: false,
            at_bound: false,
        }
    }

    #[test]
    fn a_held_fit_that_raises_the_error_gives_way_to_a_joint_one_that_lowers_it() {
        let (joint, c) = choose(trial(0.22, 8e4, 0), trial(0.008, 100.0, 2), 0.0081, 24);
        assert!(joint, "{}", c.reason);
        assert_eq!(c.kept, "joint");
    }

    #[test]
    fn the_f_test_keeps_a_joint_refit_only_when_the_drop_beats_the_scatter_left() {
        // chi-square 105 -> 47 with two more parameters and 21 degrees of
        // freedom: F = 29 / 2.24 = 12.9, p ~ 2e-4
        let (joint, c) = choose(trial(0.0081, 105.0, 1), trial(0.007, 47.0, 3), 0.0086, 24);
        assert!(joint, "{}", c.reason);
        assert!(c.p.unwrap() < 1e-3, "{:?}", c.p);
        // the same drop on a model that misses everywhere (reduced
        // chi-square ~ 2e4) is noise
        let (joint, c) = choose(trial(0.30, 4.0e5, 1), trial(0.29, 3.99e5, 3), 0.31, 24);
        assert!(!joint, "{}", c.reason);
        assert!(c.p.unwrap() > 0.5);
    }

    #[test]
    fn a_joint_refit_on_a_bound_is_not_kept_for_a_smaller_chi_square() {
        let mut j = trial(0.007, 47.0, 3);
        j.at_bound = true;
        let (joint, c) = choose(trial(0.0081, 105.0, 1), j, 0.0086, 24);
        assert!(!joint);
        assert!(c.reason.contains("bound"), "{}", c.reason);
    }

    #[test]
    fn the_f_statistic_matches_its_definition() {
        let (f, p) = f_test(trial(0.0, 30.0, 1), trial(0.0, 20.0, 2), 12).unwrap();
        // (30 - 20) / 1 / (20 / 10) = 5
        assert!((f - 5.0).abs() < 1e-12);
        // F(1, 10) upper tail at 5: 0.0494 (tables)
        assert!((p - 0.0494).abs() < 5e-4, "{p}");
    }
}
