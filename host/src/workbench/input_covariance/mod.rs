//! The covariance of the predictions across cases and quantities from the
//! inputs' uncertainties, and the chi-square of model against measurement
//! with it (generalised least squares, Aitken 1935).
//!
//! Each uncertain input is one independent source of error. Its load on a
//! predicted quantity `y_a` is the signed sensitivity times its standard
//! uncertainty, `j_a = (dy_a/dx) u_x` (the linear band's contributions,
//! [`super::propagate`]). Stacking the loads as the columns of `J`, the
//! inputs' covariance of the predictions is `C_in = J J^T` (GUM eq. 13 for
//! uncorrelated sources). Which rows a column reaches is the input's scope
//! ([`crate::data::uncertainty::scope_of`]):
//! - a per-case input (the tail's own geometry and rate) is one column per
//!   case, reaching that case's U and Omega_b only;
//! - a shared input (tube, oil, body, trim, coupler) is one column for
//!   every case that records the same value and the same uncertainty: one
//!   physical object, one error, the same in each of those cases. Cases
//!   with another value (a second oil, another tube) are another object
//!   with an independent error.
//!
//! The measurements are independent between quantities and cases (each
//! mean is over its own trials; a correlation between a case's U and
//! Omega_b from shared trials is not recorded by the data, so it is not
//! assumed): `C_meas = diag(s_m^2)`. With `r = observed - predicted`,
//! `chi2 = r^T (C_meas + C_in)^-1 r` (a Cholesky solve), on `n - k`
//! degrees of freedom (`k` the model's free parameters; the solve by the
//! Woodbury identity over the cases' blocks, [`self::solve`]), and its p-value
//! `P(chi2(n - k) >= chi2)`. The covariance is treated as known (type-B
//! inputs and measured standard errors alike), so the reference
//! distribution is chi-square, not the Student-t mixture a few trials
//! would give each quantity.
//!
//! The independent chi-square the comparison used before,
//! `sum r_a^2 / C_aa`, keeps only the diagonal: its mean is the same `n`
//! but its spread is wider than chi-square's when inputs are shared, so
//! its p-value is wrong in either direction.
//!
//! The pull of a shared input ([`Pull`]): what the data want its error to
//! be, in units of its declared uncertainty, with every other input at its
//! declared uncertainty. Writing `r = j delta + e`, `e ~ N(0, C - j j^T)`,
//! the generalised-least-squares estimate is (Sherman-Morrison on
//! `(C - j j^T)^-1`) `delta = (j^T C^-1 r) / (j^T C^-1 j)` with standard
//! deviation `sqrt(1 / (j^T C^-1 j) - 1)`. It is reported, never applied:
//! an input is never chosen because the error falls.
//!
//! References: A. C. Aitken, Proc. R. Soc. Edinburgh 55 (1935) 42-48
//! (generalised least squares); JCGM 100:2008 (GUM) 5.2 and eq. 13
//! (correlated inputs); G. Cowan, *Statistical Data Analysis* (1998),
//! section 7.6 (chi-square with correlated errors).

pub mod solve;
pub mod sources;
pub mod text;

use self::solve::Solver;
pub use self::sources::{rows_and_sources, Row, Source};
use super::propagate::Band;
use crate::data::uncertainty::{scope_of, Scope};
use crate::data::Dataset;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// What the data want of a shared input (module docs).
#[derive(Debug, Clone, Serialize)]
pub struct Pull {
    pub input: String,
    /// How many cases share it.
    pub cases: usize,
    /// The declared standard uncertainty, in the input's unit.
    pub standard: f64,
    /// The estimated error in declared standard uncertainties, and its
    /// standard deviation in the same unit.
    pub pull_sigmas: f64,
    pub pull_sd_sigmas: f64,
    /// The same estimate in the input's unit (`pull_sigmas * standard`).
    pub shift: f64,
}

/// A pull is shown in words when the data pin the input to within this
/// many declared uncertainties (its standard deviation in
/// [`Pull::pull_sd_sigmas`]); the rest are barely informed by the data.
pub const SHOWN_PULL_SD: f64 = 3.0;

impl Pull {
    /// Shared by several cases and pinned by the data ([`SHOWN_PULL_SD`]).
    pub fn informative(&self) -> bool {
        self.cases > 1 && self.pull_sd_sigmas <= SHOWN_PULL_SD
    }
}

