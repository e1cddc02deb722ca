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
    Some(perfect_quantile(dofs, level) * (n - k) as f64 / n as f64)
}

/// The Monte Carlo quantile of [`chi2_noise_floor`] before its `k`
/// scaling, remembered for the process by its exact inputs (the dofs in
/// order and the level: the same draws give the same number, so a result
/// never depends on what ran before). One costs `DRAWS x N` Student-t
/// samples, 4e8 for 10 000 cases: an audit asks for the same one for
/// every `k` and again in each of its checks, which had made the floors
/// most of an audit's time at that size.
fn perfect_quantile(dofs: &[f64], level: f64) -> f64 {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    type Key = (Vec<u64>, u64);
    static MEMO: OnceLock<Mutex<HashMap<Key, f64>>> = OnceLock::new();
    let key = (
        dofs.iter().map(|d| d.to_bits()).collect::<Vec<u64>>(),
        level.to_bits(),
    );
    let memo = MEMO.get_or_init(Default::default);
    if let Some(q) = memo.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return *q;
    }
    let q = draw_quantile(dofs, level);
    let mut m = memo.lock().unwrap_or_else(|e| e.into_inner());
    // A handful of datasets per process; bounded all the same.
    if m.len() >= 64 {
        m.clear();
    }
    m.insert(key, q);
    q
}

fn draw_quantile(dofs: &[f64], level: f64) -> f64 {
    let mut rng = StdRng::seed_from_u64(0x5eed);
    let dists: Vec<StudentT<f64>> = dofs
        .iter()
        .map(|&d| StudentT::new(d).expect("dof >= 1"))
        .collect();
    let mut sums: Vec<f64> = (0..DRAWS)
        .map(|_| dists.iter().map(|t| t.sample(&mut rng).powi(2)).sum())
        .collect();
    sums.sort_by(f64::total_cmp);
    sums[((level * DRAWS as f64) as usize).min(DRAWS - 1)]
}

/// Seconds of one uncached [`chi2_noise_floor`] over `quantities`
/// quantities on this machine (timed on a few, scaled: it is linear in
/// them); for the estimates of long work.
pub fn floor_seconds(quantities: usize) -> f64 {
    let sample = [4.0; 8];
    let start = std::time::Instant::now();
    std::hint::black_box(draw_quantile(&sample, 0.95));
    start.elapsed().as_secs_f64() * quantities as f64 / sample.len() as f64
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
