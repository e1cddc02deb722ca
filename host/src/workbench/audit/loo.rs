//! Leave-one-case-out fits for the audit's influence and outlier checks
//! ([`super::influence`]), in two ways:
//!
//! - **Exact**: every candidate refitted on the data without case `i`,
//!   started from its full-data fit. Cost: `n` fits of `n - 1` cases each,
//!   so `n^2` predictions (12 cases 1.3 s, 50 cases 23 s).
//! - **One step**: the standard approximate case deletion of regression
//!   diagnostics (Cook & Weisberg 1982, sec. 3.4; exact for a model linear
//!   in its parameters). With `J` the Jacobian of the normalised residuals
//!   `r` at the full-data fit `θ`, `J_i`, `r_i` case `i`'s rows, and
//!   `A_i = JᵀJ - J_iᵀJ_i`, one Gauss-Newton step from `θ` on the other
//!   cases gives `Δ_i = A_i⁻¹ (J_iᵀ r_i - g)` with `g = Jᵀr` (zero at an
//!   interior optimum), the parameters `θ + Δ_i` (held inside their
//!   bounds) and the chi-square of the quadratic model,
//!   `χ²_(i) = χ² - |r_i|² + 2Δ_iᵀ(g - J_iᵀr_i) + Δ_iᵀA_iΔ_i`. One Jacobian
//!   per candidate: `n` predictions per parameter, so the cost is linear.
//!   Under the Student-t likelihood the same step is taken on the
//!   pseudo-residuals whose squares sum to the deviance
//!   ([`crate::workbench::robust::Likelihood::pseudo_residual`], their Jacobian by the
//!   chain rule), giving the deviance without the case; the chi-square
//!   without it comes from the same formula in `r` at that step.
//!
//! [`LooMethod::Auto`] refits exactly up to [`EXACT_MAX_CASES`] cases (every
//! dataset of the paper's size keeps the exact answer) and takes the one
//! step beyond; `host/tests/audit.rs` checks that both give the same
//! conclusions on a dataset where both are affordable.
//!
//! Reference: R. D. Cook & S. Weisberg, *Residuals and Influence in
//! Regression* (Chapman & Hall, 1982), ch. 3.

use crate::data::{Case, Dataset};
use crate::model::Model;
use crate::workbench::fit::{fit_with, rows, FitResult, FreeParam};
use crate::workbench::robust::Likelihood;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Largest dataset refitted exactly by [`LooMethod::Auto`]: 40 cases take
/// about 15 s on two cores; the one step takes well under a second there.
pub const EXACT_MAX_CASES: usize = 40;

/// How the leave-one-out fits are made (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LooMethod {
    Exact,
    OneStep,
    Auto,
}

/// One candidate's full-data fit and the free parameters it fitted.
pub struct FullFit<'a> {
    pub fit: &'a FitResult,
    pub free: Vec<FreeParam>,
}

/// Per case `i`, per candidate: the fit without case `i` (`None` when it
/// fails), minimising the deviance of `lik` as the full-data fits did.
pub fn leave_one_out(
    full: &[FullFit],
    data: &Dataset,
    method: LooMethod,
    lik: Likelihood,
) -> Vec<Vec<Option<FitResult>>> {
    let n = data.cases.len();
    let exact = match method {
        LooMethod::Exact => true,
        LooMethod::OneStep => false,
        LooMethod::Auto => n <= EXACT_MAX_CASES,
    };
    if exact {
        return (0..n)
            .into_par_iter()
            .map(|i| {
                let mut sub = data.clone();
                sub.cases.remove(i);
                full.iter()
                    .map(|f| fit_with(&f.fit.model, &sub, None, &f.free, false, lik).ok())
                    .collect()
            })
            .collect();
    }
    let steps: Vec<Vec<Option<FitResult>>> = full
        .par_iter()
        .map(|f| one_step_all(f, &data.cases, lik))
        .collect();
    (0..n)
        .map(|i| steps.iter().map(|s| s[i].clone()).collect())
        .collect()
}

/// Residuals of one case (one or two rows) in standard errors, with the
/// trials behind each.
fn case_rows(model: &Model, case: &Case) -> Option<Vec<(f64, u32)>> {
    let r = rows(model, &[case]).ok()?;
    r.iter().all(|x| x.0.is_finite()).then_some(r)
}

fn set(model: &Model, free: &[FreeParam], theta: &[f64]) -> Model {
    let mut m = model.clone();
    for (f, v) in free.iter().zip(theta) {
        m.effects[f.effect].values[f.param] = *v;
    }
    m
}

/// One case's rows at the full-data fit: the residuals `z`, the
/// pseudo-residuals `p` of the likelihood, and their Jacobians.
struct CaseRows {
    z: DVector<f64>,
    jz: DMatrix<f64>,
    p: DVector<f64>,
    jp: DMatrix<f64>,
}

