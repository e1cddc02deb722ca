//! Why an effect cannot act on a case: the effects layer's error. The
//! model wraps it with the case and the effect's name
//! (`ModelError::Effect`); the CLI prints that whole chain.

use crate::nonlocal::NonlocalError;

/// Why an effect cannot act on a case with the values it was given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EffectError {
    /// A Stokes-flow solve needs a positive, finite viscosity.
    #[error("viscosity must be positive, got {viscosity_pa_s} Pa s")]
    Viscosity { viscosity_pa_s: f64 },
    /// A user formula's place gives a value the model cannot use (a
    /// non-positive multiplier, a load beyond floating-point sense).
    #[error(transparent)]
    Place(Box<UnusablePlace>),
    /// A non-local solve failed.
    #[error(transparent)]
    Nonlocal(#[from] NonlocalError),
    /// A solve or its cache failed (its own words).
    #[error("{0}")]
    Solve(String),
    /// One of the above, inside a named part of the effect.
    #[error("{context}: {source}")]
    Within {
        context: String,
        source: Box<EffectError>,
    },
}

/// A user formula's place and the value it gave, with the parameters it
/// was evaluated at.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "place `{place}` = `{formula}` gives {value} with {parameters} ({why}){}",
    note_defined_in(.defined_in)
)]
pub struct UnusablePlace {
    pub place: String,
    /// The formula as written, cut for the message.
    pub formula: String,
    pub value: String,
    /// `name=value` of every parameter, or "no parameters".
    pub parameters: String,
    pub why: String,
    /// The file the effect was defined in, if any.
    pub defined_in: Option<String>,
}

fn note_defined_in(file: &Option<String>) -> String {
    file.as_ref()
        .map(|f| format!("; defined in {f}"))
        .unwrap_or_default()
}
