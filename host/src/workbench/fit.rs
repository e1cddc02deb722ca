//! Weighted least-squares calibration of effect parameters against
//! measurements: minimise `chi² = sum ((pred - obs) / SE)²` over the free
//! parameters of the chosen effects, within their bounds.
//!
//! The solver is the `levenberg-marquardt` crate (MINPACK's algorithm). It
//! is unconstrained, so each bounded parameter is mapped through a logistic
//! `p = lo + (hi - lo) / (1 + e^-u)`; the fit runs in `u`. Several starts
//! (the default, and points across the range) guard against local minima.
//! The covariance `s² (J^T J)^-1` uses the Jacobian in the physical
//! parameters, with `s² = max(1, chi²_red)` so that an underfitting model
//! does not claim precise parameters.
//!
//! Reference: J. J. Moré, "The Levenberg-Marquardt algorithm:
//! implementation and theory", Lecture Notes in Math. 630 (1978) 105.

use super::compare::case_residuals;
use crate::data::{Case, Dataset};
use crate::model::{Model, ModelError};
use crate::stats::Residual;
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use serde::Serialize;

/// One free parameter: effect `effect` of the model, its parameter `param`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreeParam {
    pub effect: usize,
    pub param: usize,
}

/// All free parameters of the model's effects at the given indices.
pub fn free_params_of(model: &Model, effects: &[usize]) -> Vec<FreeParam> {
    effects
        .iter()
        .flat_map(|&e| {
            model.effects[e]
                .free_indices()
                .into_iter()
                .map(move |p| FreeParam {
                    effect: e,
                    param: p,
                })
        })
        .collect()
}

/// A fitted parameter with its uncertainty.
#[derive(Debug, Clone, Serialize)]
pub struct Estimate {
    pub effect: String,
    pub name: String,
    pub unit: String,
    pub value: f64,
    /// 95 % half-width from the covariance; `None` when not identifiable.
    pub ci95: Option<f64>,
    pub at_bound: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct FitResult {
    pub estimates: Vec<Estimate>,
    pub chi2: f64,
    /// Correlation matrix of the estimates (row-major), when defined.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Pairs of parameters that the data cannot separate (|r| > 0.95), or
    /// parameters that do not change the fit at all.
    pub non_identifiable: Vec<String>,
    pub converged: bool,
    #[serde(skip)]
    pub model: Model,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error("{0}")]
    Model(#[from] ModelError),
    #[error("nothing to fit: the dataset has no measured U or Omega_b")]
    NoData,
    #[error("the fit did not produce a finite chi-square (a prediction failed at every start)")]
    NoFiniteStart,
}

/// The fitting problem: the model with its free parameters on the cases.
struct Problem<'a> {
    model: Model,
    free: &'a [FreeParam],
    cases: &'a [&'a Case],
    u: DVector<f64>,
}

fn bounds(model: &Model, f: FreeParam) -> (f64, f64) {
    let spec = model.effects[f.effect].effect.params()[f.param];
    (spec.min, spec.max)
}

fn to_physical(lo: f64, hi: f64, u: f64) -> f64 {
    lo + (hi - lo) / (1.0 + (-u).exp())
}

fn to_internal(lo: f64, hi: f64, p: f64) -> f64 {
    let s = ((p - lo) / (hi - lo)).clamp(1e-9, 1.0 - 1e-9);
    (s / (1.0 - s)).ln()
}

/// Normalised residuals of the model on the cases.
pub fn residuals(model: &Model, cases: &[&Case]) -> Result<Vec<Residual>, ModelError> {
    let mut out = Vec::with_capacity(2 * cases.len());
    for c in cases {
        let p = model.predict(c)?;
        out.extend(case_residuals(c, &p).into_iter().map(|(_, r)| r));
    }
    Ok(out)
}

fn normalised(model: &Model, cases: &[&Case]) -> Option<DVector<f64>> {
    let r = residuals(model, cases).ok()?;
    let v = DVector::from_iterator(r.len(), r.iter().map(Residual::normalised));
    v.iter().all(|x| x.is_finite()).then_some(v)
}

