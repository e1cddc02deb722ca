//! `diagnose`: which physical effect is the model missing?
//!
//! 1. The baseline: residuals in standard errors, summary errors, and the
//!    chi-square a perfect model would show ([`super::noise`]).
//! 2. Where it fails: residual trends against case features ([`super::features`]).
//! 3. Every catalogue effect not yet in the model is added in turn, its
//!    free parameters fitted (weighted by the CIs), and scored by
//!    leave-one-case-out cross-validated MARE and by AICc
//!    (`chi² + 2k + 2k(k+1)/(n-k-1)`, undefined when `n - k - 1 <= 0`).
//! 4. If no single effect reaches the noise floor, forward selection tries
//!    the best one with each other candidate.
//! 5. The verdict names an effect only when it is supported: it reaches the
//!    noise floor, its CV error is below the baseline's, and its AICc beats
//!    every other candidate that also reaches the floor by at least
//!    `clear_margin` (4: "considerably less support" for the runner-up,
//!    Burnham & Anderson). Otherwise it says "none needed",
//!    "indistinguishable" (with the experiment that would separate them) or
//!    "unexplained".
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; C. M. Hurvich & C.-L. Tsai,
//! Biometrika 76 (1989) 297 (AICc).

use super::compare::{compare, Comparison};
use super::design::{best_discriminating_case, Suggestion};
use super::features::{trends, Trend};
use super::fit::{fit, free_params_of, Estimate, FitError};
use super::noise::{chi2_noise_floor, error_dofs};
use crate::data::Dataset;
use crate::effects::{Effect, EffectInstance};
use crate::model::Model;
use rayon::prelude::*;
use serde::Serialize;

/// Settings of [`diagnose`]; `Default` gives the documented values.
#[derive(Debug, Clone)]
pub struct DiagnoseSettings {
    /// Quantile of the perfect model's chi-square that counts as "at the noise floor" (0.95).
    pub level: f64,
    /// AICc margin that makes a winner clear (4).
    pub clear_margin: f64,
    /// Try pairs when no single effect reaches the floor (true).
    pub second_effect: bool,
    /// Also try effects marked costly (false).
    pub include_costly: bool,
}

impl Default for DiagnoseSettings {
    fn default() -> Self {
        DiagnoseSettings {
            level: 0.95,
            clear_margin: 4.0,
            second_effect: true,
            include_costly: false,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Baseline {
    pub model: String,
    pub mare: f64,
    pub max_abs_rel_err: f64,
    pub chi2: f64,
    pub chi2_reduced: Option<f64>,
    /// The reduced chi-square a perfect model stays below at `level`.
    pub noise_floor_chi2_reduced: Option<f64>,
    pub at_noise_floor: bool,
}

/// One model variant: the base plus one or two effects, fitted.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    pub effect: String,
    pub params: Vec<Estimate>,
    pub mare: f64,
    pub cv_mare: f64,
    pub chi2: f64,
    pub chi2_reduced: Option<f64>,
    pub aicc: Option<f64>,
    pub at_noise_floor: bool,
    pub non_identifiable: Vec<String>,
    pub converged: bool,
    #[serde(skip)]
    pub model: Model,
}

#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// The missing effect(s), `None` for "none needed", "indistinguishable" or "unexplained".
    pub effect: Option<String>,
    /// Some model variant fits to the noise floor.
    pub explained: bool,
    pub kind: VerdictKind,
    pub note: String,
    pub indistinguishable: Vec<String>,
    pub suggestion: Option<Suggestion>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VerdictKind {
    NoneNeeded,
    Identified,
    Indistinguishable,
    Unexplained,
}

#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    pub baseline: Baseline,
    pub comparison: Comparison,
    pub trends: Vec<Trend>,
    pub ranking: Vec<Candidate>,
    pub pairs: Vec<Candidate>,
    pub verdict: Verdict,
}

/// Effects that `diagnose` may propose: catalogue entries not in the model
/// (costly ones only on request).
pub fn candidates(model: &Model, include_costly: bool) -> Vec<&'static dyn Effect> {
    crate::effects::all()
        .into_iter()
        .filter(|e| e.candidate() && (include_costly || !e.costly()))
        .filter(|e| !model.effects.iter().any(|m| m.name() == e.name()))
        .collect()
}

