//! Calibration of effect parameters against measurements: minimise a
//! deviance of the normalised residuals `z = (pred - obs) / SE` over the
//! free parameters of the chosen effects, within their bounds. The
//! deviance is the [`Likelihood`]'s: the chi-square `sum z²` (Gaussian,
//! the default) or the Student-t deviance `sum (nu + 1) ln(1 + z²/nu)`
//! ([`crate::workbench::robust`]), which one bad run cannot drag; [`fit_with`] takes
//! it as an argument from every caller.
//!
//! The solver is the `levenberg-marquardt` crate (MINPACK's algorithm),
//! given the signed square roots of each residual's deviance (their squares
//! sum to the deviance, so least squares on them minimises it directly). It
//! is unconstrained, so each bounded parameter is mapped through a logistic
//! `p = lo + (hi - lo) / (1 + e^-u)`; the fit runs in `u`. Several starts
//! (the default, and points across the range) guard against local minima.
//! The covariance is `s² (J^T W J)^-1`, `J` the Jacobian of `z` in the
//! physical parameters, `W` the Fisher information of each residual (1
//! Gaussian, `(nu + 1)/(nu + 3)` Student-t), and `s²` the larger of the
//! deviance over its expectation for a perfect model and `chi²_red`, at
//! least 1, so that an underfitting model does not claim precise
//! parameters. When the data leave a combination of parameters free (a
//! null direction of the column-scaled `J^T W J`), its parameters get no
//! interval and the others get theirs on the constrained subspace (the
//! pseudo-inverse without the free direction: the combination held on its
//! fitted value), `s²` counted with the constrained directions only.
//!
//! References: J. J. Moré, "The Levenberg-Marquardt algorithm:
//! implementation and theory", Lecture Notes in Math. 630 (1978) 105;
//! K. L. Lange, R. J. A. Little & J. M. G. Taylor, J. Am. Stat. Assoc. 84
//! (1989) 881 (the t likelihood and its information).

pub mod profile;
pub mod report;
pub mod uncertainty;

use crate::data::{Case, Dataset};
use crate::model::{Model, ModelError};
use crate::stats::Residual;
use crate::workbench::compare::{case_residuals, Quantity};
use crate::workbench::robust::Likelihood;
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
    /// The chi-square at the optimum (whatever was minimised).
    pub chi2: f64,
    /// What was minimised ([`Likelihood::label`]).
    pub likelihood: String,
    /// The minimised deviance when it is not the chi-square (the Student-t
    /// deviance); `None` for a Gaussian fit.
    pub t_deviance: Option<f64>,
    /// The deviance that was minimised, whichever it is (the chi-square of
    /// a Gaussian fit): the figure `fit`, `diagnose` and `audit` report
    /// alike for the same model and likelihood.
    pub deviance: f64,
    /// Correlation matrix of the estimates (row-major), when defined.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Pairs of parameters that the data cannot separate (|r| > 0.95), or
    /// parameters that do not change the fit at all.
    pub non_identifiable: Vec<String>,
    /// The combinations the data leave free (`+a -b`, a null direction of
    /// the column-scaled `J^T W J`), each held on its fitted value for the
    /// other parameters' intervals; its own parameters have none.
    pub held: Vec<String>,
    pub converged: bool,
    /// The scale `s²` of the covariance (module docs): the profile's
    /// threshold carries it too ([`profile`]).
    #[serde(skip)]
    pub scale: f64,
    #[serde(skip)]
    pub model: Model,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error("{0}")]
    Model(#[from] ModelError),
    #[error("nothing to fit: the dataset has no measured U or Omega_b")]
    NoData,
    /// Names the free parameters and their ranges: which one the user
    /// must narrow is theirs to see.
    /// The first prediction that failed says which case, place and
    /// formula (the error `compare` gives on the same model).
    #[error(
        "the fit did not produce a finite chi-square (a prediction failed at every start) for {free}{}",
        first.as_ref().map(|e| format!("; first failure: {e}")).unwrap_or_default()
    )]
    NoFiniteStart {
        free: String,
        /// Boxed: a `ModelError` inline would make every fit's `Result` large.
        first: Option<Box<ModelError>>,
    },
    #[error("{0}: its range is too wide to fit (the width overflows a float, or the ends are not finite numbers): give bounds within about 1e300 of each other")]
    RangeTooWide(String),
}

/// The fitting problem: the model with its free parameters on the cases.
struct Problem<'a> {
    model: Model,
    free: &'a [FreeParam],
    cases: &'a [&'a Case],
    u: DVector<f64>,
    likelihood: Likelihood,
}

