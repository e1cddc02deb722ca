//! Discovery beyond the catalogue: locate the missing effect in the
//! model's structure and state it as a formula.
//!
//! 1. [`screen`]: the response of every measured quantity to a change at
//!    each place of the model ([`crate::effects::place`]), tabulated once.
//! 2. [`search`]: every law `(place, feature, form)` of
//!    [`crate::effects::correction`] (at most two free parameters) is fitted
//!    on the table, weighted by the measurement CIs, and ranked by AICc.
//!    On large datasets the screening uses an evenly strided subset of at
//!    most `screen_cases` cases; the ranking only picks who is refitted.
//! 3. The best `top` are refitted on every case with the real model
//!    ([`crate::workbench::fit`], starting from the screened optimum), which
//!    gives exact chi-square, MARE and 95 % CIs; their cross-validated MARE
//!    is k-fold on the table (leave-one-case-out up to ten cases). They are
//!    ranked by the AICc of the deviance the refit minimised
//!    ([`super::score`]; the screening's own ranking stays on the table's
//!    chi-square: it only picks who is refitted).
//! 4. Each is given its explained fraction of the excess chi-square above
//!    the noise floor and a physics sentence ([`interpret`]).
//!
//! Deciding what the results mean (located, indistinguishable, ...) is
//! [`crate::workbench::diagnose`]'s job.
//!
//! References: Burnham & Anderson, *Model Selection and Multimodel
//! Inference*, 2nd ed. (2002); S. L. Brunton, J. L. Proctor & J. N. Kutz,
//! PNAS 113 (2016) 3932 (sparse identification of a model's missing terms
//! from a library of candidate functions).

pub mod acts;
pub mod interpret;
pub mod least_squares;
pub mod places;
pub mod projection;
pub mod screen;
pub mod search;
pub mod write;

use super::compare::compare;
use super::fit::profile::{profile, ProfileInterval};
use super::fit::report::{strong_correlations, StrongCorrelation};
use super::fit::{fit_with, free_params_of, Estimate, FitError};
use super::score::{Deviance, FitScore};
use crate::data::{Dataset, Feature};
use crate::effects::correction::{Form, LocatedCorrection};
use crate::effects::place::Part;
use crate::effects::EffectInstance;
use crate::model::Model;
use rayon::prelude::*;
pub use screen::Table;
use search::{cv_mare, Screen};
use serde::Serialize;
use std::borrow::Cow;
use std::sync::Arc;

/// Settings of [`discover`]; `Default` gives the documented values.
#[derive(Debug, Clone)]
pub struct DiscoverySettings {
    /// Candidates refitted exactly (10; half above
    /// [`Self::large_above_cases`]).
    pub top: usize,
    /// Most cases used for screening (100).
    pub screen_cases: usize,
    /// Cross-validation folds above ten cases (10).
    pub folds: usize,
    /// Above this many cases (200) the data are large: each exact fit
    /// costs proportionally more, so half the candidates are refitted and
    /// the search over sets narrows to its large breadth
    /// ([`crate::workbench::search::settings`]).
    pub large_above_cases: usize,
}

impl DiscoverySettings {
    /// Whether `n_cases` cases are large data (above
    /// [`Self::large_above_cases`]).
    pub fn is_large(&self, n_cases: usize) -> bool {
        n_cases > self.large_above_cases
    }
}

impl Default for DiscoverySettings {
    fn default() -> Self {
        DiscoverySettings {
            top: 10,
            screen_cases: 100,
            folds: 10,
            large_above_cases: 200,
        }
    }
}

/// A located correction, fitted and scored.
#[derive(Debug, Clone, Serialize)]
pub struct Located {
    pub part: Part,
    pub target: &'static str,
    /// `part.target`.
    pub place: &'static str,
    /// The feature's id (`recorded.NAME` for a recorded column), `None`
    /// for a constant.
    pub feature: Option<Cow<'static, str>>,
    /// The feature's formula in the paper's symbols, or a recorded
    /// column's name.
    pub feature_name: Option<Cow<'static, str>>,
    pub form: Form,
    /// The law with quantity ids, as written in an effect file.
    pub formula: String,
    pub params: Vec<Estimate>,
    #[serde(flatten)]
    pub score: FitScore,
    /// Share of the reference model's chi-square above the noise floor that
    /// this correction removes (1 = all of it; negative = worse).
    pub explained_fraction: Option<f64>,
    pub interpretation: String,
    /// The readings the axial model cannot tell from this one (another
    /// place, the law mapped): its physically equivalent readings.
    pub equivalent: Vec<interpret::Equivalent>,
    pub non_identifiable: Vec<String>,
    /// The effects beneath it (`NAME:k=v,...` at full precision): the
    /// model it was fitted on top of, machine-readable.
    pub on_top_of: Vec<String>,
    /// Its Student-t deviance ([`crate::workbench::robust`]).
    pub t_deviance: f64,
    /// Its parameters' profile intervals and strong correlations, for a
    /// law the verdict keeps ([`profiled`]); `None` for the others.
    pub profile: Option<LawProfile>,
    #[serde(skip)]
    pub model: Model,
    #[serde(skip)]
    pub correction: Arc<LocatedCorrection>,
}

