//! The audit's influence and outlier checks, on the measurements with the
//! input uncertainty combined.
//!
//! **Candidates**: the model as given, and the model with each cheap
//! candidate catalogue effect added (free parameters fitted, weighted by
//! the combined standard errors), ranked by AICc
//! (the deviance's AICc, below). The conclusion is the best candidate
//! when it beats the runner-up by at least 4 (Burnham & Anderson's
//! "considerably less support"), otherwise "undecided".
//!
//! **Influence** (leave one case out, every candidate refitted from its
//! full-data fit): a case is flagged when the full data give a clear
//! conclusion and without that case the conclusion changes (another
//! effect, or undecided); when the full data give none and without that
//! case one is clear; or when, with the conclusion unchanged, a fitted
//! parameter moves by more than its full-data 95 % interval (a DFBETA in
//! the parameter's own interval; Cook & Weisberg, *Residuals and Influence
//! in Regression*, 1982, ch. 3).
//!
//! **Outliers**: a case is an outlier when some candidate fitted without it
//! reaches the noise floor on the other cases (chi-square below the 95 %
//! quantile a perfect model shows, [`crate::workbench::noise`]) and every such
//! candidate misses the case by more than the limit of the one-bad-run
//! test ([`crate::workbench::data_quality::outliers::limit`], its own Student-t degrees of freedom,
//! a false-alarm rate of 1 % per dataset) in combined standard errors: the
//! others agree with a model, this case with none.
//! When no candidate fits the others, the case cannot be called an outlier
//! (the model family itself fails) and nothing is flagged for it.
//!
//! Every fit (full data, leave-one-out, the exact re-check) minimises the
//! deviance of the audit's [`Likelihood`] (least squares by default, the
//! Student-t with `--likelihood student-t`), and the AICc is that
//! deviance's: `D + 2k + 2k(k+1)/(n-k-1)`. What is decided is here; how
//! each finding is worded is `super::influence_words`.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; R. D. Cook & S. Weisberg
//! (1982).

use super::loo::{leave_one_out, FullFit, LooMethod};
use super::Flag;
use crate::data::{Case, Dataset};
use crate::effects::{EffectInstance, CATALOGUE};
use crate::model::Model;
use crate::workbench::data_quality::unfit_case::{outlier, NoiseFloors};
use crate::workbench::fit::{fit_with, free_params_of, FitResult};
use crate::workbench::robust::Likelihood;
use rayon::prelude::*;
use serde::Serialize;

const CLEAR_MARGIN: f64 = 4.0;

#[derive(Debug, Clone, Serialize)]
pub struct InfluenceSummary {
    /// What every fit minimised ([`Likelihood::label`]).
    pub likelihood: String,
    /// Candidates with their full-data fit, best AICc first.
    pub candidates: Vec<CandidateScore>,
    /// The clear conclusion on all cases, if any.
    pub conclusion: Option<String>,
    /// Per case: the conclusion without it.
    pub without: Vec<(String, Option<String>)>,
}

/// One candidate's full-data fit, as scored.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateScore {
    pub name: String,
    /// The minimised deviance (the chi-square of a least-squares fit).
    pub deviance: f64,
    pub aicc: Option<f64>,
}

/// What the influence and outlier checks decide about one case (worded by
/// `super::influence_words`).
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// No candidate is clearly best on all cases; without the case `without` is.
    MakesAConclusion { case: String, without: String },
    /// The clear conclusion `with` changes without the case.
    ChangesTheConclusion {
        case: String,
        with: String,
        without: Option<String>,
    },
    /// With the conclusion unchanged, a parameter moves beyond its interval.
    MovesAParameter {
        case: String,
        effect: String,
        name: String,
        value: f64,
        ci95: f64,
        without: f64,
    },
    /// The others are at the noise floor under `best`; the case's
    /// `quantity` stays `z` combined standard errors off, beyond `limit`,
    /// under every candidate that fits them.
    Outlier {
        case: String,
        best: String,
        quantity: &'static str,
        z: f64,
        limit: f64,
    },
}

struct Scored {
    name: String,
    fit: FitResult,
    aicc: Option<f64>,
}