/// The chi-square with the inputs' covariance (module docs).
#[derive(Debug, Clone, Serialize)]
pub struct CorrelatedChi2 {
    pub chi2: f64,
    pub n: usize,
    pub free_params: usize,
    /// `n - k`; `None` when not positive.
    pub dof: Option<usize>,
    pub chi2_reduced: Option<f64>,
    /// `P(chi2(dof) >= chi2)`.
    pub p_value: Option<f64>,
    /// The same residuals with each quantity's combined variance alone,
    /// every quantity taken as independent (the diagonal of `C`).
    pub chi2_independent: f64,
    /// The same residuals with the cases taken as independent: every
    /// input's error its own in each case (`C` block-diagonal, each case's
    /// U and Omega_b still correlated by its inputs); `None` when not
    /// computed. Between the two others, it says how much of the change
    /// comes from within the cases and how much from across them.
    pub chi2_cases_independent: Option<f64>,
    /// The shared inputs' pulls, largest first (those the data see).
    pub pulls: Vec<Pull>,
}

/// [`correlated_chi2`] with the inputs' scopes from the data layer and
/// [`CorrelatedChi2::chi2_cases_independent`] filled in.
pub fn correlated_chi2_of(
    data: &Dataset,
    predicted: &[(f64, f64)],
    bands: &[Band],
    free_params: usize,
) -> Option<CorrelatedChi2> {
    let (rows, sources) = rows_and_sources(data, predicted, bands, scope_of);
    let mut x = correlated_chi2(&rows, &sources, free_params)?;
    let (rows, own) = rows_and_sources(data, predicted, bands, |_| Scope::PerCase);
    x.chi2_cases_independent = correlated_chi2(&rows, &own, free_params).map(|c| c.chi2);
    Some(x)
}

/// `C = C_meas + J J^T` over the rows.
pub fn covariance(rows: &[Row], sources: &[Source]) -> DMatrix<f64> {
    let n = rows.len();
    let mut c = DMatrix::from_diagonal(&DVector::from_iterator(
        n,
        rows.iter().map(|r| r.sd_measured * r.sd_measured),
    ));
    for s in sources {
        for &(a, la) in &s.loads {
            for &(b, lb) in &s.loads {
                c[(a, b)] += la * lb;
            }
        }
    }
    c
}

/// The chi-square with the covariance, its p-value and the shared inputs'
/// pulls; `None` when the covariance is not positive definite (a quantity
/// with neither a measured nor an input uncertainty).
pub fn correlated_chi2(
    rows: &[Row],
    sources: &[Source],
    free_params: usize,
) -> Option<CorrelatedChi2> {
    let solver = Solver::new(rows, sources)?;
    let r = DVector::from_iterator(rows.len(), rows.iter().map(|r| r.residual));
    let c_inv_r = solver.solve(&r);
    let chi2 = r.dot(&c_inv_r);
    let n = rows.len();
    let dof = n.checked_sub(free_params).filter(|d| *d > 0);
    let p_value = dof
        .and_then(|d| ChiSquared::new(d as f64).ok())
        .map(|d| d.sf(chi2));
    let chi2_independent = (0..n).map(|a| r[a] * r[a] / solver.diagonal[a]).sum();
    let mut pulls: Vec<Pull> = sources
        .iter()
        .filter(|s| s.scope == Scope::Shared)
        .filter_map(|s| pull(s, n, &solver, &c_inv_r))
        .collect();
    pulls.sort_by(|a, b| b.pull_sigmas.abs().total_cmp(&a.pull_sigmas.abs()));
    Some(CorrelatedChi2 {
        chi2,
        n,
        free_params,
        dof,
        chi2_reduced: dof.map(|d| chi2 / d as f64),
        p_value,
        chi2_independent,
        chi2_cases_independent: None,
        pulls,
    })
}

/// Below this information `j^T C^-1 j` the data do not see a source:
/// its pull would have a standard deviation above 1e6 declared
/// uncertainties (an input the outputs do not depend on, such as the
/// viscosity when nothing but the tail and body drags balance, has loads
/// at finite-difference round-off).
const UNSEEN: f64 = 1e-12;

