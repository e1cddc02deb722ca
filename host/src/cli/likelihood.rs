//! `--likelihood`: what every fit of `fit`, `diagnose` and `audit`
//! minimises (one option, one wording; [`crate::workbench::robust`]).

use crate::workbench::robust::Likelihood;
use clap::{Args, ValueEnum};

/// The values of `--likelihood`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LikelihoodArg {
    /// The Student-t deviance, nu = trials - 1 of each measurement: one bad
    /// run cannot drag the estimates.
    StudentT,
    /// The chi-square (least squares), the nu -> infinity limit.
    Gaussian,
}

impl From<LikelihoodArg> for Likelihood {
    fn from(a: LikelihoodArg) -> Self {
        match a {
            LikelihoodArg::StudentT => Likelihood::StudentT,
            LikelihoodArg::Gaussian => Likelihood::Gaussian,
        }
    }
}

/// The option, flattened into each command that fits.
#[derive(Args, Debug, Clone, Copy)]
pub struct LikelihoodArgs {
    /// What every fit minimises: the chi-square (least squares, the default
    /// of `fit`, `diagnose`, `audit` and the page, so their statistics
    /// agree) or the Student-t deviance with nu = trials - 1 (robust to one
    /// bad run where the model otherwise meets the data; on data it misses
    /// everywhere the t treats most cases as outliers).
    #[arg(long, value_enum, default_value = "gaussian")]
    pub likelihood: LikelihoodArg,
}

impl LikelihoodArgs {
    pub fn get(&self) -> Likelihood {
        self.likelihood.into()
    }
}

/// One line for the text output: which deviance was minimised.
pub fn minimised_line(lik: Likelihood) -> String {
    minimised_line_of(&lik.label())
}

/// [`minimised_line`] from the likelihood's label.
pub fn minimised_line_of(label: &str) -> String {
    format!("minimised: the {label} deviance")
}

/// The deviance a candidate of `diagnose` reached: the one its fit
/// minimised, so that `fit` with the same effects and likelihood reports
/// the same figure.
#[derive(serde::Serialize)]
pub struct CandidateDeviance {
    /// `single` (one catalogue effect) or `pair`.
    pub kind: &'static str,
    pub effect: String,
    pub deviance: f64,
}

/// `diagnose --format json`: the diagnosis with the likelihood its fits
/// minimised and each catalogue candidate's deviance under it (keys in
/// their declared order, the diagnosis's own in between).
#[derive(serde::Serialize)]
pub struct DiagnosisJson<'a> {
    pub likelihood: String,
    #[serde(flatten)]
    pub diagnosis: &'a crate::workbench::diagnose::Diagnosis,
    pub deviances: Vec<CandidateDeviance>,
    /// The numbers the terminal's screen prints (`cli/screen/headline.rs`).
    pub headline: super::screen::headline::Headline,
}

pub fn diagnosis_json<'a>(
    d: &'a crate::workbench::diagnose::Diagnosis,
    data: &crate::data::Dataset,
    lik: Likelihood,
) -> Result<DiagnosisJson<'a>, super::CliError> {
    let one = |kind, c: &crate::workbench::diagnose::Candidate| {
        crate::workbench::robust::deviance_of(&c.model, data, lik).map(|deviance| {
            CandidateDeviance {
                kind,
                effect: c.effect.clone(),
                deviance,
            }
        })
    };
    let deviances = d
        .ranking
        .iter()
        .map(|c| one("single", c))
        .chain(d.pairs.iter().map(|c| one("pair", c)))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| super::CliError::failure(format!("a candidate's deviance: {e}")))?;
    Ok(DiagnosisJson {
        likelihood: lik.label(),
        diagnosis: d,
        deviances,
        headline: super::screen::headline::headline(d, None),
    })
}
