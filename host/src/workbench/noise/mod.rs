//! The noise floor: how large chi-square is for a PERFECT model, given how
//! the measurements' uncertainties were estimated.
//!
//! A residual divided by a standard error estimated from `n` trials is
//! Student-t distributed with `n - 1` degrees of freedom, not normal, so a
//! perfect model's chi-square is a sum of squared t variables (mean
//! `(n-1)/(n-3)` each: 2 for the paper's five trials), not a chi-square
//! variable. Its upper quantile has no closed form (and for five trials,
//! `nu = 4`, each term has infinite variance, so no normal approximation
//! of the sum holds); it is estimated here by Monte Carlo with fixed seeds
//! (deterministic), and scaled by `(N - k) / N` for `k` fitted parameters.
//!
//! **Draws and their Monte Carlo error.** Up to [`SERIAL_SAMPLES`]
//! Student-t samples (`N` quantities x 20 000 draws: 500 quantities) the
//! draws are one stream of one seed. Beyond, the floor's relative error
//! falls as the quantities grow (the sum narrows against its size), so the
//! draws are fewer, `SERIAL_SAMPLES / N` and at least [`MIN_DRAWS`], and
//! made in parallel chunks, each from a seed of its own (the same numbers
//! on any count of threads). Measured relative standard deviation of the
//! 95 % quantile over independent seeds, `nu = 4`: 1.1 % for 12 quantities
//! and 20 000 draws (the paper's), 0.16 % for 1 000 and 20 000, 0.24 % for
//! 20 000 quantities and 2 000 draws: the fewer draws of a large dataset
//! still give a floor several times more precise than the paper's.

use crate::data::Dataset;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StudentT};

/// Draws of a floor over few quantities.
const DRAWS: usize = 20_000;
/// Student-t samples drawn as one serial stream (module docs): 500
/// quantities x `DRAWS`.
pub const SERIAL_SAMPLES: usize = 10_000_000;
/// The fewest draws of a floor over many quantities: the 95 % quantile is
/// then the 1 900th of 2 000 ordered sums.
pub const MIN_DRAWS: usize = 2_000;
/// Student-t samples per parallel chunk beyond [`SERIAL_SAMPLES`].
const CHUNK_SAMPLES: usize = 1 << 21;
const SEED: u64 = 0x5eed;

mod leave_out;
pub use leave_out::LeaveOutDraws;

// Instrumentation of the test build only (as the model's force-balance
// count): the estimates count the floors a command draws, and a test holds
// them to that count. The library keeps no state between calls.
#[cfg(test)]
thread_local! {
    static DRAWN: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many Monte Carlo floors (sets of draws) this thread has started.
#[cfg(test)]
pub fn floors_drawn_on_this_thread() -> u64 {
    DRAWN.with(std::cell::Cell::get)
}

fn count_a_floor() {
    #[cfg(test)]
    DRAWN.with(|c| c.set(c.get() + 1));
}

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
    draw_planned(dofs, level, DrawPlan::for_quantities(dofs.len()))
}

fn draw_planned(dofs: &[f64], level: f64, plan: DrawPlan) -> f64 {
    count_a_floor();
    let dists: Vec<StudentT<f64>> = dofs
        .iter()
        .map(|&d| StudentT::new(d).expect("dof >= 1"))
        .collect();
    let sums_of = |(chunk, draws): (usize, usize)| -> Vec<f64> {
        let mut rng = StdRng::seed_from_u64(SEED + chunk as u64);
        (0..draws)
            .map(|_| dists.iter().map(|t| t.sample(&mut rng).powi(2)).sum())
            .collect()
    };
    let mut sums: Vec<f64> = if plan.chunks() == 1 {
        sums_of((0, plan.draws))
    } else {
        use rayon::prelude::*;
        let parts: Vec<Vec<f64>> = (0..plan.chunks())
            .into_par_iter()
            .map(|c| (c, plan.draws_in(c)))
            .map(sums_of)
            .collect();
        parts.concat()
    };
    sums.sort_by(f64::total_cmp);
    let n = sums.len();
    sums[((level * n as f64) as usize).min(n - 1)]
}

/// How a floor over `quantities` quantities is drawn (module docs): how
/// many draws, in how many chunks of how many draws each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawPlan {
    pub draws: usize,
    pub chunk_draws: usize,
}

impl DrawPlan {
    pub fn for_quantities(quantities: usize) -> DrawPlan {
        let n = quantities.max(1);
        if n * DRAWS <= SERIAL_SAMPLES {
            return DrawPlan {
                draws: DRAWS,
                chunk_draws: DRAWS,
            };
        }
        DrawPlan {
            draws: (SERIAL_SAMPLES / n).clamp(MIN_DRAWS, DRAWS),
            chunk_draws: (CHUNK_SAMPLES / n).max(1),
        }
    }

    pub fn chunks(&self) -> usize {
        self.draws.div_ceil(self.chunk_draws)
    }

    fn draws_in(&self, chunk: usize) -> usize {
        self.chunk_draws.min(self.draws - chunk * self.chunk_draws)
    }

