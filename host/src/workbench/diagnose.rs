//! `diagnose`: which physical effect is the model missing?
//!
//! 1. The baseline: residuals in standard errors, summary errors, and the
//!    chi-square a perfect model would show ([`super::noise`]).
//! 2. Where it fails: residual trends against the quantity library
//!    ([`super::features`]).
//! 3. Every catalogue effect not yet in the model is added in turn, its
//!    free parameters fitted (weighted by the CIs), and scored by
//!    cross-validated MARE (leave-one-case-out up to ten cases, 10-fold
//!    above: leave-one-out refits grow with the square of the cases) and by
//!    AICc (`chi² + 2k + 2k(k+1)/(n-k-1)`, undefined when `n - k - 1 <= 0`).
//! 4. If no single effect reaches the noise floor, forward selection tries
//!    the best one with each other candidate.
//! 5. Discovery beyond the catalogue ([`super::discovery`]): a sparse search
//!    over (place, feature, form) locates the missing correction in the
//!    model's structure; when a catalogue effect explains most but not all
//!    of the excess, the remainder is located on top of it.
//! 6. The graded verdict ([`super::verdict`]): `none-needed`, `identified`,
//!    `located`, `indistinguishable` or `unexplained`, each named effect or
//!    correction with the share of the excess chi-square it removes.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2; C. M. Hurvich & C.-L. Tsai,
//! Biometrika 76 (1989) 297 (AICc); T. Hastie, R. Tibshirani & J. Friedman,
//! *The Elements of Statistical Learning*, 2nd ed. (2009), sec. 7.10.

use super::compare::{compare, Comparison};
use super::design::Suggestion;
use super::discovery::{Discovery, DiscoverySettings, Located};
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
    /// Search beyond the catalogue (true).
    pub discover: bool,
    pub discovery: DiscoverySettings,
    /// Called with a short message as each stage starts (progress display).
    pub progress: Option<fn(&str)>,
}

impl Default for DiagnoseSettings {
    fn default() -> Self {
        DiagnoseSettings {
            level: 0.95,
            clear_margin: 4.0,
            second_effect: true,
            include_costly: false,
            discover: true,
            discovery: DiscoverySettings::default(),
            progress: None,
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
    /// Share of the excess chi-square (above the noise floor) the named
    /// catalogue effect(s) remove.
    pub effect_explained_fraction: Option<f64>,
    /// Located corrections: for `located` the finding, for `identified` the
    /// remainder beyond the named effect (if any), for `indistinguishable`
    /// the rivals, for `unexplained` the partial corrections that remove at
    /// least half of the excess and lower MARE.
    pub located: Vec<Located>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VerdictKind {
    NoneNeeded,
    Identified,
    Located,
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
    /// The search beyond the catalogue on the model as given.
    pub discovery: Option<Discovery>,
    /// The search on top of the catalogue effect that explains most, when
    /// one explains most but not all of the excess.
    pub remainder: Option<Remainder>,
    pub verdict: Verdict,
}

/// A located remainder on top of a catalogue effect.
#[derive(Debug, Clone, Serialize)]
pub struct Remainder {
    pub effect: String,
    pub discovery: Discovery,
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

use super::discovery::aicc;

/// Fit the effects at `added` (indices into `model.effects`) and score them.
pub fn evaluate(
    model: &Model,
    added: &[usize],
    data: &Dataset,
    floor: &dyn Fn(usize) -> Option<f64>,
) -> Result<Candidate, FitError> {
    let free = free_params_of(model, added);
    let k = free.len();
    // Multi-start is what makes a fit trustworthy and what makes it slow:
    // above 60 cases run it on a strided subset of about 50, then refine
    // from that optimum on every case.
    let n_cases = data.cases.len();
    let full = if n_cases > 60 && !free.is_empty() {
        let sub: Vec<usize> = (0..n_cases).step_by(n_cases.div_ceil(50)).collect();
        let pre = fit(model, data, Some(&sub), &free, true)?;
        fit(&pre.model, data, None, &free, false)?
    } else {
        fit(model, data, None, &free, true)?
    };
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

/// Cross-validated MARE: each case alone (up to ten cases) or ten
/// interleaved folds; each fold refitted warm from the full-data optimum.
fn cross_validated_mare(fitted: &Model, data: &Dataset, free: &[super::fit::FreeParam]) -> f64 {
    let n = data.cases.len();
    let folds = if n <= 10 { n } else { 10 };
    let mut errs = Vec::new();
    for f in 0..folds {
        let train: Vec<usize> = (0..n).filter(|&j| j % folds != f).collect();
        let Ok(fit) = fit(fitted, data, Some(&train), free, false) else {
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

/// Run the whole diagnosis of `model` on `data`.
pub fn diagnose(
    model: &Model,
    data: &Dataset,
    s: &DiagnoseSettings,
) -> Result<Diagnosis, FitError> {
    let say = |m: &str| {
        if let Some(p) = s.progress {
            p(m)
        }
    };
    let cmp = compare(model, data, 0)?;
    let dofs = error_dofs(data);
    let n = cmp.summary.n;
    // The floor's quantile does not depend on k (only its (N-k)/N scaling):
    // one Monte Carlo run serves every candidate.
    let q0 = chi2_noise_floor(&dofs, 0, s.level);
    let floor = move |k: usize| q0.filter(|_| n > k).map(|q| q * (n - k) as f64 / n as f64);
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
    say("fitting the catalogue's effects");
    let cands = candidates(model, s.include_costly);
    // Warm the memoised non-local solves in parallel over cases (a
    // catalogue fit walks its cases serially; milliseconds per case).
    for e in &cands {
        let m = model.clone().with_effect(EffectInstance::default_of(*e));
        data.cases.par_iter().for_each(|c| {
            let _ = m.predict(c);
        });
    }
    let mut ranking: Vec<Candidate> = cands
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
            say("forward selection: pairs of catalogue effects");
            forward_selection(model, data, &ranking, &floor)
        } else {
            Vec::new()
        };
    let (discovery, remainder) = if s.discover && !baseline.at_noise_floor {
        say("searching beyond the catalogue: place x feature x form");
        let reference = super::discovery::Reference {
            chi2: baseline.chi2,
            k: 0,
            floor: &floor,
        };
        let d = super::discovery::discover(model, data, &reference, &s.discovery)?;
        say("locating what the best catalogue effects leave");
        let r = super::verdict::remainders(data, &baseline, &ranking, &d, &floor, s)?;
        (Some(d), r)
    } else {
        (None, None)
    };
    let verdict = super::verdict::verdict(
        data,
        &baseline,
        &ranking,
        &pairs,
        discovery.as_ref(),
        remainder.as_ref(),
        s,
    );
    Ok(Diagnosis {
        baseline,
        comparison: cmp,
        trends,
        ranking,
        pairs,
        discovery,
        remainder,
        verdict,
    })
}

pub(crate) fn sort_by_aicc(v: &mut [Candidate]) {
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