impl Problem<'_> {
    fn apply(&mut self) {
        for (i, f) in self.free.iter().enumerate() {
            let (lo, hi) = bounds(&self.model, *f);
            self.model.effects[f.effect].values[f.param] = to_physical(lo, hi, self.u[i]);
        }
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.u.copy_from(x);
        self.apply();
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        normalised(&self.model, self.cases)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = normalised(&self.model, self.cases)?;
        let mut j = DMatrix::zeros(r0.len(), self.u.len());
        for i in 0..self.u.len() {
            // Central differences in u; the model is smooth in its parameters.
            let h = 1e-6 * (1.0 + self.u[i].abs());
            let mut probe = Problem {
                model: self.model.clone(),
                free: self.free,
                cases: self.cases,
                u: self.u.clone(),
            };
            probe.u[i] += h;
            probe.apply();
            let rp = normalised(&probe.model, self.cases)?;
            probe.u[i] -= 2.0 * h;
            probe.apply();
            let rm = normalised(&probe.model, self.cases)?;
            j.set_column(i, &((rp - rm) / (2.0 * h)));
        }
        // The solver must never see a non-finite Jacobian (it would carry
        // NaN into its QR); `None` makes it stop at the last good point.
        j.iter().all(|x| x.is_finite()).then_some(j)
    }
}

/// Starting points in the internal coordinates: the current values, then a
/// small grid across each range (3 per parameter, at most 9 in all).
fn starts(model: &Model, free: &[FreeParam]) -> Vec<DVector<f64>> {
    let current = DVector::from_iterator(
        free.len(),
        free.iter().map(|f| {
            let (lo, hi) = bounds(model, *f);
            to_internal(lo, hi, model.effects[f.effect].values[f.param])
        }),
    );
    let mut out = vec![current];
    if free.len() <= 2 {
        let grid = [-3.0, 0.0, 3.0];
        let n = grid.len().pow(free.len() as u32);
        for k in 0..n {
            let mut idx = k;
            out.push(DVector::from_iterator(
                free.len(),
                (0..free.len()).map(|_| {
                    let g = grid[idx % 3];
                    idx /= 3;
                    g
                }),
            ));
        }
    }
    out
}

/// Fit `free` parameters of `model` to the measured cases of `data` (or the
/// subset `only`); `multi_start` tries several starts.
pub fn fit(
    model: &Model,
    data: &Dataset,
    only: Option<&[usize]>,
    free: &[FreeParam],
    multi_start: bool,
) -> Result<FitResult, FitError> {
    let cases: Vec<&Case> = match only {
        Some(idx) => idx.iter().map(|&i| &data.cases[i]).collect(),
        None => data.cases.iter().collect(),
    };
    let n_obs: usize = cases
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum();
    if n_obs == 0 {
        return Err(FitError::NoData);
    }
    if free.is_empty() {
        let chi2 = chi2_of(model, &cases)?;
        return Ok(finish(model.clone(), free, &cases, chi2, true));
    }
    let mut best: Option<(Model, f64, bool)> = None;
    let all_starts = starts(model, free);
    let tried = if multi_start {
        &all_starts[..]
    } else {
        &all_starts[..1]
    };
    for u0 in tried {
        let mut problem = Problem {
            model: model.clone(),
            free,
            cases: &cases,
            u: u0.clone(),
        };
        problem.apply();
        let (solved, report) = LevenbergMarquardt::new()
            .with_patience(200)
            .minimize(problem);
        let chi2 = match chi2_of(&solved.model, &cases) {
            Ok(c) if c.is_finite() => c,
            _ => continue,
        };
        if best.as_ref().is_none_or(|b| chi2 < b.1) {
            best = Some((solved.model, chi2, report.termination.was_successful()));
        }
    }
    let (m, chi2, ok) = best.ok_or(FitError::NoFiniteStart)?;
    Ok(finish(m, free, &cases, chi2, ok))
}

fn chi2_of(model: &Model, cases: &[&Case]) -> Result<f64, ModelError> {
    Ok(residuals(model, cases)?
        .iter()
        .map(|r| r.normalised().powi(2))
        .sum())
}

