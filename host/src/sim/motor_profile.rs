//! The robot's motor from the observed tail rates, with profile-likelihood
//! intervals. At steady state a DC motor at terminal voltage `V` meets the
//! tail's load (`tau_0 + c w`, [`Hydro`]) where
//!
//! `k (V - k w) / R = b w + tau_c + tau_0 + c w`,
//!
//! so the data see only the stall torque `T_s = k V / R - tau_c` and the
//! slope `s = k² / R + b`. With `R` and `V` known that fixes `k` (given
//! `tau_c`) and `b`; `k` and the Coulomb friction `tau_c` enter only as
//! `k V / R - tau_c`, so `tau_c` is not identifiable from rates at one
//! voltage and stays an assumption (the calibration reports how much `k`
//! moves with it).
//!
//! The fit minimises the squared relative misfit of the predicted tail rate
//! `f` (lab frame, `(w + Omega_b(w)) / 2 pi`), the quantity observed, over
//! `(k, b)` with `b >= 0`. Intervals are profile-likelihood intervals
//! (Venzon & Moolgavkar 1988; Bates & Watts 1988, sec. 6.1): a value of one
//! parameter is inside when the residual sum of squares, minimised over the
//! other, stays below `RSS_min (1 + F(1, n - 2; level) / (n - 2))`. Unlike a
//! linearised interval they follow the misfit's real shape and respect the
//! physical bound `b >= 0`. The residual scale comes from the misfit
//! itself: with a model error larger than the measurement error (the case
//! for the paper's tails) the interval says how well the data pin the motor
//! *given* that misfit.
//!
//! The minimisations are 1-D (a log grid, then golden-section refinement):
//! hand-written because the nuisance parameter must stay inside `[0, inf)`
//! and the grid also finds where the profile crosses the threshold, which a
//! general optimiser crate would not give.

use super::hydro::Hydro;
use statrs::distribution::{ContinuousCDF, FisherSnedecor};
use std::f64::consts::TAU;

/// What the calibration takes as known.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Assumed {
    pub resistance_ohm: f64,
    /// Mean motor voltage while the tails were filmed (V).
    pub volts: f64,
    pub coulomb_n_m: f64,
}

/// One observed case: its load and its tail rate (Hz).
#[derive(Debug, Clone)]
pub struct Observed {
    pub hydro: Hydro,
    pub f_obs_hz: f64,
}

/// A best value with its profile interval; `None` ends are unbounded within
/// the search range; `lo_at_bound` marks a lower end at the physical bound 0.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Interval {
    pub best: f64,
    pub lo: f64,
    pub hi: Option<f64>,
    pub lo_at_bound: bool,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Calibration {
    pub assumed: Assumed,
    pub level: f64,
    pub k_n_m_per_a: Interval,
    pub b_n_m_s: Interval,
    /// RMS relative error of `f` at the best `(k, b)`.
    pub rms_f: f64,
    /// `k` at the best fit if `tau_c` were 0 or twice the assumed value.
    pub k_if_coulomb_0_and_2x: (f64, f64),
}

/// Search ranges, far outside any 6 mm motor, so that an interval end at
/// the range's edge means "unbounded".
const K_RANGE: (f64, f64) = (1e-6, 1e-1);
const B_RANGE: (f64, f64) = (1e-10, 1e-1);
const GRID: usize = 240;

impl Observed {
    /// Predicted lab-frame tail rate (Hz) under stall torque `stall` and slope `slope`.
    pub fn f_hz(&self, stall: f64, slope: f64) -> f64 {
        let h = &self.hydro;
        let w = ((stall - h.tau0_n_m) / (h.damping_n_m_s + slope)).max(0.0);
        (w + h.v0[3] + h.dv[3] * w) / TAU
    }
}

/// Squared relative misfit of `f` for motor `(k, b)`.
pub fn rss(cases: &[Observed], a: &Assumed, k: f64, b: f64) -> f64 {
    let stall = k * a.volts / a.resistance_ohm - a.coulomb_n_m;
    let slope = k * k / a.resistance_ohm + b;
    cases
        .iter()
        .map(|c| (c.f_hz(stall, slope) / c.f_obs_hz - 1.0).powi(2))
        .sum()
}

