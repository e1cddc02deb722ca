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
//! candidate misses the case by more than the limit of the one-bad-run
//! test ([`super::outlier::limit`], its own Student-t degrees of freedom,
//! a false-alarm rate of 1 % per dataset) in combined standard errors: the
//! others agree with a model, this case with none.
//! When no candidate fits the others, the case cannot be called an outlier
//! (the model family itself fails) and nothing is flagged for it.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; R. D. Cook & S. Weisberg
//! (1982).

use super::audit::{Flag, Severity};
use super::audit_loo::{leave_one_out, FullFit, LooMethod};
use super::compare::case_residuals;
use super::fit::{fit, free_params_of, FitResult};
use super::noise::{chi2_noise_floor, error_dofs};
use crate::data::Dataset;
use crate::effects::{EffectInstance, CATALOGUE};
use crate::model::Model;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, HashMap, HashSet};

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

fn n_obs_case(c: &crate::data::Case) -> usize {
    c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize
}

fn n_obs(data: &Dataset) -> usize {
    data.cases.iter().map(n_obs_case).sum()
}

/// The degrees of freedom of the quantities' standard errors as a
/// histogram (bits of the dof -> count).
type DofHistogram = Vec<(u64, usize)>;

/// The noise floors the outlier check needs, and the Student-t limits: the
/// floor is a Monte Carlo quantile over every quantity (20 000 draws each)
/// and depends only on the histogram of the degrees of freedom and `k`, so
/// each distinct one is drawn once (in parallel), not once per case; with
/// equal trials everywhere leaving any case out gives the same histogram.
struct NoiseFloors {
    floors: HashMap<(DofHistogram, usize), Option<f64>>,
    limits: HashMap<u32, f64>,
}

impl NoiseFloors {
    /// For every case left out and every `k` of `ks`.
    fn new(data: &Dataset, ks: &[usize], n_all: usize) -> NoiseFloors {
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
        let floors = keys
            .into_par_iter()
            .map(|(h, k)| {
                let dofs: Vec<f64> = h
                    .iter()
                    .flat_map(|&(d, n)| std::iter::repeat_n(f64::from_bits(d), n))
                    .collect();
                let f = chi2_noise_floor(&dofs, k, 0.95);
                ((h, k), f)
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
                    super::outlier::limit(nu, n_all, super::outlier::FALSE_ALARM),
                )
            })
            .collect();
        NoiseFloors { floors, limits }
    }

    /// The floor with `case` left out.
    fn floor(&self, all: &[f64], case: &crate::data::Case, k: usize) -> Option<f64> {
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
        .filter(|e| model.can_take(**e))
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

/// Run the influence and outlier checks (module docs), the leave-one-out
/// fits by [`LooMethod::Auto`].
pub fn influence(model: &Model, data: &Dataset) -> (InfluenceSummary, Vec<Flag>) {
    influence_with(model, data, LooMethod::Auto)
}

/// [`influence`] with the leave-one-out fits made by `method`.
pub fn influence_with(
    model: &Model,
    data: &Dataset,
    method: LooMethod,
) -> (InfluenceSummary, Vec<Flag>) {
    let base_len = model.effects.len();
    let full: Vec<Scored> = candidate_models(model)
        .par_iter()
        .filter_map(|(n, m)| score(n, m, base_len, data, true))
        .collect();
    let concl = conclusion(&full);
    let n_all = n_obs(data);
    let mut flags = Vec::new();
    let mut without_list = Vec::new();
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
    let loo: Vec<Vec<Scored>> = leave_one_out(&fulls, data, method)
        .into_iter()
        .enumerate()
        .map(|(i, fits)| {
            full.iter()
                .zip(fits)
                .filter_map(|(s, f)| {
                    let f = f?;
                    Some(Scored {
                        name: s.name.clone(),
                        aicc: aicc(f.chi2, n_sub(i), f.estimates.len()),
                        fit: f,
                    })
                })
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
    let all_dofs = error_dofs(data);
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
        if changed && !exact_loo(method, data) {
            c_i = exact_conclusion(&fulls, &full, data, i);
        }
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
        if let Some(f) = outlier(case, list, &all_dofs, &floors) {
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

fn exact_loo(method: LooMethod, data: &Dataset) -> bool {
    match method {
        LooMethod::Exact => true,
        LooMethod::OneStep => false,
        LooMethod::Auto => data.cases.len() <= super::audit_loo::EXACT_MAX_CASES,
    }
}

/// The conclusion without case `i`, every candidate refitted exactly from
/// its full-data fit.
fn exact_conclusion(
    fulls: &[FullFit],
    full: &[Scored],
    data: &Dataset,
    i: usize,
) -> Option<String> {
    let mut sub = data.clone();
    sub.cases.remove(i);
    let n = n_obs(&sub);
    let list: Vec<Scored> = fulls
        .par_iter()
        .zip(full)
        .filter_map(|(f, s)| {
            let fit = fit(&f.fit.model, &sub, None, &f.free, false).ok()?;
            Some(Scored {
                name: s.name.clone(),
                aicc: aicc(fit.chi2, n, fit.estimates.len()),
                fit,
            })
        })
        .collect();
    conclusion(&list)
}

/// The outlier check of one case against the candidates fitted without it.
fn outlier(
    case: &crate::data::Case,
    fitted: &[Scored],
    all_dofs: &[f64],
    floors: &NoiseFloors,
) -> Option<Flag> {
    let at_floor: Vec<&Scored> = fitted
        .iter()
        .filter(|s| {
            let k = s.fit.estimates.len();
            floors
                .floor(all_dofs, case, k)
                .is_some_and(|f| s.fit.chi2 <= f)
        })
        .collect();
    if at_floor.is_empty() {
        return None;
    }
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
        let limit = floors.limits[&m.trials];
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