fn aicc(chi2: f64, n: usize, k: usize) -> Option<f64> {
    let denom = n as i64 - k as i64 - 1;
    (denom > 0).then(|| chi2 + 2.0 * k as f64 + 2.0 * (k * (k + 1)) as f64 / denom as f64)
}

/// Fit the effects at `added` (indices into `model.effects`) and score them.
pub fn evaluate(
    model: &Model,
    added: &[usize],
    data: &Dataset,
    floor: &dyn Fn(usize) -> Option<f64>,
) -> Result<Candidate, FitError> {
    let free = free_params_of(model, added);
    let k = free.len();
    let full = fit(model, data, None, &free, true)?;
    let cmp = compare(&full.model, data, k)?;
    let n = cmp.summary.n;
    let cv_mare = if k == 0 {
        cmp.summary.mare
    } else {
        cross_validated_mare(&full.model, data, &free)
    };
    Ok(Candidate {
        effect: added
            .iter()
            .map(|&i| model.effects[i].name())
            .collect::<Vec<_>>()
            .join(" + "),
        params: full.estimates.clone(),
        mare: cmp.summary.mare,
        cv_mare,
        chi2: full.chi2,
        chi2_reduced: cmp.summary.chi2_reduced,
        aicc: aicc(full.chi2, n, k),
        at_noise_floor: floor(k).is_some_and(|f| full.chi2 <= f),
        non_identifiable: full.non_identifiable.clone(),
        converged: full.converged,
        model: full.model,
    })
}

/// Leave one case out: fit on the rest (warm-started), predict the one left out.
fn cross_validated_mare(fitted: &Model, data: &Dataset, free: &[super::fit::FreeParam]) -> f64 {
    let mut errs = Vec::new();
    for i in 0..data.cases.len() {
        let others: Vec<usize> = (0..data.cases.len()).filter(|&j| j != i).collect();
        let Ok(f) = fit(fitted, data, Some(&others), free, false) else {
            continue;
        };
        let case = &data.cases[i];
        if let Ok(p) = f.model.predict(case) {
            for (_, r) in super::compare::case_residuals(case, &p) {
                errs.push(r.relative_error().abs());
            }
        }
    }
    if errs.is_empty() {
        f64::NAN
    } else {
        errs.iter().sum::<f64>() / errs.len() as f64
    }
}

/// Run the whole diagnosis of `model` on `data`.
pub fn diagnose(
    model: &Model,
    data: &Dataset,
    s: &DiagnoseSettings,
) -> Result<Diagnosis, FitError> {
    let cmp = compare(model, data, 0)?;
    let dofs = error_dofs(data);
    let floor = |k: usize| chi2_noise_floor(&dofs, k, s.level);
    let n = cmp.summary.n;
    let floor0 = floor(0);
    let baseline = Baseline {
        model: model.describe(),
        mare: cmp.summary.mare,
        max_abs_rel_err: cmp.summary.max_abs_rel_err,
        chi2: cmp.summary.chi2,
        chi2_reduced: cmp.summary.chi2_reduced,
        noise_floor_chi2_reduced: floor0.map(|f| f / n as f64),
        at_noise_floor: floor0.is_some_and(|f| cmp.summary.chi2 <= f),
    };
    let trends = trends(data, &cmp);
    let base_len = model.effects.len();
    let mut ranking: Vec<Candidate> = candidates(model, s.include_costly)
        .par_iter()
        .filter_map(|e| {
            let m = model.clone().with_effect(EffectInstance::default_of(*e));
            evaluate(&m, &[base_len], data, &floor).ok()
        })
        .collect();
    sort_by_aicc(&mut ranking);
    let pairs =
        if s.second_effect && !baseline.at_noise_floor && !ranking.iter().any(|c| c.at_noise_floor)
        {
            forward_selection(model, data, &ranking, &floor)
        } else {
            Vec::new()
        };
    let verdict = verdict(model, data, &baseline, &ranking, &pairs, s);
    Ok(Diagnosis {
        baseline,
        comparison: cmp,
        trends,
        ranking,
        pairs,
        verdict,
    })
}

fn sort_by_aicc(v: &mut [Candidate]) {
    v.sort_by(|a, b| {
        let key = |c: &Candidate| c.aicc.unwrap_or(f64::INFINITY);
        key(a)
            .total_cmp(&key(b))
            .then(a.cv_mare.total_cmp(&b.cv_mare))
    });
}

