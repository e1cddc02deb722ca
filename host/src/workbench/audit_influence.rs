//! The audit's influence and outlier checks, on the measurements with the
//! input uncertainty combined.
//!
//! **Candidates**: the model as given, and the model with each cheap
//! candidate catalogue effect added (free parameters fitted, weighted by
//! the combined standard errors), ranked by AICc
//! (`chi² + 2k + 2k(k+1)/(n-k-1)`). The conclusion is the best candidate
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
//! quantile a perfect model shows, [`super::noise`]) and every such
//! candidate misses the case by more than the two-sided Student-t quantile
//! at a family-wise 1 % (Bonferroni over all quantities) in combined
//! standard errors: the others agree with a model, this case with none.
//! When no candidate fits the others, the case cannot be called an outlier
//! (the model family itself fails) and nothing is flagged for it.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; R. D. Cook & S. Weisberg
//! (1982).

use super::audit::{Flag, Severity};
use super::compare::case_residuals;
use super::fit::{fit, free_params_of, FitResult};
use super::noise::{chi2_noise_floor, error_dofs};
use crate::data::Dataset;
use crate::effects::{EffectInstance, CATALOGUE};
use crate::model::Model;
use rayon::prelude::*;
use serde::Serialize;

const CLEAR_MARGIN: f64 = 4.0;

#[derive(Debug, Clone, Serialize)]
pub struct InfluenceSummary {
    /// Candidates with their full-data AICc, best first.
    pub candidates: Vec<(String, Option<f64>)>,
    /// The clear conclusion on all cases, if any.
    pub conclusion: Option<String>,
    /// Per case: the conclusion without it.
    pub without: Vec<(String, Option<String>)>,
}

struct Scored {
    name: String,
    fit: FitResult,
    aicc: Option<f64>,
}

fn n_obs(data: &Dataset) -> usize {
    data.cases
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum()
}

fn aicc(chi2: f64, n: usize, k: usize) -> Option<f64> {
    let d = n as i64 - k as i64 - 1;
    (d > 0).then(|| chi2 + 2.0 * k as f64 + 2.0 * (k * (k + 1)) as f64 / d as f64)
}

/// The model and the model with each cheap candidate effect (unfitted).
fn candidate_models(model: &Model) -> Vec<(String, Model)> {
    let mut out = vec![("(none)".to_string(), model.clone())];
    for e in CATALOGUE
        .iter()
        .filter(|e| e.candidate() && !e.costly())
        .filter(|e| !model.effects.iter().any(|m| m.name() == e.name()))
    {
        out.push((
            e.name().to_string(),
            model.clone().with_effect(EffectInstance::default_of(*e)),
        ));
    }
    out
}

