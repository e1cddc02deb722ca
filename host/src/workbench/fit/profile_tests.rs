//! The profile interval against a brute-force scan of the profiled
//! chi-square, on a fit whose deviance is not quadratic (a power law's
//! exponent); the correlation of a fit linear in its parameters against
//! the covariance `(J^T J)^-1` its Jacobian gives in closed form.

use super::*;
use crate::data::{paper, Measured};
use crate::effects::correction::{Form, LocatedCorrection};
use crate::effects::place::Place;
use crate::effects::EffectInstance;
use crate::workbench::fit::free_params_of;
use crate::workbench::fit::report::strong_correlations;
use std::sync::Arc;

fn law(
    place: Place,
    feature: Option<&str>,
    form: Form,
    scale: f64,
    values: Vec<f64>,
) -> EffectInstance {
    let q = feature.map(|id| {
        crate::data::Feature::Quantity(crate::data::quantities::by_id(id).expect("a quantity"))
    });
    let c = LocatedCorrection::new(place, q, form, scale, 1.0).expect("a law that fits its place");
    EffectInstance {
        effect: Arc::new(c).into(),
        values,
    }
}

/// The paper's six cases "measured" as `model` predicts them, each with a
/// 95 % half-width of `relative` of the value: the optimum is the planted
/// values, at chi-square 0.
fn planted(model: &Model, relative: f64) -> Dataset {
    let mut data = paper();
    for c in &mut data.cases {
        let p = model.predict(c).unwrap();
        let m = |v: f64| Measured {
            mean: v,
            ci_half_width: relative * v.abs(),
            confidence: 0.95,
            trials: 5,
        };
        c.u_mm_s = Some(m(p.u_mm_s));
        c.omega_body_hz = Some(m(p.omega_body_hz));
    }
    data
}

/// The profiled chi-square on a grid of `n` values of parameter `i`
/// across `[a, b]`, each with the others refitted from several starts,
/// and where it first crosses `threshold` on each side of `v` (linear
/// interpolation between grid points).
fn scan(
    model: &Model,
    data: &Dataset,
    free: &[FreeParam],
    i: usize,
    v: f64,
    (a, b): (f64, f64),
    threshold: f64,
) -> (Option<f64>, Option<f64>) {
    let n = 241;
    let others: Vec<FreeParam> = free
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, &f)| f)
        .collect();
    let f = free[i];
    let grid: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let t = a + (b - a) * k as f64 / (n - 1) as f64;
            let mut m = model.clone();
            m.effects[f.effect].values[f.param] = t;
            let d = fit_with(&m, data, None, &others, true, Likelihood::Gaussian)
                .unwrap()
                .deviance;
            (t, d - threshold)
        })
        .collect();
    let cross = |w: &[(f64, f64)]| {
        let ((t0, d0), (t1, d1)) = (w[0], w[1]);
        t0 + (t1 - t0) * d0 / (d0 - d1)
    };
    let low = grid
        .windows(2)
        .rev()
        .find(|w| w[1].0 <= v && w[0].1 >= 0.0 && w[1].1 < 0.0)
        .map(cross);
    let high = grid
        .windows(2)
        .find(|w| w[0].0 >= v && w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(cross);
    (low, high)
}

