//! Synthetic measurements from a chosen "truth" model: each case's true U
//! and Omega_b get `trials` noisy repeats (relative Gaussian noise), which
//! become a mean and a Student-t confidence interval, exactly as a lab
//! would report them. When the design declares input uncertainties, each
//! case's *true* inputs are drawn from them first (the tail's own inputs
//! case by case, the shared tube, oil and body once for all cases, as the
//! uncertainty module's correlation convention says) and the truth model
//! runs on those, while the dataset records the nominal inputs: what a lab
//! measures is a robot that is not exactly the one written down.
//! Deterministic for a given seed.

use crate::data::limits::MIN_RELATIVE_CI;
use crate::data::uncertainty::{field_value, scope_of, set_field, Scope};
use crate::data::{Case, Dataset, Measured};
use crate::model::{Model, ModelError};
use crate::stats::mean_and_ci;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// Settings of the synthetic experiment.
#[derive(Debug, Clone, Copy)]
pub struct SynthSettings {
    /// Relative standard deviation of one trial (0.02 = 2 %).
    pub noise_rel: f64,
    /// Trials per case (the paper: 5).
    pub trials: u32,
    pub seed: u64,
    /// Confidence level of the reported intervals (the paper: 0.95).
    pub confidence: f64,
    /// Draw the true inputs from the declared input uncertainties (false
    /// here, for the studies whose designs borrow the paper's declared
    /// uncertainties but mean exact inputs; `swimbot synth` sets it true).
    pub draw_inputs: bool,
}

impl Default for SynthSettings {
    fn default() -> Self {
        SynthSettings {
            noise_rel: 0.02,
            trials: 5,
            seed: 1,
            confidence: 0.95,
            draw_inputs: false,
        }
    }
}

