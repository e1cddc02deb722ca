//! The audit's check for a case no candidate fits
//! ([`crate::workbench::audit_influence`], module docs,
//! **Outliers**): a case that every candidate fitting the others to the
//! noise misses by more than the one-bad-run limit; and the noise floors
//! and limits it needs, each drawn once for every case left out.
//!
//! The floor is the 95 % quantile of a perfect model's chi-square over the
//! quantities left ([`crate::workbench::noise::chi2_noise_floor`], a Monte Carlo of
//! 20 000 draws); the limit is the one-bad-run test's
//! ([`super::outliers::limit`], a false-alarm rate of 1 % per dataset).

use crate::data::Case;
use crate::data::Dataset;
use crate::workbench::audit_influence::Finding;
use crate::workbench::compare::case_residuals;
use crate::workbench::fit::FitResult;
use crate::workbench::noise::{chi2_noise_floor, error_dofs};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap, HashSet};

/// The degrees of freedom of the quantities' standard errors as a
/// histogram (bits of the dof -> count).
type DofHistogram = Vec<(u64, usize)>;

/// The noise floors the outlier check needs, and the Student-t limits: the
/// floor is a Monte Carlo quantile over every quantity (20 000 draws each)
/// and depends only on the histogram of the degrees of freedom and `k`, so
/// each distinct one is drawn once (in parallel), not once per case; with
/// equal trials everywhere leaving any case out gives the same histogram.
pub(crate) struct NoiseFloors {
    floors: HashMap<(DofHistogram, usize), Option<f64>>,
    pub(crate) limits: HashMap<u32, f64>,
}

impl NoiseFloors {
    /// For every case left out and every `k` of `ks`.
    pub(crate) fn new(data: &Dataset, ks: &[usize], n_all: usize) -> NoiseFloors {
        let all = error_dofs(data);
        let keys: HashSet<(DofHistogram, usize)> = data
            .cases
            .iter()
            .flat_map(|c| {
                let own = error_dofs_of(c);
                let h = histogram(&all, &own);
                ks.iter().map(move |&k| (h.clone(), k))
            })
            .collect();
        let dofs_of = |h: &DofHistogram| -> Vec<f64> {
            h.iter()
                .flat_map(|&(d, n)| std::iter::repeat_n(f64::from_bits(d), n))
                .collect()
        };
        // The draws depend on the histogram only (`k` scales the quantile):
        // one per histogram, in parallel, remembered by the noise module;
        // drawing per `(histogram, k)` in parallel drew the same one for
        // every `k` at once.
        let hists: HashSet<&DofHistogram> = keys.iter().map(|(h, _)| h).collect();
        hists.into_par_iter().for_each(|h| {
            let _ = chi2_noise_floor(&dofs_of(h), 0, 0.95);
        });
        let floors = keys
            .iter()
            .map(|(h, k)| ((h.clone(), *k), chi2_noise_floor(&dofs_of(h), *k, 0.95)))
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
    pub(crate) fn floor(&self, all: &[f64], case: &crate::data::Case, k: usize) -> Option<f64> {
        let h = histogram(all, &error_dofs_of(case));
        self.floors.get(&(h, k)).copied().flatten()
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

/// The histogram of `all` without the values of `left_out`.
fn histogram(all: &[f64], left_out: &[f64]) -> DofHistogram {
    let mut hist: BTreeMap<u64, usize> = BTreeMap::new();
    for d in all {
        *hist.entry(d.to_bits()).or_default() += 1;
    }
    for d in left_out {
        if let Some(n) = hist.get_mut(&d.to_bits()) {
            *n -= 1;
        }
    }
    hist.into_iter().filter(|(_, n)| *n > 0).collect()
}

/// The outlier check of one case against the candidates fitted without it.
pub(crate) fn outlier(
    case: &Case,
    fitted: &[(&str, &FitResult)],
    all_dofs: &[f64],
    floors: &NoiseFloors,
) -> Option<Finding> {
    let at_floor: Vec<&(&str, &FitResult)> = fitted
        .iter()
        .filter(|(_, fit)| {
            floors
                .floor(all_dofs, case, fit.estimates.len())
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