/// The best single effect with each other candidate, fitted jointly.
fn forward_selection(
    model: &Model,
    data: &Dataset,
    ranking: &[Candidate],
    floor: &(dyn Fn(usize) -> Option<f64> + Sync),
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
            evaluate(&m, &[base_len, base_len + 1], data, floor).ok()
        })
        .collect();
    sort_by_aicc(&mut pairs);
    pairs
}

fn verdict(
    model: &Model,
    data: &Dataset,
    base: &Baseline,
    ranking: &[Candidate],
    pairs: &[Candidate],
    s: &DiagnoseSettings,
) -> Verdict {
    let fmt = |x: Option<f64>| x.map(|v| format!("{v:.3}")).unwrap_or_else(|| "n/a".into());
    if base.at_noise_floor {
        return Verdict {
            effect: None,
            explained: true,
            kind: VerdictKind::NoneNeeded,
            note: format!(
                "none needed: the model already fits to the noise (reduced chi-square {} against a noise floor of {})",
                fmt(base.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced)
            ),
            indistinguishable: Vec::new(),
            suggestion: None,
        };
    }
    let pool: &[Candidate] = if ranking.iter().any(|c| c.at_noise_floor) || pairs.is_empty() {
        ranking
    } else {
        pairs
    };
    let Some(best) = pool.iter().find(|c| c.at_noise_floor) else {
        let closest = ranking.first().map(|c| {
            format!(
                "; the closest, {}, takes MARE from {:.1} % to {:.1} % (reduced chi-square {})",
                c.effect,
                100.0 * base.mare,
                100.0 * c.mare,
                fmt(c.chi2_reduced)
            )
        });
        return Verdict {
            effect: None,
            explained: false,
            kind: VerdictKind::Unexplained,
            note: format!(
                "unexplained: no candidate{} brings the fit to the noise floor (reduced chi-square {}){}",
                if pairs.is_empty() { "" } else { " or pair of candidates" },
                fmt(base.noise_floor_chi2_reduced),
                closest.unwrap_or_default()
            ),
            indistinguishable: Vec::new(),
            suggestion: None,
        };
    };
    let best_aicc = best.aicc.unwrap_or(f64::INFINITY);
    let rivals: Vec<&Candidate> = pool
        .iter()
        .filter(|c| {
            c.effect != best.effect
                && c.at_noise_floor
                && c.aicc.unwrap_or(f64::INFINITY) - best_aicc < s.clear_margin
        })
        .collect();
    let cv_falls = best.cv_mare < base.mare;
    if rivals.is_empty() && cv_falls {
        return Verdict {
            effect: Some(best.effect.clone()),
            explained: true,
            kind: VerdictKind::Identified,
            note: format!(
                "missing: {}. MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
                best.effect,
                100.0 * base.mare,
                100.0 * best.mare,
                100.0 * best.cv_mare,
                fmt(base.chi2_reduced),
                fmt(best.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced)
            ),
            indistinguishable: Vec::new(),
            suggestion: None,
        };
    }
    let suggestion = rivals
        .first()
        .and_then(|r| best_discriminating_case(data, &best.model, &r.model));
    let mut names: Vec<String> = vec![best.effect.clone()];
    names.extend(rivals.iter().map(|r| r.effect.clone()));
    let why = if !cv_falls {
        format!(
            "its cross-validated MARE {:.1} % does not beat the baseline's {:.1} %",
            100.0 * best.cv_mare,
            100.0 * base.mare
        )
    } else {
        format!("they fit equally well (AICc within {})", s.clear_margin)
    };
    let hint = suggestion
        .as_ref()
        .map(|g| format!("; to tell them apart, measure {} with {} ({} differs by {:.0} %, about {:.0} standard errors)", g.base_case, g.change, g.quantity, 100.0 * g.rel_difference, g.in_sigma))
        .unwrap_or_default();
    let _ = model;
    Verdict {
        effect: None,
        explained: true,
        kind: VerdictKind::Indistinguishable,
        note: format!(
            "indistinguishable on this data: {}: {why}{hint}",
            names.join(", ")
        ),
        indistinguishable: names,
        suggestion,
    }
}