/// Uncertainties, correlations and identifiability at the optimum.
fn finish(
    model: Model,
    free: &[FreeParam],
    cases: &[&Case],
    chi2: f64,
    converged: bool,
) -> FitResult {
    let n = cases
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum::<usize>();
    let k = free.len();
    let jac = if k == 0 {
        None
    } else {
        physical_jacobian(&model, free, cases)
    };
    let s2 = if n > k {
        (chi2 / (n - k) as f64).max(1.0)
    } else {
        1.0
    };
    let cov = jac.as_ref().and_then(|j| {
        let jtj = j.transpose() * j;
        // nalgebra's SVD panics ("Singular value was NaN") on non-finite
        // input; J^T J overflows when a confidence interval is tiny.
        if jtj.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let svd = jtj.clone().svd(false, false);
        let (max, min) = (svd.singular_values.max(), svd.singular_values.min());
        (min > 1e-12 * max && max > 0.0)
            .then(|| jtj.try_inverse())
            .flatten()
            .map(|inv| inv * s2)
    });
    let mut non_identifiable = Vec::new();
    let label = |f: &FreeParam| {
        let e = &model.effects[f.effect];
        format!("{}.{}", e.name(), e.effect.params()[f.param].name)
    };
    let correlation = cov
        .as_ref()
        .map(|c| {
            (0..k)
                .map(|i| {
                    (0..k)
                        .map(|j| c[(i, j)] / (c[(i, i)] * c[(j, j)]).sqrt())
                        .collect::<Vec<f64>>()
                })
                .collect::<Vec<_>>()
        })
        // A non-finite correlation would reach JSON as `null`: drop it, and
        // the parameters are reported as not identifiable below.
        .filter(|r| r.iter().flatten().all(|x| x.is_finite()));
    if let Some(r) = &correlation {
        for i in 0..k {
            for j in 0..i {
                if r[i][j].abs() > 0.95 {
                    non_identifiable.push(format!(
                        "{} and {} (r = {:+.3})",
                        label(&free[i]),
                        label(&free[j]),
                        r[i][j]
                    ));
                }
            }
        }
    } else if k > 0 {
        non_identifiable.push(format!(
            "{}: the data do not constrain them (singular J^T J)",
            free.iter().map(label).collect::<Vec<_>>().join(", ")
        ));
    }
    let t95 = 1.96;
    let estimates = free
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let e = &model.effects[f.effect];
            let spec = e.effect.params()[f.param];
            let v = e.values[f.param];
            let span = spec.max - spec.min;
            Estimate {
                effect: e.name().to_string(),
                name: spec.name.to_string(),
                unit: spec.unit.to_string(),
                value: v,
                ci95: cov
                    .as_ref()
                    .map(|c| t95 * c[(i, i)].sqrt())
                    .filter(|x| x.is_finite()),
                at_bound: (v - spec.min).abs() < 1e-6 * span || (spec.max - v).abs() < 1e-6 * span,
            }
        })
        .collect();
    FitResult {
        estimates,
        chi2,
        correlation,
        non_identifiable,
        converged,
        model,
    }
}

/// Jacobian of the normalised residuals in the physical parameters.
fn physical_jacobian(model: &Model, free: &[FreeParam], cases: &[&Case]) -> Option<DMatrix<f64>> {
    let r0 = normalised(model, cases)?;
    let mut j = DMatrix::zeros(r0.len(), free.len());
    for (i, f) in free.iter().enumerate() {
        let (lo, hi) = bounds(model, *f);
        let v = model.effects[f.effect].values[f.param];
        let h = 1e-6 * (hi - lo).max(v.abs());
        let shifted = |x: f64| {
            let mut m = model.clone();
            m.effects[f.effect].values[f.param] = x;
            normalised(&m, cases)
        };
        // One-sided at a bound, central inside.
        let (a, b) = ((v - h).max(lo), (v + h).min(hi));
        let col = (shifted(b)? - shifted(a)?) / (b - a);
        j.set_column(i, &col);
    }
    j.iter().all(|x| x.is_finite()).then_some(j)
}