/// What the search found.
#[derive(Debug, Clone, Serialize)]
pub struct Discovery {
    /// Corrections screened on the table.
    pub screened: usize,
    /// The exact refits, best AICc of the minimised deviance first
    /// ([`super::score`]).
    pub located: Vec<Located>,
}

/// What the search compares against: the reference model's chi-square,
/// its already fitted parameters and the noise floor.
pub struct Reference<'a> {
    pub chi2: f64,
    /// Free parameters already fitted in the model (counted in AICc).
    pub k: usize,
    pub floor: &'a (dyn Fn(usize) -> Option<f64> + Sync),
    /// The likelihood every refit minimises.
    pub likelihood: super::robust::Likelihood,
}

pub use super::score::aicc;

/// Fraction of `reference`'s excess over the floor that `chi2` removes:
/// the one definition, [`crate::stats::excess_removed`].
pub fn explained_fraction(reference: f64, chi2: f64, floor0: Option<f64>) -> Option<f64> {
    crate::stats::excess_removed(reference, chi2, floor0)
}

/// Search for the correction `model` misses on `data`.
pub fn discover(
    model: &Model,
    data: &Dataset,
    reference: &Reference,
    s: &DiscoverySettings,
) -> Result<Discovery, FitError> {
    let table = Table::build(model, data)?;
    let screen = Screen::run(&table, data, s.screen_cases);
    discover_on(&table, &screen, model, data, reference, s)
}

/// [`discover`] on a response table already built and screened for
/// `model` (a caller that also wants the best law at each place builds
/// both once).
pub fn discover_on(
    table: &Table,
    screen: &Screen,
    model: &Model,
    data: &Dataset,
    reference: &Reference,
    s: &DiscoverySettings,
) -> Result<Discovery, FitError> {
    let n_cases = data.cases.len();
    let n_screen = screen.sub.len();
    let mut screened = screen.screened.clone();
    let key = |x: &search::Screened| {
        aicc(x.chi2, n_screen, reference.k + x.params.len()).unwrap_or(x.chi2)
    };
    screened.sort_by(|a, b| key(a).total_cmp(&key(b)));
    // The best `top`, plus at each of their places the constant and the
    // best one-parameter law, so that parsimony can choose among them.
    // Exact refits cost a full fit each: halve them on large datasets.
    let top = if s.is_large(n_cases) {
        s.top.div_ceil(2)
    } else {
        s.top
    };
    let mut keep: Vec<usize> = (0..screened.len().min(top)).collect();
    let places: Vec<_> = keep.iter().map(|&i| screened[i].correction.place).collect();
    for place in places {
        for constant in [true, false] {
            if let Some(i) = screened.iter().position(|x| {
                x.correction.place == place
                    && x.params.len() == 1
                    && (x.correction.form == Form::Constant) == constant
            }) {
                if !keep.contains(&i) {
                    keep.push(i);
                }
            }
        }
    }
    let screened: Vec<_> = keep.into_iter().map(|i| screened[i].clone()).collect();
    let folds = if n_cases <= 10 { n_cases } else { s.folds };
    let floor0 = (reference.floor)(0);
    let mut located: Vec<Located> = screened
        .into_par_iter()
        .filter_map(|mut x| {
            screen.on_all(table, &mut x);
            let cv = cv_mare(table, &x, n_cases, folds);
            refit(model, data, x, cv, reference, floor0).ok()
        })
        .collect();
    located.sort_by(|a, b| {
        let k = |l: &Located| l.score.aicc.unwrap_or(f64::INFINITY);
        k(a).total_cmp(&k(b))
    });
    Ok(Discovery {
        screened: screen.n_laws,
        located,
    })
}

/// The exact refit of one screened correction.
fn refit(
    model: &Model,
    data: &Dataset,
    x: search::Screened,
    cv_mare: f64,
    reference: &Reference,
    floor0: Option<f64>,
) -> Result<Located, FitError> {
    let c = x.correction;
    let m = model.clone().with_effect(EffectInstance {
        effect: c.clone().into(),
        values: x.params.clone(),
    });
    let free = free_params_of(&m, &[m.effects.len() - 1]);
    let full = fit_with(&m, data, None, &free, false, reference.likelihood)?;
    let k = reference.k + free.len();
    let cmp = compare(&full.model, data, k)?;
    let values = full
        .model
        .effects
        .last()
        .expect("just added")
        .values
        .clone();
    Ok(Located {
        part: c.place.part(),
        target: c.place.target(),
        place: c.place.name(),
        feature: c.feature.as_ref().map(Feature::id),
        feature_name: c.feature.as_ref().map(Feature::name),
        form: c.form,
        formula: c.formula(),
        params: full.estimates.clone(),
        score: FitScore::of(
            &cmp.summary,
            cv_mare,
            Deviance::of_fit(&full),
            k,
            (reference.floor)(k),
        ),
        explained_fraction: explained_fraction(reference.chi2, full.chi2, floor0),
        interpretation: interpretation_of(&c, &values, data),
        equivalent: interpret::equivalents(c.place).to_vec(),
        non_identifiable: full.non_identifiable.clone(),
        on_top_of: model.effects.iter().map(write::exact_spec).collect(),
        t_deviance: crate::workbench::robust::t_deviance_of(&full.model, data)?,
        profile: None,
        model: full.model,
        correction: c,
    })
}