#[test]
fn a_power_laws_profile_intervals_are_the_scans_and_asymmetric() {
    // The tail's normal resistance scaled by k (L_t/λ over 6)^p. The
    // thrust saturates in c_n, so at 200 % half-widths the chi-square is far
    // from a parabola in the parameters.
    let planted_law = law(
        Place::TailNormal,
        Some("n_waves"),
        Form::PowerLaw,
        6.0,
        vec![1.5, 1.0],
    );
    let truth = Model::base().with_effect(planted_law);
    let data = planted(&truth, 2.0);
    let start = Model::base().with_effect(law(
        Place::TailNormal,
        Some("n_waves"),
        Form::PowerLaw,
        6.0,
        vec![1.0, 0.0],
    ));
    let free = free_params_of(&start, &[0]);
    let fitted = fit_with(&start, &data, None, &free, true, Likelihood::Gaussian).unwrap();
    let (at, intervals) = profile(&fitted.model, &data, &free, Likelihood::Gaussian).unwrap();
    assert!(at.chi2 < 1e-8, "the planted optimum: {}", at.chi2);
    assert_eq!(at.scale, 1.0);
    let threshold = at.deviance + Z95 * Z95;
    for (i, p) in intervals.iter().enumerate() {
        let h = at.estimates[i].ci95.expect("identifiable");
        let (lo, hi) = bounds(&at.model, free[i]);
        let range = ((p.value - 10.0 * h).max(lo), (p.value + 10.0 * h).min(hi));
        let (low, high) = scan(&at.model, &data, &free, i, p.value, range, threshold);
        // The grid's step is h/12: its interpolation is good to a few
        // hundredths of h. An end the profile leaves open, the scan finds
        // no crossing for within the range either.
        let step = (range.1 - range.0) / 240.0;
        let agree = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() < 2.0 * step,
            (None, None) => true,
            _ => false,
        };
        assert!(
            agree(p.low, low) && agree(p.high, high),
            "{i}: profile {:?} .. {:?}, scan {low:?} .. {high:?}, h {h}",
            p.low,
            p.high
        );
    }
    let lopsided: Vec<&ProfileInterval> = intervals.iter().filter(|p| p.asymmetric).collect();
    assert!(!lopsided.is_empty(), "{intervals:?}");
    for p in lopsided
        .iter()
        .filter(|p| p.low.is_some() && p.high.is_some())
    {
        let (below, above) = (p.value - p.low.unwrap(), p.high.unwrap() - p.value);
        assert!(
            (above - below).abs() > 0.1 * (above + below) / 2.0,
            "{below} below, {above} above"
        );
    }
}

#[test]
fn a_quadratic_deviance_gives_the_covariances_interval() {
    // An added axial force enters the force balance linearly: the
    // chi-square is a parabola in it, and the profile is the covariance's.
    let truth =
        Model::base().with_effect(law(Place::LoadForce, None, Form::Constant, 1.0, vec![0.05]));
    let data = planted(&truth, 0.1);
    let free = free_params_of(&truth, &[0]);
    let (at, intervals) = profile(&truth, &data, &free, Likelihood::Gaussian).unwrap();
    let p = &intervals[0];
    let h = at.estimates[0].ci95.unwrap();
    assert!(!p.asymmetric, "{p:?}");
    assert!(
        (p.low.unwrap() - p.covariance_low.unwrap()).abs() < 0.02 * h,
        "{p:?}"
    );
    assert!(
        (p.high.unwrap() - p.covariance_high.unwrap()).abs() < 0.02 * h,
        "{p:?}"
    );
}

#[test]
fn the_correlation_of_a_linear_two_parameter_fit_is_its_jacobians() {
    // An axial force and an axial torque on the body: U and Ω_b are linear
    // in both (Stokes flow), so J is exact from unit steps and the
    // covariance is (J^T J)^-1 (chi-square 0: the scale is 1).
    let truth = Model::base()
        .with_effect(law(Place::LoadForce, None, Form::Constant, 1.0, vec![0.05]))
        .with_effect(law(
            Place::LoadTorque,
            None,
            Form::Constant,
            1.0,
            vec![0.02],
        ));
    let data = planted(&truth, 0.1);
    let free = free_params_of(&truth, &[0, 1]);
    let (at, _) = profile(&truth, &data, &free, Likelihood::Gaussian).unwrap();
    let z = |m: &Model| {
        crate::workbench::fit::normalised(m, &data.cases.iter().collect::<Vec<_>>()).unwrap()
    };
    let z0 = z(&truth);
    let column = |e: usize| {
        let mut m = truth.clone();
        m.effects[e].values[0] += 1.0;
        z(&m) - &z0
    };
    let (a, b) = (column(0), column(1));
    let (aa, bb, ab) = (a.dot(&a), b.dot(&b), a.dot(&b));
    // The inverse of [[aa, ab], [ab, bb]]: its off-diagonal over the
    // diagonal's geometric mean is -ab / sqrt(aa bb).
    let known = -ab / (aa * bb).sqrt();
    let r = at.correlation.as_ref().expect("a regular fit")[0][1];
    assert!((r - known).abs() < 1e-4, "fit {r}, closed form {known}");
    let names = vec!["force".to_string(), "torque".to_string()];
    let listed = strong_correlations(&names, at.correlation.as_ref().unwrap());
    assert_eq!(
        listed.len(),
        usize::from(known.abs() > 0.8),
        "{known}: {listed:?}"
    );
}
