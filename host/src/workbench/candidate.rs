//! The catalogue's candidates for `diagnose`: each effect not yet in the
//! model added alone, its free parameters fitted and scored by
//! cross-validated MARE and the AICc of the deviance the fit minimised
//! ([`super::score`]); forward selection of a second one.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; T. Hastie, R. Tibshirani &
//! J. Friedman, *The Elements of Statistical Learning*, 2nd ed. (2009),
//! sec. 7.10 (k-fold cross-validation).

use super::compare::compare;
use super::diagnosis::Candidate;
use super::fit::{fit_with, free_params_of, FitError};
use super::robust::Likelihood;
use super::score::{Deviance, FitScore};
use crate::data::Dataset;
use crate::effects::{Catalogue, EffectRef};
use crate::model::Model;
use rayon::prelude::*;

/// Effects that `diagnose` may propose: entries of `catalogue` not in the
/// model (costly ones only on request).
pub fn candidates(catalogue: &Catalogue, model: &Model, include_costly: bool) -> Vec<EffectRef> {
    catalogue
        .all()
        .into_iter()
        .filter(|e| e.candidate() && (include_costly || !e.costly()))
        .filter(|e| !model.effects.iter().any(|m| m.name() == e.name()))
        .filter(|e| model.can_take(&**e))
        .collect()
}

/// Fit the effects at `added` (indices into `model.effects`) and score them.
pub fn evaluate(
    model: &Model,
    added: &[usize],
    data: &Dataset,
    floor: &dyn Fn(usize) -> Option<f64>,
    lik: Likelihood,
) -> Result<Candidate, FitError> {
    let free = free_params_of(model, added);
    let k = free.len();
    // Multi-start is what makes a fit trustworthy and what makes it slow:
    // above 60 cases run it on a strided subset of about 50, then refine
    // from that optimum on every case.
    let n_cases = data.cases.len();
    let full = if n_cases > 60 && !free.is_empty() {
        let sub: Vec<usize> = (0..n_cases).step_by(n_cases.div_ceil(50)).collect();
        let pre = fit_with(model, data, Some(&sub), &free, true, lik)?;
        fit_with(&pre.model, data, None, &free, false, lik)?
    } else {
        fit_with(model, data, None, &free, true, lik)?
    };
    let cmp = compare(&full.model, data, k)?;
    let cv_mare = if k == 0 {
        cmp.summary.mare
    } else {
        cross_validated_mare(&full.model, data, &free, lik)
    };
    Ok(Candidate {
        effect: added
            .iter()
            .map(|&i| model.effects[i].name())
            .collect::<Vec<_>>()
            .join(" + "),
        params: full.estimates.clone(),
        score: FitScore::of(&cmp.summary, cv_mare, Deviance::of_fit(&full), k, floor(k)),
        non_identifiable: full.non_identifiable.clone(),
        converged: full.converged,
        model: full.model,
    })
}

/// Cross-validated MARE: each case alone (up to ten cases) or ten
/// interleaved folds; each fold refitted warm from the full-data optimum.
pub(crate) fn cross_validated_mare(
    fitted: &Model,
    data: &Dataset,
    free: &[super::fit::FreeParam],
    lik: Likelihood,
) -> f64 {
    let n = data.cases.len();
    let folds = if n <= 10 { n } else { 10 };
    let mut errs = Vec::new();
    for f in 0..folds {
        let train: Vec<usize> = (0..n).filter(|&j| j % folds != f).collect();
        let Ok(fit) = fit_with(fitted, data, Some(&train), free, false, lik) else {
            continue;
        };
        for case in data.cases.iter().skip(f).step_by(folds) {
            if let Ok(p) = fit.model.predict(case) {
                for (_, r) in super::compare::case_residuals(case, &p) {
                    errs.push(r.relative_error().abs());
                }
            }
        }
    }
    if errs.is_empty() {
        f64::NAN
    } else {
        errs.iter().sum::<f64>() / errs.len() as f64
    }
}

pub(crate) fn sort_by_aicc(v: &mut [Candidate]) {
    v.sort_by(|a, b| {
        let key = |c: &Candidate| c.score.aicc.unwrap_or(f64::INFINITY);
        key(a)
            .total_cmp(&key(b))
            .then(a.score.cv_mare.total_cmp(&b.score.cv_mare))
    });
}

/// The best single effect with each other candidate, fitted jointly.
pub fn forward_selection(
    model: &Model,
    data: &Dataset,
    ranking: &[Candidate],
    floor: &(dyn Fn(usize) -> Option<f64> + Sync),
    lik: Likelihood,
) -> Vec<Candidate> {
    let Some(first) = ranking.first() else {
        return Vec::new();
    };
    let base_len = model.effects.len();
    let mut pairs: Vec<Candidate> = ranking[1..]
        .par_iter()
        .filter_map(|second| {
            let mut m = first.model.clone();
            m.effects.push(second.model.effects[base_len].clone());
            evaluate(&m, &[base_len, base_len + 1], data, floor, lik).ok()
        })
        .collect();
    sort_by_aicc(&mut pairs);
    pairs
}