/// Minimum of `g` over `[lo, hi]` on a log grid (plus `lo` itself), refined
/// by golden section around the best grid point: `(x, g(x))`.
fn minimise(g: impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    let grid = log_grid(lo, hi);
    let (i, _) = grid
        .iter()
        .map(|&x| g(x))
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |best, (i, v)| {
                if v < best.1 {
                    (i, v)
                } else {
                    best
                }
            },
        );
    let (mut a, mut d) = (grid[i.saturating_sub(1)], grid[(i + 1).min(GRID - 1)]);
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (b, c) = (d - r * (d - a), a + r * (d - a));
        if g(b) <= g(c) {
            d = c;
        } else {
            a = b;
        }
    }
    let x = 0.5 * (a + d);
    (x, g(x))
}

fn log_grid(lo: f64, hi: f64) -> Vec<f64> {
    let step = (hi / lo).ln() / (GRID - 1) as f64;
    (0..GRID).map(|i| lo * (step * i as f64).exp()).collect()
}

/// Where `g` (a profile) crosses `limit` between `inside` (below) and
/// `outside` (above), by bisection in log space.
fn crossing(g: &impl Fn(f64) -> f64, limit: f64, mut inside: f64, mut outside: f64) -> f64 {
    for _ in 0..60 {
        let mid = (inside * outside).sqrt();
        if g(mid) <= limit {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    (inside * outside).sqrt()
}

/// Profile interval of one parameter: `profile` is the minimised RSS at a
/// value, `best` the joint optimum, `range` the search range.
fn interval(profile: impl Fn(f64) -> f64, best: f64, limit: f64, range: (f64, f64)) -> Interval {
    let grid = log_grid(range.0, range.1);
    let below = grid
        .iter()
        .rev()
        .copied()
        .find(|&x| x < best && profile(x) > limit);
    let above = grid
        .iter()
        .copied()
        .find(|&x| x > best && profile(x) > limit);
    Interval {
        best,
        lo: below.map_or(0.0, |x| crossing(&profile, limit, best, x)),
        hi: above.map(|x| crossing(&profile, limit, best, x)),
        lo_at_bound: below.is_none(),
    }
}

/// `(k, b)` minimising [`rss`] with `b >= 0`; the RSS there.
fn best_fit(cases: &[Observed], a: &Assumed) -> (f64, f64, f64) {
    let profile_k = |k: f64| minimise(|b| rss(cases, a, k, b), B_RANGE.0, B_RANGE.1);
    let (k, _) = minimise(|k| profile_k(k).1, K_RANGE.0, K_RANGE.1);
    let (b, r) = profile_k(k);
    // b at the grid's floor means the bound b = 0: check it directly.
    if rss(cases, a, k, 0.0) <= r {
        return (k, 0.0, rss(cases, a, k, 0.0));
    }
    (k, b, r)
}

/// Calibrates `(k, b)` on `cases` at confidence `level` (e.g. 0.95).
pub fn calibrate(cases: &[Observed], assumed: Assumed, level: f64) -> Option<Calibration> {
    let n = cases.len();
    if n < 3 {
        return None;
    }
    let (k, b, rss_min) = best_fit(cases, &assumed);
    let dof = (n - 2) as f64;
    let f = FisherSnedecor::new(1.0, dof).ok()?.inverse_cdf(level);
    let limit = rss_min * (1.0 + f / dof);
    let a = &assumed;
    let k_iv = interval(
        |k| {
            minimise(|b| rss(cases, a, k, b), B_RANGE.0, B_RANGE.1)
                .1
                .min(rss(cases, a, k, 0.0))
        },
        k,
        limit,
        K_RANGE,
    );
    let b_iv = interval(
        |b| minimise(|k| rss(cases, a, k, b), K_RANGE.0, K_RANGE.1).1,
        b,
        limit,
        B_RANGE,
    );
    let k_with = |coulomb_n_m: f64| {
        let a = Assumed {
            coulomb_n_m,
            ..assumed
        };
        best_fit(cases, &a).0
    };
    Some(Calibration {
        assumed,
        level,
        k_n_m_per_a: k_iv,
        b_n_m_s: b_iv,
        rms_f: (rss_min / n as f64).sqrt(),
        k_if_coulomb_0_and_2x: (k_with(0.0), k_with(2.0 * assumed.coulomb_n_m)),
    })
}

#[cfg(test)]
#[path = "motor_profile_tests.rs"]
mod tests;
