//! The uncertainty of a fit at its optimum: the covariance of the
//! estimates from the Fisher information of the likelihood, their
//! correlations, and the parameters the data cannot separate (module docs
//! of [`super::fit`]).
//!
//! Reference: K. L. Lange, R. J. A. Little & J. M. G. Taylor, "Robust
//! statistical modeling using the t distribution", J. Am. Stat. Assoc. 84
//! (1989) 881 (the information of the t location model).

use super::fit::{bounds, normalised, rows, Estimate, FitResult, FreeParam};
use super::robust::Likelihood;
use crate::data::Case;
use crate::model::{Model, ModelError};
use nalgebra::{DMatrix, DVector};

/// Uncertainties, correlations and identifiability at the optimum.
pub(super) fn finish(
    model: Model,
    free: &[FreeParam],
    cases: &[&Case],
    lik: Likelihood,
    converged: bool,
) -> Result<FitResult, ModelError> {
    let rows = rows(&model, cases)?;
    let n = rows.len();
    let chi2: f64 = rows.iter().map(|r| r.0 * r.0).sum();
    let deviance: f64 = rows.iter().map(|&(z, t)| lik.deviance_one(z, t)).sum();
    let expected: f64 = rows.iter().map(|r| lik.expected_deviance_one(r.1)).sum();
    let k = free.len();
    let jac = if k == 0 {
        None
    } else {
        physical_jacobian(&model, free, cases)
    };
    // The deviance over what a perfect model shows with n - k residuals
    // left, and the reduced chi-square, at least 1: the t deviance grows
    // only logarithmically, so for a model that misses every case it alone
    // would claim precise parameters (on the paper's data the base model's
    // body correction came out +-1.6 against least squares' +-53).
    let s2 = if n > k {
        let dof = (n - k) as f64;
        (deviance / (expected * dof / n as f64))
            .max(chi2 / dof)
            .max(1.0)
    } else {
        1.0
    };
    // J^T W J with W diagonal: scale J's rows by sqrt(w) (never form the
    // n x n matrix: 2000 rows would be 32 MB and O(k n^2) work per fit).
    let root_w = DVector::from_iterator(
        n,
        rows.iter().map(|r| lik.fisher_information_one(r.1).sqrt()),
    );
    let cov = jac.as_ref().and_then(|j| {
        let mut wj = j.clone();
        for (mut row, w) in wj.row_iter_mut().zip(root_w.iter()) {
            row *= *w;
        }
        let jtj = wj.transpose() * &wj;
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
    Ok(FitResult {
        estimates,
        chi2,
        likelihood: lik.label(),
        t_deviance: (lik != Likelihood::Gaussian).then_some(deviance),
        correlation,
        non_identifiable,
        converged,
        model,
    })
}

/// Jacobian of the normalised residuals in the physical parameters.
pub(super) fn physical_jacobian(
    model: &Model,
    free: &[FreeParam],
    cases: &[&Case],
) -> Option<DMatrix<f64>> {
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
