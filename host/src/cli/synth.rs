//! `swimbot synth`: synthetic measurements from a chosen truth model.

use super::CliError;
use crate::effects::Catalogue;
use crate::model::{preset, Model, PRESETS};
use crate::physics::coefficients::CoefficientSet;
use crate::provenance::Inputs;
use crate::workbench::synth::{generate, SynthSettings};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct SynthArgs {
    /// Case design (TOML or CSV; measurements in it are replaced) [default: the paper's cases].
    #[arg(long, value_name = "FILE")]
    pub data: Option<PathBuf>,
    /// The truth: a preset or coefficient set, then effects, joined by `+`,
    /// e.g. "base + backflow + buoyancy:net_force_mn=0.2".
    #[arg(long)]
    pub truth: String,
    /// Relative noise (standard deviation) of one trial, as a fraction (0.02 = 2 %).
    #[arg(long, default_value_t = 0.02)]
    pub noise: f64,
    /// Trials per case (each measured mean and its 95 % CI come from them).
    #[arg(long, default_value_t = 5, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<u32>)]
    pub trials: u32,
    /// Seed of the noise generator (the same seed gives the same data).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<u64>)]
    pub seed: u64,
    /// Output dataset file (TOML).
    #[arg(short, long, value_name = "FILE.toml")]
    pub output: PathBuf,
    #[command(flatten)]
    pub effect_files: super::model_args::EffectFiles,
    /// Run the truth on the recorded inputs exactly. By default, when the design declares input
    /// uncertainties, each case's true inputs are drawn from them (seeded; shared tube, oil and
    /// body once for all cases) and the file records the nominal ones, as a lab's would.
    #[arg(long)]
    pub nominal_inputs: bool,
}

/// Parse "PRESET|COEFFICIENTS + EFFECT + EFFECT...", the effects looked
/// up in `catalogue`.
pub fn parse_truth(text: &str, catalogue: &Catalogue) -> Result<Model, CliError> {
    if text.trim().is_empty() {
        return Err(CliError::input("--truth is empty"));
    }
    // An empty term (`base ++ backflow`, a trailing `+`) is a typo that
    // may have lost an effect: refused, never skipped.
    let terms: Vec<&str> = text.split('+').map(str::trim).collect();
    if let Some(i) = terms.iter().position(|t| t.is_empty()) {
        return Err(CliError::input(format!(
            "--truth `{}`: term {} of {} is empty (two `+` in a row, or one at an end); write PRESET + EFFECT + EFFECT",
            crate::data::limits::echo(text),
            i + 1,
            terms.len()
        )));
    }
    let mut parts = terms.into_iter();
    let head = parts
        .next()
        .ok_or_else(|| CliError::input("--truth is empty"))?;
    let mut model = if let Some(m) = preset(head) {
        m
    } else if let Some(set) = CoefficientSet::from_name(head) {
        Model::base().with_coefficients(set)
    } else {
        let mut m = Model::base();
        m.effects
            .push(catalogue.parse_effect_spec(head).map_err(|e| {
                let known: Vec<&str> = PRESETS.iter().map(|p| p.0).collect();
                CliError::input(format!(
                    "--truth `{head}` is not a preset ({}), a coefficient set or an effect: {e}",
                    known.join(", ")
                ))
            })?);
        m
    };
    for p in parts {
        let e = catalogue.parse_effect_spec(p)?;
        if model.effects.iter().any(|m| m.name() == e.name()) {
            return Err(CliError::input(format!(
                "--truth names `{}` twice",
                e.name()
            )));
        }
        model.effects.push(e);
    }
    Ok(model)
}

pub fn run(a: SynthArgs, inputs: &Inputs) -> Result<(), CliError> {
    if !(a.noise.is_finite() && (0.0..1.0).contains(&a.noise)) {
        return Err(CliError::input(format!(
            "--noise must be in [0, 1), got {}",
            a.noise
        )));
    }
    let max_trials = crate::data::limits::MAX_TRIALS;
    if !(2..=max_trials).contains(&a.trials) {
        return Err(CliError::input(format!(
            "--trials must be from 2 (a confidence interval needs two trials) to {max_trials}, got {}",
            a.trials
        )));
    }
    super::output::check_output_file(&a.output, inputs)?;
    let catalogue = a.effect_files.load(inputs)?;
    let design = super::model_args::load_data(&a.data, inputs)?;
    let truth = super::model_args::with_bases(parse_truth(&a.truth, &catalogue)?, &catalogue)?;
    let settings = SynthSettings {
        noise_rel: a.noise,
        trials: a.trials,
        seed: a.seed,
        draw_inputs: !a.nominal_inputs,
        ..Default::default()
    };
    let data = generate(&truth, &design, settings)?;
    // The synthetic data must load again: a truth that predicts U = 0 or a
    // rate outside the documented ranges is refused here, not on reading.
    for c in &data.cases {
        crate::data::limits::check_case(c).map_err(|(f, e)| {
            CliError::input(format!(
                "--truth `{}`: case `{}`: synthetic `{f}`: {e}",
                a.truth, c.id
            ))
        })?;
    }
    let text = crate::provenance::Provenance::capture(inputs).comment_block()
        + &crate::data::to_toml(&data);
    super::output::write_atomically(&a.output, text.as_bytes(), inputs)?;
    let drawn = settings.draw_inputs && design.cases.iter().any(|c| !c.inputs.is_empty());
    eprintln!(
        "wrote {} cases from truth `{}` to {}{}",
        data.cases.len(),
        truth.describe(),
        a.output.display(),
        if drawn {
            " (true inputs drawn from the declared input uncertainties, nominal ones recorded; --nominal-inputs runs the truth on the recorded inputs)"
        } else {
            ""
        }
    );
    Ok(())
}
