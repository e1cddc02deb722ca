//! Statistics of the comparison: Student-t confidence intervals of trial
//! means, relative errors, the reduced chi-square of a fit, and Spearman's
//! rank correlation (does a residual trend with a feature; are two features
//! the same ordering of the cases).
//!
//! References: M. Abramowitz and I. A. Stegun, Handbook of Mathematical
//! Functions (1964), 26.7.5 (Student-t quantile for many degrees of freedom);
//! C. Spearman, Am. J. Psychol. 15 (1904) 72 (rank correlation).

use statrs::distribution::{ContinuousCDF, StudentsT};

/// Above this many degrees of freedom the quantile comes from the
/// Cornish-Fisher expansion around the normal quantile: statrs' inverse CDF
/// iterates on the incomplete beta function and, for 1e8 degrees of freedom,
/// never returns. At 1e4 the expansion's next term is below 1e-12.
const T_EXPANSION_DOF: f64 = 1e4;

/// Two-sided Student-t quantile `t_{(1+confidence)/2, trials-1}` (2.776 for
/// the paper's 95 % with five trials). Terminates for every `trials`.
pub fn student_t_quantile(confidence: f64, trials: u32) -> f64 {
    // Every residual's standard error asks for this quantile, so a fit asks
    // millions of times for the few (level, trials) pairs of its dataset;
    // statrs' inverse CDF iterates on the incomplete beta function each
    // time (half the CPU time of `audit`), so the answers are remembered
    // per thread (no lock between rayon's workers).
    thread_local! {
        static KNOWN: std::cell::RefCell<std::collections::HashMap<(u64, u32), f64>> =
            std::cell::RefCell::new(std::collections::HashMap::new());
    }
    let key = (confidence.to_bits(), trials);
    if let Some(t) = KNOWN.with(|k| k.borrow().get(&key).copied()) {
        return t;
    }
    let t = student_t_quantile_uncached(confidence, trials);
    KNOWN.with(|k| k.borrow_mut().insert(key, t));
    t
}

fn student_t_quantile_uncached(confidence: f64, trials: u32) -> f64 {
    let dof = f64::from(trials.max(2) - 1);
    let p = 0.5 * (1.0 + confidence);
    if dof > T_EXPANSION_DOF {
        return t_quantile_large_dof(p, dof);
    }
    let t = StudentsT::new(0.0, 1.0, dof).expect("dof >= 1 is a valid Student-t");
    t.inverse_cdf(p)
}

/// `t_p(nu) = z + (z^3 + z) / (4 nu) + (5 z^5 + 16 z^3 + 3 z) / (96 nu^2)`
/// (Abramowitz & Stegun 26.7.5) with `z` the normal quantile.
fn t_quantile_large_dof(p: f64, dof: f64) -> f64 {
    use statrs::distribution::Normal;
    let z = Normal::new(0.0, 1.0).expect("unit normal").inverse_cdf(p);
    let (z3, z5) = (z.powi(3), z.powi(5));
    z + (z3 + z) / (4.0 * dof) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * dof * dof)
}

/// Mean and confidence half-width of raw trials (at least two values).
pub fn mean_and_ci(values: &[f64], confidence: f64) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let half = student_t_quantile(confidence, values.len() as u32) * (var / n).sqrt();
    (mean, half)
}

/// One compared quantity: a prediction against a measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residual {
    pub predicted: f64,
    pub observed: f64,
    /// Standard error of the observed mean.
    pub sigma: f64,
}

impl Residual {
    pub fn relative_error(&self) -> f64 {
        (self.predicted - self.observed) / self.observed
    }
    /// Residual in standard errors.
    pub fn normalised(&self) -> f64 {
        (self.predicted - self.observed) / self.sigma
    }
}

/// Summary of a set of residuals.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FitSummary {
    /// Mean absolute relative error over all compared quantities (0 when
    /// there is nothing to compare, `n = 0`: never NaN).
    pub mare: f64,
    pub max_abs_rel_err: f64,
    /// Chi-square over (n - k); `None` when n - k <= 0.
    pub chi2_reduced: Option<f64>,
    pub chi2: f64,
    pub n: usize,
    pub free_params: usize,
}

impl FitSummary {
    /// Degrees of freedom of the reduced chi-square, `n - k` (`None` when
    /// not positive).
    pub fn dof(&self) -> Option<usize> {
        self.n.checked_sub(self.free_params).filter(|d| *d > 0)
    }
}

/// The share of `before`'s excess chi-square (above the noise floor
/// `floor_chi2`, not reduced) that `after` removes, at most 1; `None` when
/// `before` is already at the floor. The one definition of "removes X % of
/// the excess" used by every command and the page.
pub fn excess_removed(before_chi2: f64, after_chi2: f64, floor_chi2: Option<f64>) -> Option<f64> {
    let excess = before_chi2 - floor_chi2?;
    (excess > 0.0).then(|| ((before_chi2 - after_chi2) / excess).min(1.0))
}

