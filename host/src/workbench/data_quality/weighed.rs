//! Bad runs against laws: two explanations of the same residuals, judged
//! by one criterion, the key the set search ranks by
//! ([`crate::workbench::search`]): the AICc of the chi-square plus a
//! look-elsewhere charge `2 ln(choices)` for each term chosen among many.
//!
//! - **A law** pays its parameters and `2 ln(laws screened)` (a catalogue
//!   effect `2 ln(effects tried)`), as in the search.
//! - **A bad run** frees each quantity it names: its residual is absorbed
//!   exactly, one parameter per quantity, and `2 ln(n)` for the choice of
//!   which of the `n` quantities.
//!
//! A physical effect that acts at one end of a feature (the fastest tails,
//! the thinnest oils, the tails nearest the wall) makes those cases stand
//! out under a model without it, and the bad-run rule
//! ([`super::bad_runs`]) names them. A law over that feature explains the
//! named cases together with their neighbours for a few parameters; the
//! runs must each be paid for. So the runs are stated only when their key
//! is below that of the set the search found at the noise floor; else the
//! law is stated and the runs are said to be explained by it.
//!
//! Only runs on two cases or more are weighed. The generalized ESD that
//! names them assumes a few unrelated contaminated values; one run is what
//! it is calibrated for (1 % per dataset on a right model), and on a null
//! of the paper's six cases a constant load can fit one run and the
//! noise's common sign better than freeing it (a null seed of
//! `host/tests/discovery_nulls.rs` did so by 20 in the key): weighing it
//! would trade the rule's calibrated false alarm for an uncalibrated law.
//! Several named runs are a pattern the ESD's assumption does not hold
//! for, and the one that a missing effect makes.
//!
//! Reference: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), sec. 2.4 (AICc) and sec. 4.3
//! (one criterion for every rival model).

use super::bad_runs::BadRuns;
use crate::workbench::diagnosis::{Verdict, VerdictKind};
use crate::workbench::score::aicc;
use serde::Serialize;

/// The two keys, lower is better; `runs_win` when the runs' key is lower.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Weighed {
    /// The starting model with the named quantities freed.
    pub runs_key: f64,
    /// The set the search found at the noise floor.
    pub laws_key: f64,
}

impl Weighed {
    pub fn runs_win(&self) -> bool {
        self.runs_key <= self.laws_key
    }

    /// One sentence for the note, when the law wins.
    pub fn law_sentence(&self, runs: &BadRuns) -> String {
        let mut cases: Vec<&str> = runs.runs.iter().map(|r| r.case.as_str()).collect();
        cases.dedup();
        format!(
            "{} stood out under the starting model, but a law explains {} with the other cases for fewer parameters than blaming {} (key {} against {} for the runs): physics, not bad runs",
            cases.join(", "),
            if cases.len() == 1 { "it" } else { "them" },
            if cases.len() == 1 { "the run" } else { "the runs" },
            crate::format::fmt_sig(self.laws_key, 4),
            crate::format::fmt_sig(self.runs_key, 4),
        )
    }
}

/// The runs' key: the chi-square without the named quantities, one
/// parameter and one charge `2 ln(n)` per quantity (module docs).
pub fn runs_key(runs: &BadRuns, n: usize) -> Option<f64> {
    let m = runs.runs.len();
    let without = runs.chi2_reduced_without * (n.saturating_sub(m)) as f64;
    aicc(without, n, m).map(|a| a + m as f64 * 2.0 * (n.max(1) as f64).ln())
}

/// The key of the set a physics verdict states, when it reaches the noise
/// floor: its last step's AICc plus each member's charge.
pub fn laws_key(v: &Verdict, law_charge: f64, catalogue_charge: f64) -> Option<f64> {
    if matches!(v.kind, VerdictKind::NoneNeeded | VerdictKind::Unexplained) {
        return None;
    }
    let last = v.steps.last().filter(|s| s.at_noise_floor)?;
    let charges: f64 = v
        .steps
        .iter()
        .map(|s| match s.kind {
            "catalogue" => catalogue_charge,
            _ => law_charge,
        })
        .sum();
    last.aicc.map(|a| a + charges)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workbench::data_quality::bad_runs::BadRun;

    fn runs(m: usize, without_reduced: f64) -> BadRuns {
        BadRuns {
            runs: (0..m)
                .map(|i| BadRun {
                    case: format!("c{i}"),
                    quantity: "U",
                    z: 6.0,
                    z_judged: 6.0,
                    pooled: false,
                    threshold: 4.6,
                })
                .collect(),
            rule: "esd",
            false_alarm: 0.01,
            chi2_reduced_with: 3.0,
            chi2_reduced_without: without_reduced,
            floor_reduced_without: 1.3,
        }
    }

    #[test]
    fn each_freed_quantity_costs_a_parameter_and_its_choice() {
        let n = 72;
        let one = runs_key(&runs(1, 1.0), n).unwrap();
        let four = runs_key(&runs(4, 1.0), n).unwrap();
        // chi-square 71 and 68; 2 + 2 ln 72 = 10.55 per run, and AICc's
        // small-sample term.
        assert!((one - (71.0 + 2.0 + 4.0 / 70.0 + 2.0 * 72f64.ln())).abs() < 1e-9);
        assert!(four - one > 3.0 * (2.0 + 2.0 * 72f64.ln()) - 3.0 - 1e-9);
    }

    #[test]
    fn the_lower_key_wins_and_a_tie_goes_to_the_runs() {
        let w = Weighed {
            runs_key: 80.0,
            laws_key: 80.0,
        };
        assert!(w.runs_win());
        let w = Weighed {
            laws_key: 79.0,
            ..w
        };
        assert!(!w.runs_win());
        assert!(w.law_sentence(&runs(2, 1.0)).contains("c0, c1"));
    }
}