fn n_obs_case(c: &Case) -> usize {
    c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize
}

fn n_obs(data: &Dataset) -> usize {
    data.cases.iter().map(n_obs_case).sum()
}

/// The AICc of a fit's minimised deviance over `n` quantities.
fn aicc(fit: &FitResult, n: usize) -> Option<f64> {
    let k = fit.estimates.len();
    let d = n as i64 - k as i64 - 1;
    (d > 0).then(|| fit.deviance + 2.0 * k as f64 + 2.0 * (k * (k + 1)) as f64 / d as f64)
}

fn scored(name: &str, fit: FitResult, n: usize) -> Scored {
    Scored {
        name: name.to_string(),
        aicc: aicc(&fit, n),
        fit,
    }
}

/// The model and the model with each cheap candidate effect (unfitted).
fn candidate_models(model: &Model) -> Vec<(String, Model)> {
    let mut out = vec![("(none)".to_string(), model.clone())];
    for e in CATALOGUE
        .iter()
        .filter(|e| e.candidate() && !e.costly())
        .filter(|e| !model.effects.iter().any(|m| m.name() == e.name()))
        .filter(|e| model.can_take(**e))
    {
        out.push((
            e.name().to_string(),
            model.clone().with_effect(EffectInstance::default_of(*e)),
        ));
    }
    out
}

/// The clear winner of a scored list, if any.
fn conclusion(list: &[Scored]) -> Option<String> {
    let mut v: Vec<(f64, &str)> = list
        .iter()
        .filter_map(|s| s.aicc.map(|a| (a, s.name.as_str())))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    match v.as_slice() {
        [only] => Some(only.1.to_string()),
        [a, b, ..] if b.0 - a.0 >= CLEAR_MARGIN => Some(a.1.to_string()),
        _ => None,
    }
}

/// Run the influence and outlier checks (module docs), the leave-one-out
/// fits by [`LooMethod::Auto`].
pub fn influence(model: &Model, data: &Dataset, lik: Likelihood) -> (InfluenceSummary, Vec<Flag>) {
    influence_with(model, data, LooMethod::Auto, lik)
}

/// [`influence`] with the leave-one-out fits made by `method`.
pub fn influence_with(
    model: &Model,
    data: &Dataset,
    method: LooMethod,
    lik: Likelihood,
) -> (InfluenceSummary, Vec<Flag>) {
    let (summary, findings) = decide(model, data, method, lik, true);
    (summary, findings.iter().map(Finding::flag).collect())
}

