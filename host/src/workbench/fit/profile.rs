//! Profile-likelihood intervals of fitted parameters, for where the
//! covariance's symmetric `value ± 1.96 u` misreads a deviance that is
//! not quadratic (an exponent, a multiplier near zero).
//!
//! Each parameter is held at trial values `t` while the others are
//! refitted; the 95 % interval is where the profiled deviance `D(t)`
//! rises above its minimum by `1.96² s²` (Wilks' theorem for one
//! parameter, `chi²_1(0.95) = 3.84`, times the same scale `s²` the
//! covariance carries, `uncertainty.rs`, so that on a quadratic deviance
//! both intervals agree). The crossing is bracketed by doubling steps from
//! the optimum and refined by bisection; an end not reached within the
//! parameter's range is open (`None`).
//!
//! References: D. J. Venzon & S. H. Moolgavkar, Appl. Statist. 37 (1988)
//! 87 (profile-likelihood intervals); lmfit's `conf_interval` (the same
//! scan with an F-test); JCGM 100 (GUM) sec. 6.2.

use super::report::Z95;
use super::{bounds, deviance_of, fit_with, FitError, FitResult, FreeParam};
use crate::data::{Case, Dataset};
use crate::model::Model;
use crate::workbench::robust::Likelihood;
use serde::Serialize;

/// A profile end differing from the covariance's by more than this share
/// of the covariance's half-width makes the interval asymmetric: the
/// profile is then the one reported.
pub const ASYMMETRY: f64 = 0.1;

/// Bisection steps after the bracket: the end to 2^-16 of the bracket,
/// well below the two significant digits it is printed with.
const BISECTIONS: usize = 16;

/// Doubling steps out of the optimum before an end is called open.
const DOUBLINGS: usize = 12;

/// One parameter's 95 % intervals, the profile's beside the covariance's
/// of the same fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProfileInterval {
    pub value: f64,
    /// The profile's ends; `None` where the deviance stays below the
    /// threshold up to the parameter's bound.
    pub low: Option<f64>,
    pub high: Option<f64>,
    /// The covariance's ends (`value ± 1.96 u`) of the same fit.
    pub covariance_low: Option<f64>,
    pub covariance_high: Option<f64>,
    /// Whether the two differ by more than [`ASYMMETRY`] of the
    /// covariance's half-width at either end.
    pub asymmetric: bool,
}

/// The fit of `free` at its optimum (started from `model`'s values) and
/// each free parameter's profile interval in it.
pub fn profile(
    model: &Model,
    data: &Dataset,
    free: &[FreeParam],
    lik: Likelihood,
) -> Result<(FitResult, Vec<ProfileInterval>), FitError> {
    let all: Vec<usize> = (0..free.len()).collect();
    profile_of(model, data, free, &all, lik)
}

/// [`profile`], the intervals of `free[i]` for each `i` of `which` only
/// (in that order), the others still refitted at every trial value: a
/// study's step profiles its own effect's parameters within a joint fit
/// of every step's.
pub fn profile_of(
    model: &Model,
    data: &Dataset,
    free: &[FreeParam],
    which: &[usize],
    lik: Likelihood,
) -> Result<(FitResult, Vec<ProfileInterval>), FitError> {
    let at = fit_with(model, data, None, free, false, lik)?;
    let cases: Vec<&Case> = data.cases.iter().collect();
    let threshold = at.deviance + Z95 * Z95 * at.scale;
    let intervals = which
        .iter()
        .map(|&i| {
            let p = Profiler {
                at: &at,
                data,
                cases: &cases,
                free,
                i,
                lik,
                threshold,
            };
            p.interval()
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((at, intervals))
}

struct Profiler<'a> {
    at: &'a FitResult,
    data: &'a Dataset,
    cases: &'a [&'a Case],
    free: &'a [FreeParam],
    i: usize,
    lik: Likelihood,
    threshold: f64,
}

impl Profiler<'_> {
    fn interval(&self) -> Result<ProfileInterval, FitError> {
        let e = &self.at.estimates[self.i];
        let half = e.ci95.filter(|c| c.is_finite() && *c > 0.0);
        let low = self.end(-1.0, half)?;
        let high = self.end(1.0, half)?;
        let (cl, ch) = (half.map(|h| e.value - h), half.map(|h| e.value + h));
        let differs = |p: Option<f64>, c: Option<f64>| match (p, c, half) {
            (Some(p), Some(c), Some(h)) => (p - c).abs() > ASYMMETRY * h,
            (None, Some(_), _) => true,
            _ => false,
        };
        Ok(ProfileInterval {
            value: e.value,
            low,
            high,
            covariance_low: cl,
            covariance_high: ch,
            asymmetric: half.is_some() && (differs(low, cl) || differs(high, ch)),
        })
    }

    /// The profiled deviance with parameter `i` held at `t`, and the model
    /// it was refitted to (the start of the next trial value).
    fn deviance(&self, start: &Model, t: f64) -> Result<(f64, Model), FitError> {
        let f = self.free[self.i];
        let mut m = start.clone();
        m.effects[f.effect].values[f.param] = t;
        let others: Vec<FreeParam> = self
            .free
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != self.i)
            .map(|(_, &g)| g)
            .collect();
        if others.is_empty() {
            let d = deviance_of(&m, self.cases, self.lik)?;
            return Ok((d, m));
        }
        let r = fit_with(&m, self.data, None, &others, false, self.lik)?;
        Ok((r.deviance, r.model))
    }

    /// Where the profile crosses the threshold on the side `sign`, or
    /// `None` when it does not within the parameter's bound.
    fn end(&self, sign: f64, half: Option<f64>) -> Result<Option<f64>, FitError> {
        let f = self.free[self.i];
        let (lo, hi) = bounds(&self.at.model, f);
        let v = self.at.model.effects[f.effect].values[f.param];
        let bound = if sign < 0.0 { lo } else { hi };
        let mut step = half.unwrap_or(0.05 * (hi - lo)).min((bound - v).abs());
        if step <= 0.0 {
            return Ok(None);
        }
        let (mut inner, mut start) = (v, self.at.model.clone());
        let mut outer = None;
        for _ in 0..DOUBLINGS {
            let t = (v + sign * step).clamp(lo, hi);
            let (d, m) = self.deviance(&start, t)?;
            if !d.is_finite() || d >= self.threshold {
                outer = Some(t);
                break;
            }
            (inner, start) = (t, m);
            if t == bound {
                return Ok(None);
            }
            step *= 2.0;
        }
        let Some(mut outer) = outer else {
            return Ok(None);
        };
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (inner + outer);
            let (d, m) = self.deviance(&start, mid)?;
            if d.is_finite() && d < self.threshold {
                (inner, start) = (mid, m);
            } else {
                outer = mid;
            }
        }
        Ok(Some(0.5 * (inner + outer)))
    }
}

#[cfg(test)]
#[path = "profile_tests.rs"]
mod tests;