/// The pull of one source (module docs); `None` for a source the data
/// do not see ([`UNSEEN`]).
fn pull(s: &Source, n: usize, solver: &Solver, c_inv_r: &DVector<f64>) -> Option<Pull> {
    let mut j = DVector::zeros(n);
    for &(a, l) in &s.loads {
        j[a] += l;
    }
    let c_inv_j = solver.solve(&j);
    let a = j.dot(&c_inv_j);
    (a > UNSEEN).then(|| {
        let delta = j.dot(c_inv_r) / a;
        Pull {
            input: s.name.clone(),
            cases: s.cases,
            standard: s.standard,
            pull_sigmas: delta,
            // a < 1 always (C holds j j^T plus a positive diagonal)
            pull_sd_sigmas: (1.0 / a - 1.0).max(0.0).sqrt(),
            shift: delta * s.standard,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workbench::compare::Quantity;
    use proptest::prelude::*;

    fn rows(res: &[f64], sd: &[f64]) -> Vec<Row> {
        // two quantities per case, as U and Omega_b
        res.iter()
            .zip(sd)
            .enumerate()
            .map(|(a, (r, s))| Row {
                case: format!("case-{}", a / 2),
                quantity: Quantity::U,
                residual: *r,
                sd_measured: *s,
            })
            .collect()
    }

    fn shared(loads: &[f64]) -> Source {
        Source {
            name: "x".into(),
            scope: Scope::Shared,
            standard: 0.5,
            loads: loads.iter().copied().enumerate().collect(),
            cases: loads.len(),
        }
    }

    proptest! {
        /// The pull's closed form (Sherman-Morrison on C - j j^T) is the
        /// generalised-least-squares estimate solved directly, and the
        /// chi-square is never negative.
        #[test]
        fn the_pull_is_the_gls_estimate_solved_directly(
            res in prop::collection::vec(-3.0f64..3.0, 4),
            sd in prop::collection::vec(0.1f64..2.0, 4),
            j in prop::collection::vec(-2.0f64..2.0, 4),
            other in prop::collection::vec(-1.0f64..1.0, 4),
        ) {
            prop_assume!(j.iter().map(|x| x * x).sum::<f64>() > 1e-3);
            let rs = rows(&res, &sd);
            let mut second = shared(&other);
            second.name = "y".into();
            let sources = [shared(&j), second];
            let x = correlated_chi2(&rs, &sources, 0).unwrap();
            prop_assert!(x.chi2 >= 0.0);
            // the Woodbury solve against the dense Cholesky of C
            let r0 = DVector::from_vec(res.clone());
            let dense = covariance(&rs, &sources).cholesky().unwrap().solve(&r0);
            prop_assert!((x.chi2 - r0.dot(&dense)).abs() < 1e-8 * (1.0 + x.chi2));
            let p = x.pulls.iter().find(|p| p.input == "x").unwrap();
            // direct: the noise is C without x's own column
            let noise = covariance(&rs, &sources[1..]);
            let w = noise.try_inverse().unwrap();
            let jv = DVector::from_vec(j.clone());
            let r = DVector::from_vec(res.clone());
            let info = jv.dot(&(&w * &jv));
            let delta = jv.dot(&(&w * &r)) / info;
            prop_assert!((p.pull_sigmas - delta).abs() < 1e-8 * (1.0 + delta.abs()));
            prop_assert!((p.pull_sd_sigmas - info.powf(-0.5)).abs() < 1e-8 * (1.0 + info.powf(-0.5)));
            prop_assert!((p.shift - 0.5 * delta).abs() < 1e-8 * (1.0 + delta.abs()));
        }

        /// A covariance with each source on one row only is diagonal: the
        /// statistic is the independent sum.
        #[test]
        fn one_row_per_source_is_the_independent_sum(
            res in prop::collection::vec(-3.0f64..3.0, 5),
            sd in prop::collection::vec(0.1f64..2.0, 5),
            l in prop::collection::vec(-2.0f64..2.0, 5),
        ) {
            let rs = rows(&res, &sd);
            let sources: Vec<Source> = l
                .iter()
                .enumerate()
                .map(|(a, v)| Source { loads: vec![(a, *v)], cases: 1, ..shared(&[]) })
                .collect();
            let x = correlated_chi2(&rs, &sources, 2).unwrap();
            prop_assert!((x.chi2 - x.chi2_independent).abs() < 1e-10 * (1.0 + x.chi2));
            prop_assert_eq!(x.dof, Some(3));
        }
    }
}
