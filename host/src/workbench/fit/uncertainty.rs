//! The uncertainty of a fit at its optimum: the covariance of the
//! estimates from the Fisher information of the likelihood, their
//! correlations, and the parameters the data cannot separate (module docs
//! of [`super`]).
//!
//! Reference: K. L. Lange, R. J. A. Little & J. M. G. Taylor, "Robust
//! statistical modeling using the t distribution", J. Am. Stat. Assoc. 84
//! (1989) 881 (the information of the t location model).

use super::{bounds, normalised, rows, Estimate, FitResult, FreeParam};
use crate::data::Case;
use crate::model::{Model, ModelError};
use crate::workbench::robust::Likelihood;
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
    // J^T W J with W diagonal: scale J's rows by sqrt(w) (never form the
    // n x n matrix: 2000 rows would be 32 MB and O(k n^2) work per fit).
    let root_w = DVector::from_iterator(
        n,
        rows.iter().map(|r| lik.fisher_information_one(r.1).sqrt()),
    );
    let info = jac.as_ref().map(|j| {
        let mut wj = j.clone();
        for (mut row, w) in wj.row_iter_mut().zip(root_w.iter()) {
            row *= *w;
        }
        wj.transpose() * &wj
    });
    let inv = info.as_ref().and_then(inverse);
    // The deviance over what a perfect model shows with n - rank residuals
    // left, and the reduced chi-square, at least 1: the t deviance grows
    // only logarithmically, so for a model that misses every case it alone
    // would claim precise parameters (on the paper's data the base model's
    // body correction came out +-1.6 against least squares' +-53).
    let rank = inv.as_ref().map_or(k, |i| i.rank);
    let s2 = if n > rank {
        let dof = (n - rank) as f64;
        (deviance / (expected * dof / n as f64))
            .max(chi2 / dof)
            .max(1.0)
    } else {
        1.0
    };
    let cov = inv.as_ref().map(|i| &i.cov * s2);
    let held: Vec<Vec<(usize, f64)>> = match (&inv, &info) {
        (Some(i), _) => i.held.clone(),
        (None, Some(m)) => unconstrained_directions(m),
        (None, None) => Vec::new(),
    };
    let in_held = |i: usize| held.iter().flatten().any(|&(p, _)| p == i);
    let mut non_identifiable = Vec::new();
    let label = |f: &FreeParam| {
        let e = &model.effects[f.effect];
        format!("{}.{}", e.name(), e.effect.params()[f.param].name)
    };
    let correlation = cov
        .as_ref()
        .filter(|_| held.is_empty())
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
    } else if k > 0 && held.is_empty() {
        non_identifiable.push(format!(
            "{}: the data do not constrain them (singular J^T J)",
            free.iter().map(label).collect::<Vec<_>>().join(", ")
        ));
    }
    let combos: Vec<String> = held
        .iter()
        .map(|combo| {
            combo
                .iter()
                .map(|&(i, c)| format!("{}{}", if c < 0.0 { "-" } else { "+" }, label(&free[i])))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    for c in &combos {
        non_identifiable.push(format!(
            "{c}: the data leave this combination of them free (a null direction of \
             J^T J, in relative steps): fix one of them; it has no interval, and the \
             other parameters' intervals are with {c} held on its fitted value"
        ));
    }
    let t95 = super::report::Z95;
    let estimates = free
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let e = &model.effects[f.effect];
            let spec = &e.effect.params()[f.param];
            let v = e.values[f.param];
            let span = spec.max - spec.min;
            Estimate {
                effect: e.name().to_string(),
                name: spec.name.to_string(),
                unit: spec.unit.to_string(),
                value: v,
                ci95: cov
                    .as_ref()
                    .filter(|_| !in_held(i))
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
        deviance,
        correlation,
        non_identifiable,
        held: combos,
        converged,
        scale: s2,
        model,
    })
}

