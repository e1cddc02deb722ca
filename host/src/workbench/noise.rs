//! The noise floor: how large chi-square is for a PERFECT model, given how
//! the measurements' uncertainties were estimated.
//!
//! A residual divided by a standard error estimated from `n` trials is
//! Student-t distributed with `n - 1` degrees of freedom, not normal, so a
//! perfect model's chi-square is a sum of squared t variables (mean
//! `(n-1)/(n-3)` each: 2 for the paper's five trials), not a chi-square
//! variable. Its upper quantile has no closed form; it is estimated here by
//! Monte Carlo with a fixed seed (deterministic), and scaled by
//! `(N - k) / N` for `k` fitted parameters.

use crate::data::Dataset;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StudentT};

const DRAWS: usize = 20_000;

/// Degrees of freedom of each measured quantity's standard error.
pub fn error_dofs(data: &Dataset) -> Vec<f64> {
    data.cases
        .iter()
        .flat_map(|c| [c.u_mm_s, c.omega_body_hz])
        .flatten()
        .map(|m| f64::from(m.trials.max(2) - 1))
        .collect()
}

/// Upper `level` quantile of chi-square for a perfect model with `k`
/// fitted parameters (`None` when nothing is left to test: N <= k).
pub fn chi2_noise_floor(dofs: &[f64], k: usize, level: f64) -> Option<f64> {
    let n = dofs.len();
    if n <= k {
        return None;
    }
    let mut rng = StdRng::seed_from_u64(0x5eed);
    let dists: Vec<StudentT<f64>> = dofs
        .iter()
        .map(|&d| StudentT::new(d).expect("dof >= 1"))
        .collect();
    let mut sums: Vec<f64> = (0..DRAWS)
        .map(|_| dists.iter().map(|t| t.sample(&mut rng).powi(2)).sum())
        .collect();
    sums.sort_by(f64::total_cmp);
    let q = sums[((level * DRAWS as f64) as usize).min(DRAWS - 1)];
    Some(q * (n - k) as f64 / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn many_trials_approach_the_chi_square_quantile() {
        // 12 quantities with near-exact errors: chi2_{0.95}(12) = 21.03.
        let q = chi2_noise_floor(&[1000.0; 12], 0, 0.95).unwrap();
        assert!((q - 21.03).abs() < 0.8, "{q}");
    }

    #[test]
    fn five_trials_raise_the_floor_above_chi_square() {
        let five = chi2_noise_floor(&[4.0; 12], 0, 0.95).unwrap();
        let exact = chi2_noise_floor(&[1000.0; 12], 0, 0.95).unwrap();
        assert!(five > 1.5 * exact, "{five} vs {exact}");
        assert_eq!(chi2_noise_floor(&[4.0; 3], 3, 0.95), None);
    }
}