    /// Student-t samples of the whole floor.
    pub fn samples(&self, quantities: usize) -> usize {
        self.draws * quantities
    }
}

/// Seconds of one uncached [`chi2_noise_floor`] over `quantities`
/// quantities on this machine's cores: the Student-t samples of its
/// [`DrawPlan`] at the cost of one, timed on a small floor, spread over
/// the cores when the plan draws in chunks; for the estimates of long work.
pub fn floor_seconds(quantities: usize) -> f64 {
    let sample = [4.0; 8];
    let start = std::time::Instant::now();
    std::hint::black_box(draw_quantile(&sample, 0.95));
    let per_sample = start.elapsed().as_secs_f64() / (sample.len() * DRAWS) as f64;
    let plan = DrawPlan::for_quantities(quantities);
    let parallel = plan.chunks().min(rayon::current_num_threads()).max(1);
    per_sample * plan.samples(quantities) as f64 / parallel as f64
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

    #[test]
    fn few_quantities_draw_one_stream_and_many_draw_fewer_in_chunks() {
        let paper = DrawPlan::for_quantities(12);
        assert_eq!((paper.draws, paper.chunks()), (DRAWS, 1));
        assert_eq!(DrawPlan::for_quantities(500).chunks(), 1);
        let big = DrawPlan::for_quantities(20_000);
        assert_eq!(big.draws, MIN_DRAWS);
        assert!(big.chunks() > 1, "{big:?}");
        // The chunks cover the draws exactly.
        let covered: usize = (0..big.chunks()).map(|c| big.draws_in(c)).sum();
        assert_eq!(covered, big.draws);
        // Samples stay bounded as the quantities grow: ten times the
        // serial stream's at most, at the 20 000 quantities of 10 000 cases.
        for n in [501, 2_000, 5_000, 20_000] {
            let s = DrawPlan::for_quantities(n).samples(n);
            assert!(s <= 4 * SERIAL_SAMPLES, "{n}: {s}");
        }
    }

    #[test]
    fn chunked_floors_are_deterministic_and_agree_with_one_stream() {
        // A small floor drawn as a large one is (chunks of 3 000 draws):
        // the same number twice, and within the Monte Carlo error of the one
        // stream (relative standard deviation 1.1 % each at 12 quantities
        // and 20 000 draws; 6 % is about four of their difference's).
        let dofs = [4.0; 12];
        let chunked = DrawPlan {
            draws: DRAWS,
            chunk_draws: 3_000,
        };
        let a = draw_planned(&dofs, 0.95, chunked);
        assert_eq!(a.to_bits(), draw_planned(&dofs, 0.95, chunked).to_bits());
        let serial = draw_quantile(&dofs, 0.95);
        assert_ne!(a.to_bits(), serial.to_bits(), "other seeds, other draws");
        assert!((a / serial - 1.0).abs() < 0.06, "{a} vs {serial}");
        // One chunk is the one stream.
        let one = DrawPlan {
            draws: DRAWS,
            chunk_draws: DRAWS,
        };
        assert_eq!(draw_planned(&dofs, 0.95, one).to_bits(), serial.to_bits());
    }

    #[test]
    fn a_floor_left_out_of_shared_draws_is_the_floor_of_the_quantities_left() {
        use std::collections::BTreeMap;
        let (four, thirty) = (4f64.to_bits(), 30f64.to_bits());
        let all = BTreeMap::from([(four, 10), (thirty, 2)]);
        let spare = BTreeMap::from([(four, 1), (thirty, 1)]);
        let draws = LeaveOutDraws::new(&all, &spare);
        // Nothing left out: all 12 quantities, against their own floor
        // (other draws: relative standard deviation about 1 % each).
        let mut dofs = vec![4.0; 10];
        dofs.extend([30.0; 2]);
        let whole = draws.floor(&BTreeMap::new(), 0, 0.95).unwrap();
        let own = chi2_noise_floor(&dofs, 0, 0.95).unwrap();
        assert!((whole / own - 1.0).abs() < 0.06, "{whole} vs {own}");
        // One of each left out: the floor of the ten left, scaled for k.
        let out = BTreeMap::from([(four, 1), (thirty, 1)]);
        let left = draws.floor(&out, 2, 0.95).unwrap();
        let mut rest = vec![4.0; 9];
        rest.push(30.0);
        let own = chi2_noise_floor(&rest, 2, 0.95).unwrap();
        assert!((left / own - 1.0).abs() < 0.06, "{left} vs {own}");
        assert!(left < whole, "fewer quantities, a lower floor");
        // The same draws, the same number; more left out than kept: none.
        assert_eq!(
            draws.floor(&out, 2, 0.95).unwrap().to_bits(),
            left.to_bits()
        );
        assert_eq!(draws.floor(&BTreeMap::from([(four, 2)]), 0, 0.95), None);
        assert_eq!(draws.floor(&out, 10, 0.95), None, "nothing left to test");
    }
}