/// What the checks decide; `recheck`: confirm a conclusion the one-step
/// approximation changes by exact refits (always, but for the test that
/// shows the re-check matters).
#[doc(hidden)]
pub fn decide(
    model: &Model,
    data: &Dataset,
    method: LooMethod,
    lik: Likelihood,
    recheck: bool,
) -> (InfluenceSummary, Vec<Finding>) {
    let base_len = model.effects.len();
    let n_all = n_obs(data);
    let full: Vec<Scored> = candidate_models(model)
        .par_iter()
        .filter_map(|(name, m)| {
            let free = free_params_of(m, &(base_len..m.effects.len()).collect::<Vec<_>>());
            let f = fit_with(m, data, None, &free, true, lik).ok()?;
            Some(scored(name, f, n_all))
        })
        .collect();
    let concl = conclusion(&full);
    let fulls: Vec<FullFit> = full
        .iter()
        .map(|s| FullFit {
            fit: &s.fit,
            free: free_params_of(
                &s.fit.model,
                &(base_len..s.fit.model.effects.len()).collect::<Vec<_>>(),
            ),
        })
        .collect();
    let n_sub = |i: usize| n_all - n_obs_case(&data.cases[i]);
    let loo: Vec<Vec<Scored>> = leave_one_out(&fulls, data, method, lik)
        .into_iter()
        .enumerate()
        .map(|(i, fits)| {
            full.iter()
                .zip(fits)
                .filter_map(|(s, f)| Some(scored(&s.name, f?, n_sub(i))))
                .collect()
        })
        .collect();
    let mut ks: Vec<usize> = loo
        .iter()
        .flatten()
        .map(|s| s.fit.estimates.len())
        .collect();
    ks.sort_unstable();
    ks.dedup();
    let floors = NoiseFloors::new(data, &ks, n_all);
    let mut findings = Vec::new();
    let mut without_list = Vec::new();
    for (i, list) in loo.iter().enumerate() {
        let case = &data.cases[i];
        let mut c_i = conclusion(list);
        // A changed conclusion from the one-step approximation is checked
        // by exact refits before a warning claims it: "clearly best
        // without this case" must hold by the same criterion on the data
        // without it.
        let changed = match &concl {
            None => c_i.is_some(),
            Some(x) => c_i.as_ref() != Some(x),
        };
        if recheck && changed && !exact_loo(method, data) {
            c_i = exact_conclusion(&fulls, &full, data, i, lik);
        }
        without_list.push((case.id.clone(), c_i.clone()));
        findings.extend(conclusion_findings(case, &concl, &c_i, &full, list));
        let fitted: Vec<(&str, &FitResult)> =
            list.iter().map(|s| (s.name.as_str(), &s.fit)).collect();
        findings.extend(outlier(case, &fitted, &floors));
    }
    let mut ranked: Vec<CandidateScore> = full
        .iter()
        .map(|s| CandidateScore {
            name: s.name.clone(),
            deviance: s.fit.deviance,
            aicc: s.aicc,
        })
        .collect();
    ranked.sort_by(|a, b| {
        a.aicc
            .unwrap_or(f64::INFINITY)
            .total_cmp(&b.aicc.unwrap_or(f64::INFINITY))
    });
    let summary = InfluenceSummary {
        likelihood: lik.label(),
        candidates: ranked,
        conclusion: concl,
        without: without_list,
    };
    (summary, findings)
}

/// The findings of one case about the conclusion and the parameters
/// (module docs, **Influence**).
fn conclusion_findings(
    case: &Case,
    concl: &Option<String>,
    c_i: &Option<String>,
    full: &[Scored],
    list: &[Scored],
) -> Vec<Finding> {
    let id = case.id.clone();
    let Some(x) = concl else {
        return c_i
            .iter()
            .map(|y| Finding::MakesAConclusion {
                case: id.clone(),
                without: y.clone(),
            })
            .collect();
    };
    if c_i.as_ref() != Some(x) {
        return vec![Finding::ChangesTheConclusion {
            case: id,
            with: x.clone(),
            without: c_i.clone(),
        }];
    }
    let (Some(f), Some(l)) = (
        full.iter().find(|s| &s.name == x),
        list.iter().find(|s| &s.name == x),
    ) else {
        return Vec::new();
    };
    f.fit
        .estimates
        .iter()
        .zip(&l.fit.estimates)
        .filter_map(|(e, el)| {
            let ci = e.ci95?;
            ((el.value - e.value).abs() > ci).then(|| Finding::MovesAParameter {
                case: id.clone(),
                effect: e.effect.clone(),
                name: e.name.clone(),
                value: e.value,
                ci95: ci,
                without: el.value,
            })
        })
        .collect()
}

fn exact_loo(method: LooMethod, data: &Dataset) -> bool {
    match method {
        LooMethod::Exact => true,
        LooMethod::OneStep => false,
        LooMethod::Auto => data.cases.len() <= super::loo::EXACT_MAX_CASES,
    }
}

/// The conclusion without case `i`, every candidate refitted exactly from
/// its full-data fit.
fn exact_conclusion(
    fulls: &[FullFit],
    full: &[Scored],
    data: &Dataset,
    i: usize,
    lik: Likelihood,
) -> Option<String> {
    let mut sub = data.clone();
    sub.cases.remove(i);
    let n = n_obs(&sub);
    let list: Vec<Scored> = fulls
        .par_iter()
        .zip(full)
        .filter_map(|(f, s)| {
            let fit = fit_with(&f.fit.model, &sub, None, &f.free, false, lik).ok()?;
            Some(scored(&s.name, fit, n))
        })
        .collect();
    conclusion(&list)
}