/// The reading of a law with these values on this design
/// ([`interpret::interpret_on`]): rising or falling across the data, judged
/// at the extreme cases of its feature.
pub fn interpretation_of(c: &LocatedCorrection, values: &[f64], data: &Dataset) -> String {
    let by_x = |a: &&crate::data::Case, b: &&crate::data::Case| c.x(a).total_cmp(&c.x(b));
    let lo = data.cases.iter().min_by(by_x).expect("cases");
    let hi = data.cases.iter().max_by(by_x).expect("cases");
    let rising = c.value(values, hi) > c.value(values, lo);
    let mean_value =
        data.cases.iter().map(|k| c.value(values, k)).sum::<f64>() / data.cases.len() as f64;
    interpret::interpret_on(
        c.place,
        c.feature.as_ref(),
        rising,
        mean_value,
        design_of(c, values, data),
    )
}

/// The channel's variation and the law's range over the cases.
fn design_of(c: &LocatedCorrection, values: &[f64], data: &Dataset) -> interpret::Design {
    let d: Vec<f64> = data.cases.iter().map(|k| k.channel_diameter_mm).collect();
    let (lo_d, hi_d) = d.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &x| {
        (a.0.min(x), a.1.max(x))
    });
    let v: Vec<f64> = data.cases.iter().map(|k| c.value(values, k)).collect();
    let range = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &x| {
        (a.0.min(x), a.1.max(x))
    });
    interpret::Design {
        channel_varies: hi_d - lo_d > 1e-6 * hi_d,
        range,
    }
}

/// A law's parameters as the profile likelihood and the covariance of
/// one fit see them: the law's parameters refitted, the model beneath it
/// held at its values.
#[derive(Debug, Clone, Serialize)]
pub struct LawProfile {
    /// Per parameter, in the law's order.
    pub intervals: Vec<ProfileInterval>,
    /// The pairs correlated beyond [`crate::workbench::fit::report::STRONG_CORRELATION`].
    pub correlations: Vec<StrongCorrelation>,
}

/// The profile of `l`'s parameters (the law is its model's last effect);
/// `None` when the law has none or a refit fails (the covariance's
/// intervals then stand alone).
pub fn profiled(l: &Located, data: &Dataset, lik: super::robust::Likelihood) -> Option<LawProfile> {
    let last = l.model.effects.len().checked_sub(1)?;
    let free = free_params_of(&l.model, &[last]);
    if free.is_empty() {
        return None;
    }
    let (at, intervals) = profile(&l.model, data, &free, lik).ok()?;
    let names: Vec<String> = at.estimates.iter().map(|e| e.name.clone()).collect();
    let correlations = at
        .correlation
        .as_ref()
        .map(|r| strong_correlations(&names, r))
        .unwrap_or_default();
    Some(LawProfile {
        intervals,
        correlations,
    })
}

impl Located {
    /// `tail.c_n = 1 + k (wire_over_gap/0.1)^p` with fitted values.
    pub fn describe(&self) -> String {
        let params = self
            .params
            .iter()
            .map(|p| format!("{}={}", p.name, crate::format::fmt_sig(p.value, 4)))
            .collect::<Vec<_>>()
            .join(", ");
        format!("{} = {} ({params})", self.place, self.formula)
    }

    /// Whether two findings name the same physics: same place, and the same
    /// feature or features ordered identically across the cases (monotone
    /// functions of each other on this design, which no fit can tell apart).
    pub fn same_finding(&self, other: &Located, data: &Dataset) -> bool {
        if self.place != other.place {
            return false;
        }
        match (&self.correction.feature, &other.correction.feature) {
            (None, None) => true,
            (Some(a), Some(b)) => a.same(b) || equivalent(a, b, data),
            _ => false,
        }
    }
}

/// Two features are equivalent on a design when their Spearman rank
/// correlation is +-1 (within 1e-9): one is a monotone function of the
/// other over the cases.
pub fn equivalent(a: &Feature, b: &Feature, data: &Dataset) -> bool {
    let values = |q: &Feature| -> Vec<f64> { data.cases.iter().map(|c| q.of(c)).collect() };
    crate::stats::spearman_rho(&values(a), &values(b)).is_some_and(|rho| rho.abs() > 1.0 - 1e-9)
}

/// Whether a form is a constant (no feature).
pub fn is_constant(l: &Located) -> bool {
    l.form == Form::Constant
}
