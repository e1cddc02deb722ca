//! A model's curve through its own markers in the paper's Fig. 4: the
//! model evaluated densely between the outer measured cases of one
//! amplitude group (never beyond them: no tail was built there), against
//! the number of waves `N_lambda`. A group of one case has no curve.
//!
//! The paper kept the wire's chord length `ell` fixed and varied the
//! wavelength; the recorded cases do not share one `ell` exactly (see
//! `swimbot audit`), nor one tail rate `f`, nor one observed speed (which
//! the paper's back-flow, eq. 9, reads). So between two neighbouring cases
//! every input that differs (chord, rate, observed speed and body rate,
//! setup) is interpolated piecewise-linearly in `N_lambda`, the figure's
//! axis, and held at the end case's value beyond them; the helix follows
//! from `N_lambda` and the chord: `lambda = sqrt((ell / N_lambda)^2 - (2 pi
//! B_o)^2)`, `L_t = N_lambda lambda`. At a measured `N_lambda` the curve's
//! case *is* the measured case, so the curve passes through the model's
//! marker there; and the curve is a function of `N_lambda` (interpolating
//! in `lambda` instead folds back on itself beyond the cases when the chord
//! differs between them).

use crate::data::quantities::chord_length_mm;
use crate::data::{Case, Measured};
use crate::model::{Model, Prediction};
use std::f64::consts::PI;

/// Points sampled across a group (plus the cases' own).
const SAMPLES: usize = 160;
/// How far the curve's wavelength may leave the cases' range (fraction).
const LAMBDA_REACH: f64 = 0.1;

/// The scalar inputs interpolated between cases (the helix follows from
/// the chord and `N_lambda`; the observations are interpolated apart).
const SCALARS: &[fn(&mut Case) -> &mut f64] = &[
    |c| &mut c.amplitude_mm,
    |c| &mut c.wire_diameter_mm,
    |c| &mut c.frequency_hz,
    |c| &mut c.channel_diameter_mm,
    |c| &mut c.channel_length_mm,
    |c| &mut c.viscosity_pa_s,
    |c| &mut c.density_kg_m3,
    |c| &mut c.body_diameter_mm,
    |c| &mut c.body_length_mm,
    |c| &mut c.coupler_diameter_mm,
    |c| &mut c.coupler_length_mm,
];

fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

fn lerp_measured(a: Option<Measured>, b: Option<Measured>, t: f64) -> Option<Measured> {
    match (a, b) {
        (Some(a), Some(b)) => Some(Measured {
            mean: lerp(a.mean, b.mean, t),
            ci_half_width: lerp(a.ci_half_width, b.ci_half_width, t),
            ..if t < 0.5 { a } else { b }
        }),
        _ => None,
    }
}

/// `case` with its helix reshaped to `n_waves` at chord `chord_mm` (its
/// amplitude kept); `None` when no helix of that chord has so many waves.
fn reshaped(case: &Case, n_waves: f64, chord_mm: f64) -> Option<Case> {
    let lambda_sq = (chord_mm / n_waves).powi(2) - (2.0 * PI * case.amplitude_mm).powi(2);
    (lambda_sq > 0.0 && n_waves > 0.0).then(|| {
        let lambda = lambda_sq.sqrt();
        Case {
            wavelength_mm: lambda,
            tail_length_mm: n_waves * lambda,
            ..case.clone()
        }
    })
}

/// The group's cases as curve nodes, sorted by `N_lambda`, one per value
/// (cases sharing an `N_lambda` are merged into their mean, so the curve
/// passes between them).
fn nodes(cases: &[&Case]) -> Vec<Case> {
    let mut sorted: Vec<&Case> = cases.to_vec();
    sorted.sort_by(|a, b| a.n_waves().total_cmp(&b.n_waves()));
    let mut out: Vec<(Case, usize)> = Vec::new();
    for c in sorted {
        match out.last_mut() {
            Some((n, k)) if (n.n_waves() - c.n_waves()).abs() <= 1e-9 * c.n_waves() => {
                *k += 1;
                let t = 1.0 / *k as f64;
                if let Some(m) = between(n, c, t) {
                    *n = m;
                }
            }
            _ => out.push(((*c).clone(), 1)),
        }
    }
    out.into_iter().map(|(c, _)| c).collect()
}

