//! The sparse search: every (place, feature, form) with at most two free
//! parameters is fitted on the response table ([`super::screen`]) by a small
//! bounded Levenberg-Marquardt, weighted by the measurement CIs, and scored
//! by AICc; cross-validation is k-fold (exact leave-one-case-out for ten
//! cases or fewer), refitting on the table from the full-data optimum.
//!
//! References: J. J. Moré, Lecture Notes in Math. 630 (1978) 105 (LM);
//! C. M. Hurvich & C.-L. Tsai, Biometrika 76 (1989) 297 (AICc);
//! T. Hastie, R. Tibshirani & J. Friedman, *The Elements of Statistical
//! Learning*, 2nd ed. (2009), sec. 7.10 (k-fold cross-validation).

use super::least_squares::least_squares;
use super::projection::{Basis, Span};
use super::screen::{CaseFeature, Table};
use crate::data::model_quantities::MODEL_QUANTITIES;
use crate::data::quantities::{FEATURES, FIELDS, SETUP_GROUPS};
use crate::data::{Dataset, Feature};
use crate::effects::correction::{Form, LocatedCorrection};
use crate::effects::place::Place;
use crate::effects::Effect;
use rayon::prelude::*;
use std::sync::Arc;

/// One screened candidate: a correction with its table-fitted parameters.
#[derive(Clone)]
pub struct Screened {
    pub correction: Arc<LocatedCorrection>,
    pub params: Vec<f64>,
    pub chi2: f64,
    /// Scaled feature per case (all cases of the dataset).
    pub xs: CaseFeature,
}

/// Features usable on this design: finite on every case and not constant
/// (else it is the constant form), and positive on every case for a
/// library quantity (powers need it). The derived groups come first; then
/// every recorded field and setup group that varies (viscosity, density,
/// body and coupler sizes, channel length, Reynolds numbers, ...), then the
/// model's own quantities when the cases carry them
/// ([`crate::data::model_quantities`]: load torque, thrust, drag, power, U,
/// Omega_b, Reynolds numbers), then the lab's recorded columns
/// ([`crate::data::recorded`]: a temperature, a day, a robot's id), each
/// unless it orders the cases exactly as one already in the list (a
/// monotone function of it on this design, which no fit can tell apart:
/// [`super::equivalent`]); a dataset's own feature is kept before a model
/// quantity or a recorded column that orders the cases alike, as the
/// simpler statement. A recorded column that is zero or negative on some
/// case (a robot's id 0 or 1, a temperature in degrees Celsius below 0)
/// is kept for the forms without a power ([`Usable::positive`]).
///
/// The model's predicted U is nearly a function of the geometry, but not a
/// monotone function of any one feature on a design that varies more than
/// one thing, so it is usually offered; a law in it then competes with the
/// geometry laws under the same criterion, and where both fit alike the
/// criterion's tie rules, not the library, decide. On a design that varies
/// one thing only (a rate sweep, say), U is that thing's monotone function
/// and is left out. A quantity that is not positive on every case (U of a
/// tail-first swimmer) is left out like any other, and so is a model
/// Reynolds number too small to act ([`super::acts::large_enough`]).
pub fn usable_features(data: &Dataset) -> Vec<Usable> {
    let mut out: Vec<Usable> = FEATURES
        .iter()
        .filter_map(|q| Usable::of(Feature::Quantity(q), data))
        .filter(|u| u.positive)
        .collect();
    for q in SETUP_GROUPS.iter().chain(FIELDS).chain(MODEL_QUANTITIES) {
        let Some(u) = Usable::of(Feature::Quantity(q), data).filter(|u| u.positive) else {
            continue;
        };
        if super::acts::large_enough(q, data) {
            push_unless_equivalent(&mut out, u, data);
        }
    }
    for (name, _) in crate::data::recorded::features(data) {
        if let Some(u) = Feature::recorded(&name).and_then(|f| Usable::of(f, data)) {
            push_unless_equivalent(&mut out, u, data);
        }
    }
    out
}

fn push_unless_equivalent(out: &mut Vec<Usable>, u: Usable, data: &Dataset) {
    if !out
        .iter()
        .any(|o| super::equivalent(&o.feature, &u.feature, data))
    {
        out.push(u);
    }
}

/// A feature the search may use on this design, with the reference value
/// its laws are scaled by.
#[derive(Debug, Clone)]
pub struct Usable {
    pub feature: Feature,
    /// The median over the cases (for a column that is not positive on
    /// every case, the median of its magnitude, or its largest magnitude
    /// where that median is 0), so that `x = g / g_ref` is of order one.
    pub reference: f64,
    /// Positive on every case: the forms with a power apply.
    pub positive: bool,
}