pub(super) fn bounds(model: &Model, f: FreeParam) -> (f64, f64) {
    let spec = &model.effects[f.effect].effect.params()[f.param];
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

/// Each residual in standard errors with the trials behind its SE.
pub(super) fn rows(model: &Model, cases: &[&Case]) -> Result<Vec<(f64, u32)>, ModelError> {
    let mut out = Vec::with_capacity(2 * cases.len());
    for c in cases {
        let p = model.predict(c)?;
        out.extend(case_residuals(c, &p).into_iter().map(|(q, r)| {
            let m = match q {
                Quantity::U => c.u_mm_s,
                Quantity::Omega => c.omega_body_hz,
            };
            (r.normalised(), m.map_or(2, |m| m.trials))
        }));
    }
    Ok(out)
}

pub(super) fn normalised(model: &Model, cases: &[&Case]) -> Option<DVector<f64>> {
    let r = residuals(model, cases).ok()?;
    let v = DVector::from_iterator(r.len(), r.iter().map(Residual::normalised));
    v.iter().all(|x| x.is_finite()).then_some(v)
}

/// The pseudo-residuals whose squares sum to the deviance.
fn scored(model: &Model, cases: &[&Case], lik: Likelihood) -> Option<DVector<f64>> {
    if lik == Likelihood::Gaussian {
        return normalised(model, cases);
    }
    let r = rows(model, cases).ok()?;
    let v = DVector::from_iterator(r.len(), r.iter().map(|&(z, t)| lik.pseudo_residual(z, t)));
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
        scored(&self.model, self.cases, self.likelihood)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = scored(&self.model, self.cases, self.likelihood)?;
        let mut j = DMatrix::zeros(r0.len(), self.u.len());
        for i in 0..self.u.len() {
            // Central differences in u; the model is smooth in its parameters.
            let h = 1e-6 * (1.0 + self.u[i].abs());
            let mut probe = Problem {
                model: self.model.clone(),
                free: self.free,
                cases: self.cases,
                u: self.u.clone(),
                likelihood: self.likelihood,
            };
            probe.u[i] += h;
            probe.apply();
            let rp = scored(&probe.model, self.cases, self.likelihood)?;
            probe.u[i] -= 2.0 * h;
            probe.apply();
            let rm = scored(&probe.model, self.cases, self.likelihood)?;
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
/// subset `only`), minimising the deviance of `likelihood` (the Gaussian's
/// is least squares); `multi_start` tries several starts. The likelihood
/// is an argument, not a setting of the thread: every layer of `diagnose`
/// passes on the one its settings carry.
pub fn fit_with(
    model: &Model,
    data: &Dataset,
    only: Option<&[usize]>,
    free: &[FreeParam],
    multi_start: bool,
    likelihood: Likelihood,
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
        return Ok(self::uncertainty::finish(
            model.clone(),
            free,
            &cases,
            likelihood,
            true,
        )?);
    }
    for &f in free {
        let (lo, hi) = bounds(model, f);
        if !(hi - lo).is_finite() {
            return Err(FitError::RangeTooWide(describe_free(model, &[f])));
        }
    }
    let mut best: Option<(Model, f64, bool)> = None;
    let mut first_failure: Option<ModelError> = None;
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
            likelihood,
        };
        problem.apply();
        let (solved, report) = LevenbergMarquardt::new()
            .with_patience(200)
            .minimize(problem);
        let objective = match deviance_of(&solved.model, &cases, likelihood) {
            Ok(c) if c.is_finite() => c,
            Ok(_) => continue,
            Err(e) => {
                first_failure.get_or_insert(e);
                continue;
            }
        };
        if best.as_ref().is_none_or(|b| objective < b.1) {
            best = Some((solved.model, objective, report.termination.was_successful()));
        }
    }
    let (m, _, ok) = best.ok_or_else(|| FitError::NoFiniteStart {
        free: describe_free(model, free),
        first: first_failure.map(Box::new),
    })?;
    Ok(self::uncertainty::finish(m, free, &cases, likelihood, ok)?)
}

/// "effect `E`, parameter `p` in [lo, hi]" for each free parameter.
fn describe_free(model: &Model, free: &[FreeParam]) -> String {
    free.iter()
        .map(|&f| {
            let (lo, hi) = bounds(model, f);
            let e = &model.effects[f.effect].effect;
            format!(
                "effect `{}`, parameter `{}` in [{lo:e}, {hi:e}]",
                e.name(),
                e.params()[f.param].name
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The deviance of `likelihood` (the chi-square for the Gaussian).
pub(super) fn deviance_of(
    model: &Model,
    cases: &[&Case],
    lik: Likelihood,
) -> Result<f64, ModelError> {
    Ok(rows(model, cases)?
        .iter()
        .map(|&(z, t)| lik.deviance_one(z, t))
        .sum())
}