fn score(name: &str, m: &Model, base_len: usize, data: &Dataset, multi: bool) -> Option<Scored> {
    let added: Vec<usize> = (base_len..m.effects.len()).collect();
    let free = free_params_of(m, &added);
    let f = fit(m, data, None, &free, multi).ok()?;
    let a = aicc(f.chi2, n_obs(data), free.len());
    Some(Scored {
        name: name.to_string(),
        fit: f,
        aicc: a,
    })
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

fn without(data: &Dataset, i: usize) -> Dataset {
    let mut d = data.clone();
    d.cases.remove(i);
    d
}

/// Run the influence and outlier checks (module docs).
pub fn influence(model: &Model, data: &Dataset) -> (InfluenceSummary, Vec<Flag>) {
    let base_len = model.effects.len();
    let full: Vec<Scored> = candidate_models(model)
        .par_iter()
        .filter_map(|(n, m)| score(n, m, base_len, data, true))
        .collect();
    let concl = conclusion(&full);
    let n_all = n_obs(data);
    let mut flags = Vec::new();
    let mut without_list = Vec::new();
    let loo: Vec<Vec<Scored>> = (0..data.cases.len())
        .into_par_iter()
        .map(|i| {
            let sub = without(data, i);
            full.iter()
                .filter_map(|s| score(&s.name, &s.fit.model, base_len, &sub, false))
                .collect()
        })
        .collect();
    for (i, list) in loo.iter().enumerate() {
        let case = &data.cases[i];
        let sub = without(data, i);
        let c_i = conclusion(list);
        without_list.push((case.id.clone(), c_i.clone()));
        if let (None, Some(y)) = (&concl, &c_i) {
            flags.push(Flag {
                case: case.id.clone(),
                kind: "influence-verdict".into(),
                detail: format!(
                    "{}: with all cases no candidate is clearly best; without this case {y} is (ahead by 4 or more in AICc): this one case stands against that conclusion, check its record or re-measure it",
                    case.id
                ),
                severity: Severity::Warning,
            });
        }
        if let Some(x) = &concl {
            if c_i.as_ref() != Some(x) {
                flags.push(Flag {
                    case: case.id.clone(),
                    kind: "influence-verdict".into(),
                    detail: format!(
                        "{}: with all cases the best-supported effect is {x}; without this case it is {}: the conclusion rests on this one case, re-measure it before relying on it",
                        case.id,
                        c_i.as_deref().map(|s| format!("{s} instead")).unwrap_or_else(|| "undecided".into())
                    ),
                    severity: Severity::Warning,
                });
            } else if let (Some(f), Some(l)) = (
                full.iter().find(|s| &s.name == x),
                list.iter().find(|s| &s.name == x),
            ) {
                for (e, el) in f.fit.estimates.iter().zip(&l.fit.estimates) {
                    let Some(ci) = e.ci95 else { continue };
                    if (el.value - e.value).abs() > ci {
                        flags.push(Flag {
                            case: case.id.clone(),
                            kind: "influence-parameter".into(),
                            detail: format!(
                                "{}: leaving it out moves the fitted {} {} from {} (95 % interval) to {}, beyond the interval: this case drives the fitted value",
                                case.id, e.effect, e.name,
                                crate::format::fmt_value_unc(e.value, ci),
                                crate::format::fmt_sig(el.value, 3)
                            ),
                            severity: Severity::Warning,
                        });
                    }
                }
            }
        }
        if let Some(f) = outlier(case, &sub, list, n_all) {
            flags.push(f);
        }
    }
    let mut ranked: Vec<(String, Option<f64>)> =
        full.iter().map(|s| (s.name.clone(), s.aicc)).collect();
    ranked.sort_by(|a, b| {
        a.1.unwrap_or(f64::INFINITY)
            .total_cmp(&b.1.unwrap_or(f64::INFINITY))
    });
    (
        InfluenceSummary {
            candidates: ranked,
            conclusion: concl,
            without: without_list,
        },
        flags,
    )
}

/// The outlier check of one case against the candidates fitted without it.
fn outlier(
    case: &crate::data::Case,
    others: &Dataset,
    fitted: &[Scored],
    n_all: usize,
) -> Option<Flag> {
    let dofs = error_dofs(others);
    let at_floor: Vec<&Scored> = fitted
        .iter()
        .filter(|s| {
            let k = s.fit.estimates.len();
            chi2_noise_floor(&dofs, k, 0.95).is_some_and(|f| s.fit.chi2 <= f)
        })
        .collect();
    if at_floor.is_empty() {
        return None;
    }
    let level = 1.0 - 0.01 / n_all.max(1) as f64;
    let mut best: Option<(f64, f64, &str, &'static str)> = None;
    for s in &at_floor {
        let p = s.fit.model.predict(case).ok()?;
        let (q, r) = case_residuals(case, &p)
            .into_iter()
            .max_by(|a, b| a.1.normalised().abs().total_cmp(&b.1.normalised().abs()))?;
        let m = if q == super::compare::Quantity::U {
            case.u_mm_s
        } else {
            case.omega_body_hz
        }?;
        let limit = crate::stats::student_t_quantile(level, m.trials);
        let z = r.normalised().abs();
        if z <= limit {
            return None;
        }
        if best.is_none_or(|b| z < b.0) {
            best = Some((z, limit, s.name.as_str(), q.label()));
        }
    }
    let (z, limit, name, q) = best?;
    Some(Flag {
        case: case.id.clone(),
        kind: "outlier".into(),
        detail: format!(
            "{}: the other cases are fitted to the noise (best: {name}), but this case's {q} stays {z:.1} combined standard errors away (limit {limit:.1}) under every model that fits them: no candidate effect removes it; check this case's record or re-measure it",
            case.id
        ),
        severity: Severity::Error,
    })
}