impl Usable {
    /// The feature when it is finite and varies on this design.
    fn of(feature: Feature, data: &Dataset) -> Option<Usable> {
        let mut v: Vec<f64> = data.cases.iter().map(|c| feature.of(c)).collect();
        if v.iter().any(|x| !x.is_finite()) {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let (lo, hi) = (v[0], v[v.len() - 1]);
        let positive = lo > 0.0;
        if hi - lo <= 1e-6 * hi.abs().max(lo.abs()) {
            return None;
        }
        let reference = if positive {
            v[v.len() / 2]
        } else {
            let mut mag: Vec<f64> = v.iter().map(|x| x.abs()).collect();
            mag.sort_by(f64::total_cmp);
            let m = mag[mag.len() / 2];
            if m > 0.0 {
                m
            } else {
                mag[mag.len() - 1]
            }
        };
        Some(Usable {
            feature,
            reference,
            positive,
        })
    }
}

/// Every correction the search considers, at the places the model is
/// sensitive to.
pub fn corrections(table: &Table, data: &Dataset) -> Vec<Arc<LocatedCorrection>> {
    let features = usable_features(data);
    let mut out = Vec::new();
    for place in Place::ALL {
        if !table.is_sensitive(place) {
            continue;
        }
        let ls = table.load_scale(place);
        for form in Form::ALL {
            if !form.fits(place) {
                continue;
            }
            if form.needs_feature() {
                for u in &features {
                    let needs_positive = form.has_power() && !u.positive;
                    let library_affine = form == Form::Affine && !u.feature.is_recorded();
                    if !super::acts::acts_at(&u.feature, place) || needs_positive || library_affine
                    {
                        continue;
                    }
                    let f = Some(u.feature.clone());
                    if let Some(c) = LocatedCorrection::new(place, f, form, u.reference, ls) {
                        out.push(Arc::new(c));
                    }
                }
            } else if let Some(c) = LocatedCorrection::new(place, None, form, 1.0, ls) {
                out.push(Arc::new(c));
            }
        }
    }
    out
}

fn starts(c: &LocatedCorrection) -> Vec<Vec<f64>> {
    let additive = c.place.is_additive();
    match (c.form, additive) {
        (Form::Constant, false) => vec![vec![1.0]],
        (Form::Proportional, false) => vec![vec![1.0]],
        (Form::Constant | Form::Linear | Form::Proportional, _) => vec![vec![0.0]],
        (Form::Power, _) | (Form::PowerLaw, true) => {
            vec![vec![0.0, -1.0], vec![0.0, 1.0], vec![0.0, 3.0]]
        }
        (Form::PowerLaw, false) => vec![vec![1.0, -2.0], vec![1.0, 0.0], vec![1.0, 2.0]],
        (Form::Affine, _) => vec![vec![0.0, 1.0], vec![0.0, 0.5], vec![0.0, 2.0]],
    }
}

/// A law's residuals on the observations `sub` into `out`, less their
/// part in the members' span when a basis of it is given
/// ([`super::projection`]); returns their sum of squares (infinite when it
/// is not finite).
fn residuals(
    table: &Table,
    c: &LocatedCorrection,
    p: &[f64],
    xs: &CaseFeature,
    sub: &[usize],
    basis: Option<&Basis>,
    out: &mut Vec<f64>,
) -> f64 {
    table.residuals_into(c, p, xs, sub, out);
    if let Some(b) = basis {
        b.remove(out);
    }
    let s: f64 = out.iter().map(|x| x * x).sum();
    if s.is_finite() {
        s
    } else {
        f64::INFINITY
    }
}

/// Bounded Levenberg-Marquardt on the table from `start`; returns the
/// parameters and chi-square over the observations `sub` (with a basis of
/// the members' span on `sub`: the added-variable chi-square).
pub fn fit_on_table(
    table: &Table,
    c: &LocatedCorrection,
    xs: &CaseFeature,
    sub: &[usize],
    start: &[f64],
    basis: Option<&Basis>,
) -> (Vec<f64>, f64) {
    let bounds: Vec<(f64, f64)> = c.params().iter().map(|s| (s.min, s.max)).collect();
    let mut r = |p: &[f64], out: &mut Vec<f64>| residuals(table, c, p, xs, sub, basis, out);
    least_squares(&mut r, start, &bounds)
}

/// The scaled feature of every case for a correction.
pub fn xs_of(c: &LocatedCorrection, data: &Dataset) -> CaseFeature {
    CaseFeature::new(data.cases.iter().map(|case| c.x(case)).collect())
}

/// Fit one correction on the observations `sub` from each of its starts.
pub fn screen_one(
    table: &Table,
    c: &Arc<LocatedCorrection>,
    data: &Dataset,
    sub: &[usize],
    basis: Option<&Basis>,
) -> Screened {
    let xs = xs_of(c, data);
    let mut best = (Vec::new(), f64::INFINITY);
    for s in starts(c) {
        let (p, f) = fit_on_table(table, c, &xs, sub, &s, basis);
        if f < best.1 || best.0.is_empty() {
            best = (p, f);
        }
    }
    Screened {
        correction: c.clone(),
        params: best.0,
        chi2: best.1,
        xs,
    }
}

/// Cross-validated MARE of a screened correction: cases split into
/// `folds` interleaved folds (each case alone when `folds` >= cases).
pub fn cv_mare(table: &Table, s: &Screened, n_cases: usize, folds: usize) -> f64 {
    let folds = folds.clamp(2, n_cases.max(2));
    let mut errs = Vec::with_capacity(table.obs.len());
    let mut r = Vec::new();
    for f in 0..folds {
        let (test, train): (Vec<usize>, Vec<usize>) =
            (0..table.obs.len()).partition(|&o| table.obs[o].case % folds == f);
        if test.is_empty() || train.is_empty() {
            continue;
        }
        let (p, _) = fit_on_table(table, &s.correction, &s.xs, &train, &s.params, None);
        table.residuals_into(&s.correction, &p, &s.xs, &test, &mut r);
        for (o, z) in test.iter().zip(&r) {
            let ob = table.obs[*o];
            errs.push((z * ob.sigma / ob.observed).abs());
        }
    }
    if errs.is_empty() {
        f64::NAN
    } else {
        errs.iter().sum::<f64>() / errs.len() as f64
    }
}

/// Every law screened once on a response table: on every `stride`-th case
/// when the data hold more than `screen_cases` cases, in the order of
/// [`corrections`]. The search and the best law at each place read the
/// same screen of one model (backfitting asks both of every model it
/// tries), so it is run once.
pub struct Screen {
    /// Every observation of the table.
    pub all: Vec<usize>,
    /// The observations screened on.
    pub sub: Vec<usize>,
    stride: usize,
    /// How many laws were screened (the `M` of the charge `2 ln M`).
    pub n_laws: usize,
    /// The laws whose screened chi-square is finite.
    pub screened: Vec<Screened>,
    /// The members' span on the screened and on every observation, when
    /// the laws were screened with the members free ([`super::projection`]).
    bases: Option<(Basis, Basis)>,
}

impl Screen {
    /// Every law screened with the members already in the table's model
    /// held at their values.
    pub fn run(table: &Table, data: &Dataset, screen_cases: usize) -> Screen {
        Screen::run_free(table, data, screen_cases, None)
    }

