//! The audit's check for a case no candidate fits
//! ([`crate::workbench::audit::influence`], module docs,
//! **Outliers**): a case that every candidate fitting the others to the
//! noise misses by more than the one-bad-run limit; and the noise floors
//! and limits it needs, for every case left out.
//!
//! The floor is the 95 % quantile of a perfect model's chi-square over the
//! quantities left ([`crate::workbench::noise`], a Monte Carlo whose draws
//! serve every case left out); the limit is the one-bad-run test's
//! ([`super::outliers::limit`], a false-alarm rate of 1 % per dataset).

use crate::data::Case;
use crate::data::Dataset;
use crate::workbench::audit::influence::Finding;
use crate::workbench::compare::case_residuals;
use crate::workbench::fit::FitResult;
use crate::workbench::noise::{error_dofs, LeaveOutDraws};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap, HashSet};

/// A case's quantities as degrees of freedom (bits -> count).
type LeftOut = BTreeMap<u64, usize>;
/// The same, as a key: the counts in order.
type LeftOutKey = Vec<(u64, usize)>;

/// The noise floors the outlier check needs, and the Student-t limits: the
/// floor with each case left out, for every parameter count, from one set
/// of draws over all the quantities ([`LeaveOutDraws`]: with the input
/// uncertainty combined every case has its own degrees of freedom, and one
/// Monte Carlo per case left out grew as the square of the cases).
pub(crate) struct NoiseFloors {
    floors: HashMap<(LeftOutKey, usize), Option<f64>>,
    pub(crate) limits: HashMap<u32, f64>,
}

impl NoiseFloors {
    /// For every case left out and every `k` of `ks`.
    pub(crate) fn new(data: &Dataset, ks: &[usize], n_all: usize) -> NoiseFloors {
        let all = counts(&error_dofs(data));
        let left: HashSet<LeftOutKey> = data
            .cases
            .iter()
            .map(|c| counts(&error_dofs_of(c)).into_iter().collect())
            .collect();
        let mut spare = LeftOut::new();
        for (d, m) in left.iter().flatten() {
            let s = spare.entry(*d).or_default();
            *s = (*s).max(*m);
        }
        let draws = LeaveOutDraws::new(&all, &spare);
        let floors = left
            .par_iter()
            .flat_map_iter(|l| {
                let out: LeftOut = l.iter().copied().collect();
                let draws = &draws;
                ks.iter()
                    .map(move |&k| ((l.clone(), k), draws.floor(&out, k, 0.95)))
            })
            .collect();
        let trials: HashSet<u32> = data
            .cases
            .iter()
            .flat_map(|c| [c.u_mm_s, c.omega_body_hz])
            .flatten()
            .map(|m| m.trials)
            .collect();
        let limits = trials
            .into_par_iter()
            .map(|t| {
                let nu = f64::from(t.max(2) - 1);
                (
                    t,
                    super::outliers::limit(nu, n_all, super::outliers::FALSE_ALARM),
                )
            })
            .collect();
        NoiseFloors { floors, limits }
    }

    /// The floor with `case` left out.
    pub(crate) fn floor(&self, case: &crate::data::Case, k: usize) -> Option<f64> {
        let l: LeftOutKey = counts(&error_dofs_of(case)).into_iter().collect();
        self.floors.get(&(l, k)).copied().flatten()
    }
}

/// One case's part of [`error_dofs`] (the same rule: `trials - 1`, at least 1).
fn error_dofs_of(c: &crate::data::Case) -> Vec<f64> {
    [c.u_mm_s, c.omega_body_hz]
        .into_iter()
        .flatten()
        .map(|m| f64::from(m.trials.max(2) - 1))
        .collect()
}

/// How many of `dofs` have each value (bits of the dof -> count).
fn counts(dofs: &[f64]) -> BTreeMap<u64, usize> {
    let mut hist: BTreeMap<u64, usize> = BTreeMap::new();
    for d in dofs {
        *hist.entry(d.to_bits()).or_default() += 1;
    }
    hist
}

/// The outlier check of one case against the candidates fitted without it.
pub(crate) fn outlier(
    case: &Case,
    fitted: &[(&str, &FitResult)],
    floors: &NoiseFloors,
) -> Option<Finding> {
    let at_floor: Vec<&(&str, &FitResult)> = fitted
        .iter()
        .filter(|(_, fit)| {
            floors
                .floor(case, fit.estimates.len())
                .is_some_and(|f| fit.chi2 <= f)
        })
        .collect();
    if at_floor.is_empty() {
        return None;
    }
    let mut best: Option<(f64, f64, &str, &'static str)> = None;
    for (name, fit) in at_floor {
        let p = fit.model.predict(case).ok()?;
        let (q, r) = case_residuals(case, &p)
            .into_iter()
            .max_by(|a, b| a.1.normalised().abs().total_cmp(&b.1.normalised().abs()))?;
        let m = if q == crate::workbench::compare::Quantity::U {
            case.u_mm_s
        } else {
            case.omega_body_hz
        }?;
        let limit = floors.limits[&m.trials];
        let z = r.normalised().abs();
        if z <= limit {
            return None;
        }
        if best.is_none_or(|b| z < b.0) {
            best = Some((z, limit, name, q.label()));
        }
    }
    let (z, limit, name, quantity) = best?;
    Some(Finding::Outlier {
        case: case.id.clone(),
        best: name.to_string(),
        quantity,
        z,
        limit,
    })
}
