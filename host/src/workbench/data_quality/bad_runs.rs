//! The bad runs a model names: the quantities the generalized ESD
//! ([`super::outliers`]) puts beyond their limits, each named with its
//! case and quantity, when without them the model fits every other
//! quantity to the noise.
//!
//! **Runs are named** for a model when
//! (a) the generalized ESD puts them beyond their limits at a false-alarm
//! rate of 1 % per dataset, or
//! (a') the data are above the noise floor and one quantity's residual is
//! beyond the two-sided 1 % Student-t quantile of its own trials
//! (`t_{0.995, nu}` = 4.60 for five trials): the excess is this run's;
//! and in either case
//! (b) without those quantities the chi-square is at or below the noise
//! floor of the quantities left (the same quantile,
//! [`crate::workbench::noise::chi2_noise_floor`]).
//! Then no effect is needed for the rest: the runs are what to check or
//! re-measure, and no law is located to explain them. When (b) fails the
//! model misses more than a few runs and nothing is named: a bad run is
//! then not told from the largest residuals of a missing effect.

use super::outliers::{esd, Judged, FALSE_ALARM};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::model::{Model, ModelError};
use crate::workbench::noise::chi2_noise_floor;
use crate::workbench::robust::{observations, Obs};
use serde::Serialize;

/// One bad run: a case's quantity beyond its limit.
#[derive(Debug, Clone, Serialize)]
pub struct BadRun {
    pub case: String,
    /// `U` or `Omega_b`.
    pub quantity: &'static str,
    /// Its residual in the case's own standard errors.
    pub z: f64,
    /// The same residual in the standard errors it is judged in: pooled
    /// over the cases when they share one trial scatter, else its own.
    pub z_judged: f64,
    /// Whether `z_judged` is over a pooled standard error.
    pub pooled: bool,
    /// The limit `|z_judged|` exceeds.
    pub threshold: f64,
}

/// The runs a model names (module docs), with the numbers behind them.
#[derive(Debug, Clone, Serialize)]
pub struct BadRuns {
    pub runs: Vec<BadRun>,
    /// `esd`: beyond the generalized ESD's limits; `excess`: the data are
    /// above the noise floor only by this run (module docs, (a')).
    pub rule: &'static str,
    /// The false-alarm rate per dataset of the rule on a right model:
    /// the ESD's (1 %), or the floor's (5 %) for `excess`.
    pub false_alarm: f64,
    pub chi2_reduced_with: f64,
    pub chi2_reduced_without: f64,
    /// The noise floor (reduced) of the quantities without the runs.
    pub floor_reduced_without: f64,
}

impl BadRuns {
    /// How many cases the runs are on.
    pub fn n_cases(&self) -> usize {
        let mut cases: Vec<&str> = self.runs.iter().map(|r| r.case.as_str()).collect();
        cases.sort_unstable();
        cases.dedup();
        cases.len()
    }

    /// Whether `case` holds one of the runs.
    pub fn names_case(&self, case: &str) -> bool {
        self.runs.iter().any(|r| r.case == case)
    }

    /// One sentence for the terminal and the audit.
    pub fn sentence(&self) -> String {
        let runs: Vec<String> = self.runs.iter().map(|r| self.run_words(r)).collect();
        let (what, them) = if self.runs.len() == 1 {
            ("one run stands out", "it")
        } else {
            ("several runs stand out", "them")
        };
        format!(
            "{what}: {}; without {them} the model fits the other quantities to the noise (reduced chi-square {} -> {}, floor {}): check {} record or re-measure",
            runs.join("; "),
            fmt_sig(self.chi2_reduced_with, 3),
            fmt_sig(self.chi2_reduced_without, 3),
            fmt_sig(self.floor_reduced_without, 3),
            if self.runs.len() == 1 { "its" } else { "their" }
        )
    }

    fn run_words(&self, r: &BadRun) -> String {
        let limit = |z: String| {
            format!(
                "{z}, beyond the limit {:.2} (a right model has a run named somewhere in {} % of datasets)",
                r.threshold,
                100.0 * self.false_alarm
            )
        };
        let why = match (self.rule, r.pooled) {
            ("excess", _) => format!(
                "{:.1} of its own standard errors off, beyond the 1 % Student-t quantile {:.2} of its trials, and the data are above the noise floor by this run alone",
                r.z, r.threshold
            ),
            (_, true) => limit(format!(
                "{:.1} standard errors of the trial scatter the cases share off ({:.1} of its own)",
                r.z_judged, r.z
            )),
            _ => limit(format!("{:.1} of its own standard errors off", r.z)),
        };
        format!("{}'s {} is {why}", r.case, r.quantity)
    }
}

/// The bad runs under `model`, if any; `level` is the noise floor's
/// quantile (0.95 in every command).
pub fn bad_runs(model: &Model, data: &Dataset, level: f64) -> Result<Option<BadRuns>, ModelError> {
    let obs = observations(model, data)?;
    Ok(bad_runs_of(&obs, data, level))
}

/// [`bad_runs`] from residuals already computed.
pub fn bad_runs_of(obs: &[Obs], data: &Dataset, level: f64) -> Option<BadRuns> {
    let n = obs.len();
    if n < 3 || data.cases.len() < 3 {
        return None;
    }
    let chi2: f64 = obs.iter().map(|o| o.z * o.z).sum();
    let named = esd(obs, data, FALSE_ALARM);
    let (named, rule, false_alarm) = if named.is_empty() {
        (
            vec![excess_run(obs, chi2, data, level)?],
            "excess",
            1.0 - level,
        )
    } else {
        (named, "esd", FALSE_ALARM)
    };
    let is_named = |o: &Obs| {
        named
            .iter()
            .any(|j| j.obs.case == o.case && j.obs.quantity == o.quantity)
    };
    let rest: Vec<&Obs> = obs.iter().filter(|o| !is_named(o)).collect();
    let without: f64 = rest.iter().map(|o| o.z * o.z).sum();
    let dofs: Vec<f64> = rest
        .iter()
        .map(|o| f64::from(o.trials.max(2) - 1))
        .collect();
    let floor_rest = chi2_noise_floor(&dofs, 0, level)?;
    (without <= floor_rest).then(|| BadRuns {
        runs: named
            .iter()
            .map(|j| BadRun {
                case: data.cases[j.obs.case].id.clone(),
                quantity: j.obs.quantity.label(),
                z: j.obs.z,
                z_judged: j.z,
                pooled: j.pooled,
                threshold: j.limit,
            })
            .collect(),
        rule,
        false_alarm,
        chi2_reduced_with: chi2 / n as f64,
        chi2_reduced_without: without / rest.len().max(1) as f64,
        floor_reduced_without: floor_rest / rest.len().max(1) as f64,
    })
}

/// Rule (a'): the data are above the floor and the largest residual is
/// beyond the two-sided 1 % Student-t quantile of its own trials.
fn excess_run(obs: &[Obs], chi2: f64, data: &Dataset, level: f64) -> Option<Judged> {
    let big = obs.iter().max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))?;
    let threshold = crate::stats::student_t_quantile(0.99, big.trials);
    let dofs = crate::workbench::noise::error_dofs(data);
    if big.z.abs() <= threshold || chi2 <= chi2_noise_floor(&dofs, 0, level)? {
        return None;
    }
    Some(Judged {
        obs: *big,
        z: big.z,
        limit: threshold,
        pooled: false,
        nu: f64::from(big.trials.max(2) - 1),
    })
}