    /// Every law screened; with `span`, the members that span covers are
    /// free to first order (the added-variable screen,
    /// [`super::projection`]).
    pub fn run_free(
        table: &Table,
        data: &Dataset,
        screen_cases: usize,
        span: Option<&Span>,
    ) -> Screen {
        let all: Vec<usize> = (0..table.obs.len()).collect();
        let stride = data.cases.len().div_ceil(screen_cases.max(1)).max(1);
        let sub: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&o| table.obs[o].case.is_multiple_of(stride))
            .collect();
        let bases = span.map(|s| (s.basis(&sub), s.basis(&all)));
        let basis = bases.as_ref().map(|b| &b.0);
        let list = corrections(table, data);
        let screened = list
            .par_iter()
            .map(|c| screen_one(table, c, data, &sub, basis))
            .filter(|x| x.chi2.is_finite())
            .collect();
        Screen {
            all,
            sub,
            stride,
            n_laws: list.len(),
            screened,
            bases,
        }
    }

    /// Whether case `i` is among those screened on (every `stride`-th).
    pub fn screens_case(&self, i: usize) -> bool {
        i.is_multiple_of(self.stride)
    }

    /// `x` refitted on every observation when it was screened on a
    /// subsample.
    pub fn on_all(&self, table: &Table, x: &mut Screened) {
        if self.stride > 1 {
            let basis = self.bases.as_ref().map(|b| &b.1);
            let (p, f) = fit_on_table(table, &x.correction, &x.xs, &self.all, &x.params, basis);
            x.params = p;
            x.chi2 = f;
        }
    }
}