/// `J^T J` and `J^T r` summed over the cases, for `r` and `J` picked from each.
fn normal_sums(
    rows: &[CaseRows],
    k: usize,
    pick: fn(&CaseRows) -> (&DVector<f64>, &DMatrix<f64>),
) -> (DMatrix<f64>, DVector<f64>) {
    let mut jtj = DMatrix::zeros(k, k);
    let mut g = DVector::zeros(k);
    for c in rows {
        let (r, j) = pick(c);
        jtj += j.transpose() * j;
        g += j.transpose() * r;
    }
    (jtj, g)
}

/// The quadratic model's sum of squares without case `c` after the step
/// `d`, from its full-data value `total`.
fn without(
    total: f64,
    (jtj, g): &(DMatrix<f64>, DVector<f64>),
    (r, j): (&DVector<f64>, &DMatrix<f64>),
    d: &DVector<f64>,
) -> f64 {
    let jr = j.transpose() * r;
    let a = jtj - j.transpose() * j;
    total - r.norm_squared() + 2.0 * d.dot(&(g - &jr)) + d.dot(&(&a * d))
}

/// The one-step fit without each case in turn.
fn one_step_all(full: &FullFit, cases: &[Case], lik: Likelihood) -> Vec<Option<FitResult>> {
    let model = &full.fit.model;
    let k = full.free.len();
    let Some(r): Option<Vec<Vec<(f64, u32)>>> = cases.iter().map(|c| case_rows(model, c)).collect()
    else {
        return vec![None; cases.len()];
    };
    let theta: Vec<f64> = full
        .free
        .iter()
        .map(|f| model.effects[f.effect].values[f.param])
        .collect();
    let bounds: Vec<(f64, f64)> = full
        .free
        .iter()
        .map(|f| {
            let s = &model.effects[f.effect].effect.params()[f.param];
            (s.min, s.max)
        })
        .collect();
    // Per case, its Jacobian rows (rows x k), by central differences inside the bounds.
    let mut jac: Vec<DMatrix<f64>> = r.iter().map(|ri| DMatrix::zeros(ri.len(), k)).collect();
    for p in 0..k {
        let (lo, hi) = bounds[p];
        let h = 1e-6 * (hi - lo).max(theta[p].abs());
        let (a, b) = ((theta[p] - h).max(lo), (theta[p] + h).min(hi));
        let at = |x: f64| {
            let mut t = theta.clone();
            t[p] = x;
            set(model, &full.free, &t)
        };
        let (ma, mb) = (at(a), at(b));
        for (i, c) in cases.iter().enumerate() {
            let (Some(ra), Some(rb)) = (case_rows(&ma, c), case_rows(&mb, c)) else {
                return vec![None; cases.len()];
            };
            for (row, (x, y)) in ra.iter().zip(&rb).enumerate() {
                jac[i][(row, p)] = (y.0 - x.0) / (b - a);
            }
        }
    }
    let rows: Vec<CaseRows> = r
        .iter()
        .zip(jac)
        .map(|(ri, jz)| {
            let z = DVector::from_iterator(ri.len(), ri.iter().map(|x| x.0));
            let p = DVector::from_iterator(
                ri.len(),
                ri.iter().map(|&(z, t)| lik.pseudo_residual(z, t)),
            );
            let mut jp = jz.clone();
            for (mut row, &(z, t)) in jp.row_iter_mut().zip(ri) {
                row *= lik.pseudo_residual_slope(z, t);
            }
            CaseRows { z, jz, p, jp }
        })
        .collect();
    let on_p = normal_sums(&rows, k, |c| (&c.p, &c.jp));
    let on_z = normal_sums(&rows, k, |c| (&c.z, &c.jz));
    rows.iter()
        .map(|c| {
            let (jtj, g) = &on_p;
            let jr = c.jp.transpose() * &c.p;
            let a = jtj - c.jp.transpose() * &c.jp;
            let step = if k == 0 {
                DVector::zeros(0)
            } else {
                a.try_inverse()? * (&jr - g)
            };
            let moved: Vec<f64> = (0..k)
                .map(|p| (theta[p] + step[p]).clamp(bounds[p].0, bounds[p].1))
                .collect();
            let d = DVector::from_iterator(k, (0..k).map(|p| moved[p] - theta[p]));
            let chi2 = without(full.fit.chi2, &on_z, (&c.z, &c.jz), &d).max(0.0);
            let deviance = without(full.fit.deviance, &on_p, (&c.p, &c.jp), &d).max(0.0);
            let mut f = full.fit.clone();
            f.model = set(model, &full.free, &moved);
            for (e, v) in f.estimates.iter_mut().zip(&moved) {
                e.value = *v;
            }
            f.chi2 = chi2;
            f.deviance = deviance;
            f.t_deviance = f.t_deviance.map(|_| deviance);
            (chi2.is_finite() && deviance.is_finite() && moved.iter().all(|x| x.is_finite()))
                .then_some(f)
        })
        .collect()
}
