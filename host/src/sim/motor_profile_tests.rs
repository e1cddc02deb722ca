//! The calibration recovers a known motor from rates synthesised by the
//! same steady balance with noise, and its intervals behave.

use super::*;
use crate::data::paper;
use crate::sim::default_robot;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

const ASSUMED: Assumed = Assumed {
    resistance_ohm: 7.0,
    volts: 3.0,
    coulomb_n_m: 1.2e-5,
};

/// The paper's six tails with `f` from motor `(k, b)`, times `1 + noise`.
fn synthetic(k: f64, b: f64, noise: f64, seed: u64) -> Vec<Observed> {
    let robot = default_robot();
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let n = Normal::new(0.0, noise).unwrap();
    let a = &ASSUMED;
    let stall = k * a.volts / a.resistance_ohm - a.coulomb_n_m;
    let slope = k * k / a.resistance_ohm + b;
    paper()
        .cases
        .iter()
        .map(|c| {
            let hydro = Hydro::new(&robot.model, c).unwrap();
            let mut o = Observed {
                hydro,
                f_obs_hz: 1.0,
            };
            o.f_obs_hz = o.f_hz(stall, slope) * (1.0 + n.sample(&mut rng));
            o
        })
        .collect()
}

fn contains(iv: &Interval, x: f64) -> bool {
    x >= iv.lo && iv.hi.is_none_or(|h| x <= h)
}

#[test]
fn recovers_a_known_motor_exactly_without_noise() {
    let (k, b) = (1.3e-3, 4e-5);
    let c = calibrate(&synthetic(k, b, 0.0, 1), ASSUMED, 0.95).unwrap();
    assert!(c.rms_f < 1e-6, "{c:?}");
    assert!((c.k_n_m_per_a.best / k - 1.0).abs() < 1e-4, "{c:?}");
    assert!((c.b_n_m_s.best / b - 1.0).abs() < 1e-4, "{c:?}");
}

#[test]
fn recovers_a_known_motor_from_noisy_rates_inside_its_intervals() {
    // 5 % noise on f, twenty draws: the 95 % intervals hold the truth in
    // most of them (a profile interval on six points is approximate, so
    // allow a few misses), and they are finite and ordered.
    let (k, b) = (1.5e-3, 6e-5);
    let mut held = 0;
    for seed in 0..20 {
        let c = calibrate(&synthetic(k, b, 0.05, seed), ASSUMED, 0.95).unwrap();
        for iv in [&c.k_n_m_per_a, &c.b_n_m_s] {
            assert!(
                iv.lo <= iv.best && iv.hi.is_none_or(|h| iv.best <= h),
                "{iv:?}"
            );
        }
        if contains(&c.k_n_m_per_a, k) && contains(&c.b_n_m_s, b) {
            held += 1;
        }
        assert!(
            (c.k_n_m_per_a.best / k - 1.0).abs() < 0.2,
            "seed {seed}: {c:?}"
        );
    }
    assert!(
        held >= 16,
        "truth inside both intervals in {held} of 20 draws"
    );
}

#[test]
fn intervals_widen_with_noise() {
    let (k, b) = (1.5e-3, 6e-5);
    let width = |noise| {
        let c = calibrate(&synthetic(k, b, noise, 7), ASSUMED, 0.95).unwrap();
        c.k_n_m_per_a.hi.unwrap() - c.k_n_m_per_a.lo
    };
    assert!(width(0.01) < width(0.1), "{} {}", width(0.01), width(0.1));
}

#[test]
fn a_frictionless_motor_puts_b_at_its_bound() {
    // b = 0: the best b sits on the bound and the interval's lower end is 0.
    let c = calibrate(&synthetic(1.5e-3, 0.0, 0.0, 3), ASSUMED, 0.95).unwrap();
    assert!(c.b_n_m_s.best < 1e-9, "{c:?}");
    assert!(c.b_n_m_s.lo_at_bound, "{c:?}");
}

#[test]
fn coulomb_friction_moves_k_along_the_stall_torque() {
    // Rates at one voltage fix k V / R - tau_c: k shifts by tau_c R / V.
    let c = calibrate(&synthetic(1.5e-3, 6e-5, 0.0, 1), ASSUMED, 0.95).unwrap();
    let (k0, k2) = c.k_if_coulomb_0_and_2x;
    let shift = ASSUMED.coulomb_n_m * ASSUMED.resistance_ohm / ASSUMED.volts;
    assert!(
        (c.k_n_m_per_a.best - k0 - shift).abs() < 0.02 * shift,
        "{c:?}"
    );
    assert!(
        (k2 - c.k_n_m_per_a.best - shift).abs() < 0.02 * shift,
        "{c:?}"
    );
}