/// The case a fraction `t` of the way from `a` to `b` in `N_lambda` (at
/// `t = 0` exactly `a`, at `t = 1` exactly `b`).
fn between(a: &Case, b: &Case, t: f64) -> Option<Case> {
    if t == 0.0 {
        return Some(a.clone());
    }
    if t == 1.0 {
        return Some(b.clone());
    }
    let mut c = if t < 0.5 { a.clone() } else { b.clone() };
    let (mut a2, mut b2) = (a.clone(), b.clone());
    for field in SCALARS {
        *field(&mut c) = lerp(*field(&mut a2), *field(&mut b2), t);
    }
    c.u_mm_s = lerp_measured(a.u_mm_s, b.u_mm_s, t);
    c.omega_body_hz = lerp_measured(a.omega_body_hz, b.omega_body_hz, t);
    let n = lerp(a.n_waves(), b.n_waves(), t);
    reshaped(&c, n, lerp(chord_length_mm(a), chord_length_mm(b), t))
}

/// The curve's case at `n_waves`: interpolated between the nodes, the end
/// node's inputs (with its chord) beyond them.
pub fn case_at(nodes: &[Case], n_waves: f64) -> Option<Case> {
    let first = &nodes[0];
    let last = &nodes[nodes.len() - 1];
    let hold = |c: &Case| {
        if n_waves == c.n_waves() {
            Some(c.clone())
        } else {
            reshaped(c, n_waves, chord_length_mm(c))
        }
    };
    if n_waves <= first.n_waves() {
        return hold(first);
    }
    if n_waves >= last.n_waves() {
        return hold(last);
    }
    let i = nodes
        .windows(2)
        .position(|w| n_waves <= w[1].n_waves())
        .expect("inside the nodes' range");
    let (a, b) = (&nodes[i], &nodes[i + 1]);
    between(a, b, (n_waves - a.n_waves()) / (b.n_waves() - a.n_waves()))
}

