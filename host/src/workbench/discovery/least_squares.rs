//! Bounded Levenberg-Marquardt for the screens: a few parameters, residuals
//! that are a few dozen arithmetic expressions (a law read off the response
//! table, or a speed read off each case's force balance), fitted hundreds
//! of times per diagnosis.
//!
//! The Jacobian is taken by forward differences and the bounds by clamping.
//! Written here rather than taken from a crate: it is the screen's own solver,
//! moved here unchanged so that the speed pairs share it, and the screen's
//! ranking, and so every verdict, depends on its arithmetic to the last
//! digit at near-ties (the normal equations are summed in observation
//! order and solved in closed form for one or two parameters). Moving it
//! left every verdict of the recovery seeds checked byte-identical.
//!
//! References: K. Levenberg, Q. Appl. Math. 2 (1944) 164; D. W. Marquardt,
//! J. SIAM 11 (1963) 431.

/// Most iterations (40) and damping increases per iteration (12).
const ITERATIONS: usize = 40;
const TRIES: usize = 12;

/// Most parameters a fit may have (4: two laws of two parameters).
pub const MAX_PARAMS: usize = 4;

/// A fit stops when a step lowers the sum by less than this fraction: a
/// screen needs a ranking, not the last digit.
const RELATIVE_DECREASE: f64 = 1e-8;

/// Minimise the sum of squares of `r` from `start` within `bounds`; `r`
/// writes the residuals at a point into its buffer and returns their sum
/// of squares (infinite when it is not finite). Returns the parameters
/// and the sum.
pub fn least_squares(
    r: &mut dyn FnMut(&[f64], &mut Vec<f64>) -> f64,
    start: &[f64],
    bounds: &[(f64, f64)],
) -> (Vec<f64>, f64) {
    let k = start.len();
    assert!(
        (1..=MAX_PARAMS).contains(&k),
        "{k} parameters: the screens fit one to {MAX_PARAMS}"
    );
    let clamp = |p: &mut [f64]| {
        for (v, (lo, hi)) in p.iter_mut().zip(bounds) {
            *v = v.clamp(*lo, *hi);
        }
    };
    let mut p = start.to_vec();
    clamp(&mut p);
    let (mut res, mut shifted, mut trial) = (Vec::new(), Vec::new(), Vec::new());
    let mut f = r(&p, &mut res);
    let mut lambda = 1e-3;
    for _ in 0..ITERATIONS {
        // `res` holds the residuals at `p`: computed once, then swapped in
        // with each accepted step.
        let mut jac = vec![vec![0.0; res.len()]; k];
        for (i, col) in jac.iter_mut().enumerate() {
            let h = 1e-6 * (1.0 + p[i].abs());
            let mut q = p.clone();
            q[i] += h;
            r(&q, &mut shifted);
            for (j, v) in col.iter_mut().enumerate() {
                *v = (shifted[j] - res[j]) / h;
            }
        }
        // Fixed-size normal equations: this loop runs for every law the
        // screen tries, and allocating them measurably slowed the screen.
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let (mut g, mut a) = ([0.0; MAX_PARAMS], [[0.0; MAX_PARAMS]; MAX_PARAMS]);
        for i in 0..k {
            g[i] = dot(&jac[i], &res);
            for j in 0..k {
                a[i][j] = dot(&jac[i], &jac[j]);
            }
        }
        let mut improved = false;
        for _ in 0..TRIES {
            let mut m = a;
            for (i, row) in m.iter_mut().enumerate().take(k) {
                row[i] += lambda * row[i] + 1e-12 * (1.0 + a[0][0].abs());
            }
            let delta = solve(&m, &g, k);
            let mut q: Vec<f64> = p.iter().zip(&delta).map(|(x, d)| x - d).collect();
            clamp(&mut q);
            let fq = r(&q, &mut trial);
            if fq < f {
                let done = (f - fq) <= RELATIVE_DECREASE * f.max(1e-300);
                p = q;
                f = fq;
                std::mem::swap(&mut res, &mut trial);
                lambda = (lambda / 4.0).max(1e-9);
                improved = !done;
                break;
            }
            lambda *= 8.0;
        }
        if !improved {
            break;
        }
    }
    (p, f)
}

/// `m x = g` in the first `k` unknowns: closed form for one or two, LU
/// beyond; a component that is not finite (a singular system) is no step.
/// (One unknown needs no such guard: the damping keeps `m[0][0]`
/// positive.)
fn solve(m: &[[f64; MAX_PARAMS]; MAX_PARAMS], g: &[f64; MAX_PARAMS], k: usize) -> Vec<f64> {
    let x = match k {
        1 => return vec![g[0] / m[0][0]],
        2 => {
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            vec![
                (m[1][1] * g[0] - m[0][1] * g[1]) / det,
                (m[0][0] * g[1] - m[1][0] * g[0]) / det,
            ]
        }
        n => {
            let a = nalgebra::DMatrix::from_fn(n, n, |i, j| m[i][j]);
            let b = nalgebra::DVector::from_column_slice(&g[..n]);
            a.lu()
                .solve(&b)
                .map_or_else(|| vec![0.0; n], |x| x.iter().copied().collect())
        }
    };
    x.into_iter()
        .map(|v| if v.is_finite() { v } else { 0.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exponential decay `y = a exp(-b t) + c` fitted from far off
    /// reaches the parameters that made it, and a bound holds.
    #[test]
    fn a_three_parameter_curve_is_fitted_back_and_bounds_hold() {
        let t: Vec<f64> = (0..20).map(|i| 0.25 * i as f64).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.7 * t).exp() + 0.3).collect();
        let mut r = |p: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend(
                t.iter()
                    .zip(&y)
                    .map(|(t, y)| p[0] * (-p[1] * t).exp() + p[2] - y),
            );
            out.iter().map(|x| x * x).sum()
        };
        let wide = [(0.0, 10.0), (0.0, 10.0), (-5.0, 5.0)];
        let (p, f) = least_squares(&mut r, &[1.0, 0.2, 0.0], &wide);
        assert!(f < 1e-16, "{f}");
        for (got, want) in p.iter().zip([2.0, 0.7, 0.3]) {
            assert!((got - want).abs() < 1e-6, "{p:?}");
        }
        let (p, _) = least_squares(
            &mut r,
            &[1.0, 0.2, 0.0],
            &[(0.0, 1.5), (0.0, 10.0), (-5.0, 5.0)],
        );
        assert!(p[0] <= 1.5, "{p:?}");
    }
}