/// The covariance of the estimates before the scale `s²`, on the subspace
/// the data constrain.
#[derive(Debug, Clone)]
pub(crate) struct Inverse {
    pub cov: DMatrix<f64>,
    /// The number of directions the data constrain.
    pub rank: usize,
    /// The combinations held ([`unconstrained_directions`]).
    pub held: Vec<Vec<(usize, f64)>>,
}

/// `(J^T W J)^-1` when it is regular; otherwise its pseudo-inverse in the
/// column-scaled parameters (relative steps) with the free combinations
/// removed: the information about every other direction, each free
/// combination held on its fitted value. For two parameters acting only
/// through one combination this gives the others exactly the intervals of
/// the fit with one of the pair fixed (the test below). `None` when the
/// matrix is not finite or singular without a nameable free combination.
pub(crate) fn inverse(jtj: &DMatrix<f64>) -> Option<Inverse> {
    // nalgebra's SVD panics ("Singular value was NaN") on non-finite
    // input; J^T J overflows when a confidence interval is tiny.
    if jtj.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let k = jtj.nrows();
    let svd = jtj.clone().svd(false, false);
    let (max, min) = (svd.singular_values.max(), svd.singular_values.min());
    if max.is_nan() || max <= 0.0 {
        return None;
    }
    if min > 1e-12 * max {
        let cov = jtj.clone().try_inverse()?;
        return Some(Inverse {
            cov,
            rank: k,
            held: Vec::new(),
        });
    }
    let held = unconstrained_directions(jtj);
    if held.is_empty() {
        return None;
    }
    let d: Vec<f64> = (0..k).map(|i| jtj[(i, i)].sqrt()).collect();
    let live: Vec<usize> = (0..k).filter(|&i| d[i] > 0.0).collect();
    let scaled = DMatrix::from_fn(live.len(), live.len(), |a, b| {
        jtj[(live[a], live[b])] / (d[live[a]] * d[live[b]])
    });
    let eig = scaled.symmetric_eigen();
    let top = eig.eigenvalues.max();
    let mut cov = DMatrix::zeros(k, k);
    let mut rank = 0;
    for (j, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda < NULL_EIGENVALUE * top {
            continue;
        }
        rank += 1;
        let v = eig.eigenvectors.column(j);
        for (a, &pa) in live.iter().enumerate() {
            for (b, &pb) in live.iter().enumerate() {
                cov[(pa, pb)] += v[a] * v[b] / (lambda * d[pa] * d[pb]);
            }
        }
    }
    Some(Inverse { cov, rank, held })
}

/// An eigenvalue of the column-scaled `J^T W J` below this fraction of the
/// largest is a direction the data leave free.
const NULL_EIGENVALUE: f64 = 1e-10;

/// The parameter combinations the data leave free: the eigenvectors of
/// the column-scaled `J^T W J` whose eigenvalue is below 1e-10 of the
/// largest, each as the parameters it moves by more than a fifth (index
/// and signed component). Scaling each column to unit norm makes the
/// components relative steps, so parameters of different units compare;
/// a parameter no residual depends on is its own direction.
fn unconstrained_directions(jtj: &DMatrix<f64>) -> Vec<Vec<(usize, f64)>> {
    let k = jtj.nrows();
    if jtj.iter().any(|x| !x.is_finite()) {
        return Vec::new();
    }
    let d: Vec<f64> = (0..k).map(|i| jtj[(i, i)].sqrt()).collect();
    let mut out: Vec<Vec<(usize, f64)>> = (0..k)
        .filter(|&i| d[i] == 0.0)
        .map(|i| vec![(i, 1.0)])
        .collect();
    let live: Vec<usize> = (0..k).filter(|&i| d[i] > 0.0).collect();
    if live.len() < 2 {
        return out;
    }
    let scaled = DMatrix::from_fn(live.len(), live.len(), |a, b| {
        jtj[(live[a], live[b])] / (d[live[a]] * d[live[b]])
    });
    let eig = scaled.symmetric_eigen();
    let max = eig.eigenvalues.max();
    for (j, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda < NULL_EIGENVALUE * max {
            let v = eig.eigenvectors.column(j);
            // A sign convention so the same direction reads the same.
            let lead = v
                .iter()
                .copied()
                .fold(0.0_f64, |m, x| if x.abs() > m.abs() { x } else { m });
            let combo: Vec<(usize, f64)> = v
                .iter()
                .enumerate()
                .filter(|(_, c)| c.abs() > 0.2)
                .map(|(a, &c)| (live[a], c * lead.signum()))
                .collect();
            out.push(combo);
        }
    }
    out
}

