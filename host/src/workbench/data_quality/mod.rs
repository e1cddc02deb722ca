//! What the data say about themselves before any law is located: runs
//! that are bad, intervals stated too narrow. `diagnose` states these
//! first, sets the bad runs aside and judges what it locates on the
//! intervals this module trusts.
//!
//! Order: the intervals first ([`intervals`]), judged without the runs the
//! generalized ESD puts beyond their limits ([`outliers`]); then the bad
//! runs ([`bad_runs`]: named only when without them the model fits the
//! rest to the noise), on the widened intervals when those were widened.
//! Each test's false-alarm rate is stated in its module (1 % per dataset).
//! Bad runs are then weighed against the laws the search finds, by one
//! criterion ([`weighed`]): runs that a law explains with their neighbours
//! are physics, and are not stated as bad.

pub mod bad_runs;
pub mod intervals;
pub mod outliers;
pub(crate) mod unfit_case;
pub mod weighed;

use crate::data::Dataset;
use crate::model::{Model, ModelError};
use crate::workbench::robust::observations;
pub use bad_runs::{BadRun, BadRuns};
pub use intervals::IntervalFinding;
use serde::Serialize;

/// The data-quality findings of one model on one dataset.
#[derive(Debug, Clone, Default, Serialize)]
pub struct DataQuality {
    /// Intervals that look too narrow (`null` when they look right).
    pub intervals: Option<IntervalFinding>,
    /// Runs that stand out (`null` when none does, or when a law
    /// explains them: [`Self::explained_runs`]).
    pub bad_runs: Option<BadRuns>,
    /// Runs the bad-run rule named under the starting model that a law
    /// explains with the other cases by the one criterion ([`weighed`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub explained_runs: Option<BadRuns>,
    /// The two keys, when runs were weighed against a law at the floor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weighed: Option<weighed::Weighed>,
}

impl DataQuality {
    /// The sentences to print before anything is located, in order.
    pub fn sentences(&self) -> Vec<String> {
        let mut out: Vec<String> = self.intervals.iter().map(|i| i.sentence()).collect();
        out.extend(self.bad_runs.iter().map(|b| b.sentence()));
        if let (Some(runs), Some(w)) = (&self.explained_runs, &self.weighed) {
            out.push(w.law_sentence(runs));
        }
        out
    }

    /// Bad runs on two cases or more are named and no intervals account for
    /// the excess: the runs are then weighed against the laws ([`weighed`]).
    pub fn runs_to_weigh(&self) -> bool {
        let intervals = self.intervals.as_ref().is_some_and(|i| i.explains_all());
        !intervals && self.bad_runs.as_ref().is_some_and(|b| b.n_cases() >= 2)
    }

    /// Weigh the named runs against the physics verdict `v`; when the law
    /// wins, the runs are moved to [`Self::explained_runs`] and `true` is
    /// returned.
    pub fn weigh(
        &mut self,
        v: &crate::workbench::diagnosis::Verdict,
        n: usize,
        charges: (f64, f64),
    ) -> bool {
        let Some(runs) = &self.bad_runs else {
            return false;
        };
        let keys = weighed::runs_key(runs, n).zip(weighed::laws_key(v, charges.0, charges.1));
        let Some((runs_key, laws_key)) = keys else {
            return false;
        };
        let w = weighed::Weighed { runs_key, laws_key };
        self.weighed = Some(w);
        if w.runs_win() {
            return false;
        }
        self.explained_runs = self.bad_runs.take();
        true
    }

    /// Nothing is left for a law: the bad runs, or the widened intervals,
    /// account for the whole excess.
    pub fn explains_all(&self) -> bool {
        self.bad_runs.is_some() || self.intervals.as_ref().is_some_and(|i| i.explains_all())
    }
}

/// Assess `data` under `model` (module docs); returns the findings and the
/// dataset the search should read: the intervals widened on the cases
/// named, when they are.
pub fn assess(
    model: &Model,
    data: &Dataset,
    level: f64,
) -> Result<(DataQuality, Option<Dataset>), ModelError> {
    let obs = observations(model, data)?;
    // The intervals are judged without the runs the ESD puts beyond their
    // limits: a few bad runs must not read as intervals too narrow.
    let beyond = outliers::esd(&obs, data, outliers::FALSE_ALARM);
    let rest: Vec<_> = obs
        .iter()
        .filter(|o| {
            !beyond
                .iter()
                .any(|j| j.obs.case == o.case && j.obs.quantity == o.quantity)
        })
        .copied()
        .collect();
    let Some(found) = intervals::calibrate(&rest, data, level) else {
        let q = DataQuality {
            intervals: None,
            bad_runs: bad_runs::bad_runs_of(&obs, data, level),
            ..DataQuality::default()
        };
        return Ok((q, None));
    };
    let widened = widen(data, &found);
    let bad = bad_runs::bad_runs(model, &widened, level)?;
    let q = DataQuality {
        intervals: Some(found),
        bad_runs: bad,
        ..DataQuality::default()
    };
    Ok((q, Some(widened)))
}

/// `data` with the intervals of the finding's cases widened by its factor.
pub fn widen(data: &Dataset, found: &IntervalFinding) -> Dataset {
    let mut out = data.clone();
    for c in &mut out.cases {
        if found.cases.contains(&c.id) {
            for m in [&mut c.u_mm_s, &mut c.omega_body_hz].into_iter().flatten() {
                m.ci_half_width *= found.factor;
            }
        }
    }
    out
}

/// Put the data-quality sentences in front of a verdict's `note`: they are
/// read before anything located.
pub fn say_first(quality: &DataQuality, note: &mut String) {
    let first = quality.sentences();
    if !first.is_empty() {
        *note = format!("{}. {note}", first.join(". "));
    }
}