/// `(N_lambda, ratio)` of `model` along the group's curve, in increasing
/// `N_lambda`; the cases' own `N_lambda` are among the samples, so the
/// line passes through the markers, not near them. Points where no helix
/// fits or the model fails are left out.
pub fn model_curve(
    model: &Model,
    cases: &[&Case],
    ratio_of: fn(&Prediction) -> f64,
) -> Vec<(f64, f64, f64)> {
    let nodes = nodes(cases);
    if nodes.len() < 2 {
        return Vec::new();
    }
    let (lo, hi) = (nodes[0].n_waves(), nodes[nodes.len() - 1].n_waves());
    // Beyond the cases, a held chord near its tightest helix (lambda -> 0)
    // is no tail anyone built: keep lambda near the measured range.
    let lambda_min = nodes
        .iter()
        .map(|c| c.wavelength_mm)
        .fold(f64::INFINITY, f64::min);
    let lambda_max = nodes.iter().map(|c| c.wavelength_mm).fold(0.0, f64::max);
    let plausible = |c: &Case| {
        c.wavelength_mm >= (1.0 - LAMBDA_REACH) * lambda_min
            && c.wavelength_mm <= (1.0 + LAMBDA_REACH) * lambda_max
    };
    // interior samples, and the nodes themselves as the ends
    let mut xs: Vec<f64> = (1..SAMPLES - 1)
        .map(|i| lo + (hi - lo) * i as f64 / (SAMPLES - 1) as f64)
        .chain(nodes.iter().map(Case::n_waves))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs.into_iter()
        .filter_map(|n| {
            let c = case_at(&nodes, n).filter(plausible)?;
            let p = model.predict(&c).ok()?;
            Some((n, ratio_of(&p), 0.0))
        })
        .filter(|p| p.1.is_finite())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::preset;
    use crate::report::figure4::models::amplitude_groups;

    /// The curve's value at a marker's `N_lambda` (it is one of the samples).
    fn at(curve: &[(f64, f64, f64)], n: f64) -> f64 {
        curve
            .iter()
            .find(|p| (p.0 - n).abs() <= 1e-12 * n)
            .map(|p| p.1)
            .unwrap_or(f64::NAN)
    }

    #[test]
    fn both_paper_models_curves_pass_through_their_markers() {
        let data = crate::data::paper();
        for name in ["paper", "paper-lighthill"] {
            let model = preset(name).unwrap();
            for (_, cases) in amplitude_groups(&data) {
                let ratios: [fn(&Prediction) -> f64; 2] = [|p| p.u_over_u_wave, |p| p.omega_ratio];
                for ratio in ratios {
                    let curve = model_curve(&model, &cases, ratio);
                    // dense: no gap wider than 2 % of the span between the outer cases
                    let span = cases.iter().map(|c| c.n_waves()).fold(f64::MIN, f64::max)
                        - cases.iter().map(|c| c.n_waves()).fold(f64::MAX, f64::min);
                    let widest = curve
                        .windows(2)
                        .map(|w| w[1].0 - w[0].0)
                        .fold(0.0, f64::max);
                    assert!(widest <= 0.02 * span, "{name}: a gap of {widest} in {span}");
                    assert!(curve.windows(2).all(|w| w[1].0 > w[0].0), "a function of N");
                    // no line past the outer cases
                    let lo = cases.iter().map(|c| c.n_waves()).fold(f64::MAX, f64::min);
                    let hi = cases.iter().map(|c| c.n_waves()).fold(f64::MIN, f64::max);
                    assert!(curve.iter().all(|p| p.0 >= lo && p.0 <= hi), "{name}");
                    assert_eq!(curve.first().map(|p| p.0), Some(lo));
                    assert_eq!(curve.last().map(|p| p.0), Some(hi));
                    for c in &cases {
                        let marker = ratio(&model.predict(c).unwrap());
                        let on_curve = at(&curve, c.n_waves());
                        assert!(
                            ((on_curve - marker) / marker).abs() < 1e-9,
                            "{name} {}: curve {on_curve} against marker {marker}",
                            c.id
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_group_of_one_case_has_markers_but_no_curve() {
        let data = crate::data::paper();
        let model = preset("paper").unwrap();
        assert!(model_curve(&model, &[&data.cases[0]], |p| p.u_over_u_wave).is_empty());
    }

    #[test]
    fn between_cases_every_differing_input_is_interpolated_and_held_beyond() {
        let data = crate::data::paper();
        let (a, b) = (&data.cases[1], &data.cases[0]); // tail-2 (8.8 waves), tail-1 (8.39)
        let nodes = nodes(&[a, b]);
        let mid = case_at(&nodes, 0.5 * (a.n_waves() + b.n_waves())).unwrap();
        let half = |x: f64, y: f64| 0.5 * (x + y);
        assert!((mid.frequency_hz - half(a.frequency_hz, b.frequency_hz)).abs() < 1e-12);
        let u = mid.u_mm_s.unwrap().mean;
        assert!((u - half(a.u_mm_s.unwrap().mean, b.u_mm_s.unwrap().mean)).abs() < 1e-12);
        let chord = chord_length_mm(&mid);
        assert!((chord - half(chord_length_mm(a), chord_length_mm(b))).abs() < 1e-9);
        // beyond the most waves (tail-2's 8.8): tail-2's rate, speed and chord
        assert!((mid.n_waves() - 0.5 * (a.n_waves() + b.n_waves())).abs() < 1e-12);
        let out = case_at(&nodes, 1.05 * a.n_waves()).unwrap();
        assert_eq!(out.frequency_hz, a.frequency_hz);
        assert_eq!(out.u_mm_s, a.u_mm_s);
        assert!((chord_length_mm(&out) - chord_length_mm(a)).abs() < 1e-9);
        assert!((out.n_waves() - 1.05 * a.n_waves()).abs() < 1e-12);
    }
}