/// The summary statistics of `residuals` judged with `free_params` fitted
/// parameters: MARE and max |relative error| over every compared quantity,
/// chi-square and its reduced value over `n - k` degrees of freedom.
pub fn summarise(residuals: &[Residual], free_params: usize) -> FitSummary {
    let n = residuals.len();
    let rel: Vec<f64> = residuals.iter().map(|r| r.relative_error().abs()).collect();
    let chi2: f64 = residuals.iter().map(|r| r.normalised().powi(2)).sum();
    let dof = n as i64 - free_params as i64;
    FitSummary {
        mare: if n == 0 {
            0.0
        } else {
            rel.iter().sum::<f64>() / n as f64
        },
        max_abs_rel_err: rel.iter().copied().fold(0.0, f64::max),
        chi2_reduced: (dof > 0).then(|| chi2 / dof as f64),
        chi2,
        n,
        free_params,
    }
}

/// Ranks from 1, ties sharing their mean rank.
pub fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let mean_rank = (i + j) as f64 / 2.0 + 1.0;
        for &k in &idx[i..=j] {
            r[k] = mean_rank;
        }
        i = j + 1;
    }
    r
}

/// Spearman's rank correlation of `x` and `y` (Pearson's on the ranks);
/// `None` when either takes one value only, so no ordering exists.
pub fn spearman_rho(x: &[f64], y: &[f64]) -> Option<f64> {
    let (rx, ry) = (ranks(x), ranks(y));
    // Ties keep the ranks' mean at (n + 1) / 2.
    let mean = (x.len() as f64 + 1.0) / 2.0;
    let (mut cov, mut vx, mut vy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(&ry) {
        cov += (a - mean) * (b - mean);
        vx += (a - mean) * (a - mean);
        vy += (b - mean) * (b - mean);
    }
    (vx > 0.0 && vy > 0.0).then(|| cov / (vx * vy).sqrt())
}

/// The two-sided p-value of Spearman's rho against no association, from the
/// t approximation `rho sqrt((n-2)/(1-rho^2))` on `n - 2` degrees of
/// freedom (1 when there is no ordering or fewer than 3 points).
pub fn spearman_p(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let Some(rho) = spearman_rho(x, y).filter(|_| n > 2.0) else {
        return 1.0;
    };
    let rho = rho.clamp(-0.999_999, 0.999_999);
    let t = rho * ((n - 2.0) / (1.0 - rho * rho)).sqrt();
    let dist = StudentsT::new(0.0, 1.0, n - 2.0).expect("n > 2");
    2.0 * dist.sf(t.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_share_ties_and_spearman_sees_a_monotone_trend() {
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), vec![3.5, 1.0, 3.5, 2.0]);
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| v.powi(3)).collect();
        assert!(spearman_p(&x, &y) < 1e-6);
        assert_eq!(spearman_rho(&x, &y), Some(1.0));
        let down: Vec<f64> = x.iter().map(|v| -v.exp()).collect();
        assert_eq!(spearman_rho(&x, &down), Some(-1.0));
        assert_eq!(spearman_rho(&x, &[2.0; 20]), None, "no ordering");
    }

    #[test]
    fn student_t_matches_tables() {
        assert!((student_t_quantile(0.95, 5) - 2.776445).abs() < 1e-5);
        assert!((student_t_quantile(0.95, 2) - 12.706205).abs() < 1e-4);
        assert!((student_t_quantile(0.99, 11) - 3.169273).abs() < 1e-5);
    }

    #[test]
    fn student_t_terminates_and_matches_across_the_switch() {
        // Both branches at the switch agree, and huge trial counts (which
        // used to hang) give the normal quantile.
        let (p, nu) = (0.975, T_EXPANSION_DOF);
        let exact = StudentsT::new(0.0, 1.0, nu).unwrap().inverse_cdf(p);
        assert!((exact - t_quantile_large_dof(p, nu)).abs() < 1e-9);
        assert!((student_t_quantile(0.95, u32::MAX) - 1.959964).abs() < 1e-5);
        assert!((student_t_quantile(0.95, 100_000_000) - 1.959964).abs() < 1e-5);
    }

    #[test]
    fn ci_of_known_trials() {
        let (m, h) = mean_and_ci(&[1.0, 2.0, 3.0, 4.0, 5.0], 0.95);
        assert!((m - 3.0).abs() < 1e-15);
        // s = sqrt(2.5), se = s / sqrt(5)
        assert!((h - 2.776445 * (2.5f64 / 5.0).sqrt()).abs() < 1e-5);
    }

    #[test]
    fn reduced_chi_square_guards_its_degrees_of_freedom() {
        let r = [Residual {
            predicted: 2.0,
            observed: 1.0,
            sigma: 0.5,
        }; 3];
        let s = summarise(&r, 1);
        assert_eq!(s.chi2, 12.0);
        assert_eq!(s.chi2_reduced, Some(6.0));
        assert_eq!(summarise(&r, 3).chi2_reduced, None);
        assert!((s.mare - 1.0).abs() < 1e-15);
        assert_eq!(s.dof(), Some(2));
        assert_eq!(summarise(&r, 3).dof(), None);
    }

    #[test]
    fn the_excess_removed_is_a_share_of_what_lies_above_the_floor() {
        // 100 above a floor of 10: falling to 55 removes half the excess
        assert_eq!(excess_removed(110.0, 60.0, Some(10.0)), Some(0.5));
        // below the floor it is all removed, not more
        assert_eq!(excess_removed(110.0, 1.0, Some(10.0)), Some(1.0));
        // a rise removes a negative share
        assert_eq!(excess_removed(110.0, 210.0, Some(10.0)), Some(-1.0));
        assert_eq!(excess_removed(5.0, 1.0, Some(10.0)), None);
        assert_eq!(excess_removed(5.0, 1.0, None), None);
    }
}
