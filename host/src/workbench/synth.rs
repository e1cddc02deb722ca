//! Synthetic measurements from a chosen "truth" model: each case's true U
//! and Omega_b get `trials` noisy repeats (relative Gaussian noise), which
//! become a mean and a Student-t confidence interval, exactly as a lab
//! would report them. Deterministic for a given seed.

use crate::data::limits::MIN_RELATIVE_CI;
use crate::data::{Dataset, Measured};
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
}

impl Default for SynthSettings {
    fn default() -> Self {
        SynthSettings {
            noise_rel: 0.02,
            trials: 5,
            seed: 1,
            confidence: 0.95,
        }
    }
}

/// Replace the measurements of `design` by synthetic ones from `truth`.
pub fn generate(truth: &Model, design: &Dataset, s: SynthSettings) -> Result<Dataset, ModelError> {
    let mut rng = StdRng::seed_from_u64(s.seed);
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let mut out = design.clone();
    out.name = format!(
        "synthetic ({} + noise {} %, {} trials, seed {})",
        truth.describe(),
        100.0 * s.noise_rel,
        s.trials,
        s.seed
    );
    out.source = format!("swimbot synth from `{}`", design.name);
    for case in &mut out.cases {
        let p = truth.predict(case)?;
        let mut draw = |truth_value: f64| {
            let trials: Vec<f64> = (0..s.trials.max(2))
                .map(|_| truth_value * (1.0 + s.noise_rel * unit.sample(&mut rng)))
                .collect();
            let (mean, half) = mean_and_ci(&trials, s.confidence);
            Measured {
                mean,
                // Noise 0 gives identical trials; the floor is the finest
                // resolution the data limits accept (twice it, so that a
                // TOML round trip stays inside).
                ci_half_width: half.max(2.0 * MIN_RELATIVE_CI * mean.abs()),
                confidence: s.confidence,
                trials: s.trials.max(2),
            }
        };
        case.u_mm_s = Some(draw(p.u_mm_s));
        case.omega_body_hz = Some(draw(p.omega_body_hz));
    }
    Ok(out)
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