/// Jacobian of the normalised residuals in the physical parameters.
pub(crate) fn physical_jacobian(
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

#[cfg(test)]
mod tests {
    use super::{inverse, unconstrained_directions};
    use nalgebra::DMatrix;

    /// Two parameters that act only through their ratio (column 1 is twice
    /// column 0), one that acts on its own, one that acts on nothing.
    #[test]
    fn the_free_combination_names_exactly_the_degenerate_parameters() {
        let j = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 2.0, 0.3, 0.0, //
                -0.5, -1.0, 1.0, 0.0, //
                2.0, 4.0, -0.7, 0.0, //
                0.1, 0.2, 0.2, 0.0,
            ],
        );
        let dirs = unconstrained_directions(&(j.transpose() * &j));
        assert_eq!(dirs.len(), 2, "{dirs:?}");
        assert!(dirs.contains(&vec![(3, 1.0)]), "{dirs:?}");
        let pair = dirs.iter().find(|d| d.len() == 2).expect("the pair");
        assert_eq!((pair[0].0, pair[1].0), (0, 1));
        // Equal relative steps of opposite sign keep the product fixed.
        assert!((pair[0].1 + pair[1].1).abs() < 1e-9, "{pair:?}");
        assert!((pair[0].1.abs() - 0.5_f64.sqrt()).abs() < 1e-9, "{pair:?}");
    }

    /// Parameters 0 and 1 act only through `a + 2b` (column 1 twice column
    /// 0): the others' covariance on the constrained subspace is exactly
    /// that of the information without parameter 1 (it fixed), and the
    /// rank is one less.
    #[test]
    fn the_others_intervals_equal_those_with_one_of_the_pair_fixed() {
        let j = DMatrix::from_row_slice(
            5,
            4,
            &[
                1.0, 2.0, 0.3, 10.0, //
                -0.5, -1.0, 1.0, 4.0, //
                2.0, 4.0, -0.7, -3.0, //
                0.1, 0.2, 0.2, 1.0, //
                0.7, 1.4, 0.5, -2.0,
            ],
        );
        let inv = inverse(&(j.transpose() * &j)).expect("a nameable free combination");
        assert_eq!(inv.rank, 3);
        assert_eq!(inv.held.len(), 1);
        let fixed = j.clone().remove_column(1);
        let reference = (fixed.transpose() * &fixed).try_inverse().unwrap();
        // Others (2, 3) of the full against (1, 2) of the reduced.
        for (a, ra) in [(2, 1), (3, 2)] {
            for (b, rb) in [(2, 1), (3, 2)] {
                let (x, y) = (inv.cov[(a, b)], reference[(ra, rb)]);
                assert!((x - y).abs() < 1e-9 * y.abs().max(1e-3), "{a} {b}: {x} {y}");
            }
        }
        // A regular matrix is simply inverted, at full rank.
        let regular = inverse(&(fixed.transpose() * &fixed)).unwrap();
        assert!(regular.held.is_empty() && regular.rank == 3);
        assert!((regular.cov.clone() - reference).norm() < 1e-9);
    }

    #[test]
    fn a_well_posed_fit_has_no_free_combination() {
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.5, 1.0, -1.0, 2.0]);
        assert!(unconstrained_directions(&(j.transpose() * &j)).is_empty());
    }
}