/// Replace the measurements of `design` by synthetic ones from `truth`.
pub fn generate(truth: &Model, design: &Dataset, s: SynthSettings) -> Result<Dataset, ModelError> {
    let mut rng = StdRng::seed_from_u64(s.seed);
    let mut out = design.clone();
    out.name = format!(
        "synthetic ({} + noise {} %, {} trials, seed {})",
        truth.describe(),
        100.0 * s.noise_rel,
        s.trials,
        s.seed
    );
    out.source = format!("swimbot synth from `{}`", design.name);
    let declared = s.draw_inputs && out.cases.iter().any(|c| !c.inputs.is_empty());
    if declared {
        out.name
            .push_str(", true inputs drawn from the declared input uncertainties");
    }
    // One standard-normal draw per shared input, for every case.
    let mut shared: Vec<(&'static str, f64)> = Vec::new();
    for case in &mut out.cases {
        let true_case = if declared {
            true_inputs(case, &mut shared, &mut rng)
        } else {
            case.clone()
        };
        let p = truth.predict(&true_case)?;
        case.u_mm_s = Some(measure(p.u_mm_s, &s, &mut rng));
        case.omega_body_hz = Some(measure(p.omega_body_hz, &s, &mut rng));
    }
    Ok(out)
}

/// One measured quantity: `s.trials` trials (at least 2), each the true
/// value with relative Gaussian noise `s.noise_rel`, as their mean and
/// confidence interval.
pub fn measure(truth_value: f64, s: &SynthSettings, rng: &mut StdRng) -> Measured {
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let trials: Vec<f64> = (0..s.trials.max(2))
        .map(|_| truth_value * (1.0 + s.noise_rel * unit.sample(rng)))
        .collect();
    let (mean, half) = mean_and_ci(&trials, s.confidence);
    Measured {
        mean,
        // Noise 0 gives identical trials; the floor is the finest
        // resolution the data limits accept (twice it, so that a TOML
        // round trip stays inside).
        ci_half_width: half.max(2.0 * MIN_RELATIVE_CI * mean.abs()),
        confidence: s.confidence,
        trials: s.trials.max(2),
    }
}

/// `case` with its uncertain inputs drawn around the recorded values:
/// per-case inputs independently, shared ones with the one draw `shared`
/// holds for them (made on first use). A draw at or below zero (lengths,
/// rates and viscosities are positive) is redrawn.
fn true_inputs(case: &Case, shared: &mut Vec<(&'static str, f64)>, rng: &mut StdRng) -> Case {
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let mut c = case.clone();
    for (field, u) in case.inputs.nonzero(case) {
        let x = field_value(case, field).unwrap_or(0.0);
        let mut z = || unit.sample(rng);
        if crate::data::uncertainty::is_signed(field) {
            // The trim has no sign to keep: one draw, shared by every case.
            let k = match shared.iter().find(|(f, _)| *f == field) {
                Some((_, k)) => *k,
                None => {
                    let k = z();
                    shared.push((field, k));
                    k
                }
            };
            set_field(&mut c, field, x + u * k);
            continue;
        }
        let value = match scope_of(field) {
            Scope::PerCase => (0..100).map(|_| x + u * z()).find(|v| *v > 0.0),
            Scope::Shared => {
                let k = match shared.iter().find(|(f, _)| *f == field) {
                    Some((_, k)) => *k,
                    None => {
                        let k = (0..100)
                            .map(|_| z())
                            .find(|k| x + u * k > 0.0)
                            .unwrap_or(0.0);
                        shared.push((field, k));
                        k
                    }
                };
                Some(x + u * k).filter(|v| *v > 0.0)
            }
        };
        set_field(&mut c, field, value.unwrap_or(x));
    }
    c
}

/// A case design for hidden-effect studies: each paper tail as built, in a
/// wider channel at a higher rate, and longer in a narrower channel, so
/// that channel confinement, tail rate and tail length all vary.
pub fn varied_design(paper: &Dataset) -> Dataset {
    let mut out = paper.clone();
    out.name = format!("{} (varied design)", paper.name);
    out.cases.clear();
    for c in &paper.cases {
        out.cases.push(c.clone());
        let mut wide = c.clone();
        wide.id = format!("{}-wide-fast", c.id);
        wide.channel_diameter_mm = 50.0;
        wide.frequency_hz *= 1.6;
        out.cases.push(wide);
        let mut long = c.clone();
        long.id = format!("{}-long-narrow", c.id);
        long.channel_diameter_mm = 28.0;
        long.tail_length_mm *= 1.4;
        out.cases.push(long);
    }
    out
}

/// A richer design for discovery studies: each paper tail in three
/// channels (28, 35, 50 mm) at two rates (as recorded and 1.6 times), plus
/// a 1.4 times longer tail in the paper's channel: channel, rate, tail
/// length, amplitude and wavelength all vary, and channel and rate are not
/// confounded (they are in [`varied_design`]).
pub fn rich_design(paper: &Dataset) -> Dataset {
    let mut out = paper.clone();
    out.name = format!("{} (rich design)", paper.name);
    out.cases.clear();
    for c in &paper.cases {
        for d_ch in [28.0, 35.0, 50.0] {
            for rate in [1.0, 1.6] {
                let mut v = c.clone();
                v.id = format!("{}-d{d_ch}-x{rate}", c.id);
                v.channel_diameter_mm = d_ch;
                v.frequency_hz *= rate;
                out.cases.push(v);
            }
        }
        let mut long = c.clone();
        long.id = format!("{}-long", c.id);
        long.tail_length_mm *= 1.4;
        out.cases.push(long);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::preset;

    fn exact(draw_inputs: bool, seed: u64) -> SynthSettings {
        SynthSettings {
            noise_rel: 0.0,
            seed,
            draw_inputs,
            ..Default::default()
        }
    }

    #[test]
    fn declared_input_uncertainties_move_the_truth_but_not_the_record() {
        let design = crate::data::paper();
        let truth = preset("paper").unwrap();
        let nominal = generate(&truth, &design, exact(false, 7)).unwrap();
        let drawn = generate(&truth, &design, exact(true, 7)).unwrap();
        let bands = super::super::propagate::bands(&truth, &design).unwrap();
        let mut moved = 0;
        for ((n, d), (c, b)) in nominal
            .cases
            .iter()
            .zip(&drawn.cases)
            .zip(design.cases.iter().zip(&bands))
        {
            // the file records the nominal inputs
            assert_eq!(d.wavelength_mm, c.wavelength_mm);
            assert_eq!(d.frequency_hz, c.frequency_hz);
            // without drawing, the truth on the recorded inputs
            let p = truth.predict(c).unwrap();
            assert!((n.u_mm_s.unwrap().mean - p.u_mm_s).abs() <= 1e-12 * p.u_mm_s.abs());
            // with it, a different robot, by about the propagated band
            let du = d.u_mm_s.unwrap().mean - p.u_mm_s;
            assert!(
                du.abs() < 5.0 * b.u_sd_mm_s,
                "{}: {du} against {}",
                c.id,
                b.u_sd_mm_s
            );
            moved += (du.abs() > 0.05 * b.u_sd_mm_s) as usize;
        }
        assert!(moved >= 3, "only {moved} cases moved");
        // seeded: the same seed the same robot, another seed another
        let again = generate(&truth, &design, exact(true, 7)).unwrap();
        let other = generate(&truth, &design, exact(true, 8)).unwrap();
        let u = |d: &Dataset| {
            d.cases
                .iter()
                .map(|c| c.u_mm_s.unwrap().mean)
                .collect::<Vec<_>>()
        };
        assert_eq!(u(&again), u(&drawn));
        assert_ne!(u(&other), u(&drawn));
        assert!(drawn
            .name
            .contains("drawn from the declared input uncertainties"));
    }

    #[test]
    fn without_declared_uncertainties_nothing_is_drawn() {
        let mut design = crate::data::paper();
        for c in &mut design.cases {
            c.inputs.uncertainties.clear();
        }
        let truth = preset("paper").unwrap();
        let a = generate(&truth, &design, exact(true, 3)).unwrap();
        let b = generate(&truth, &design, exact(false, 3)).unwrap();
        let u = |d: &Dataset| {
            d.cases
                .iter()
                .map(|c| c.u_mm_s.unwrap().mean)
                .collect::<Vec<_>>()
        };
        assert_eq!(u(&a), u(&b));
        assert!(!a.name.contains("drawn"));
    }
}
