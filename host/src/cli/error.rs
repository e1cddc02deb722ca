//! Errors of the command line and their exit codes: bad input (files,
//! flags, values) is exit 2, anything that fails afterwards exit 1.

use std::fmt;

#[derive(Debug)]
pub enum CliError {
    /// The user's input is wrong; the message says where and what.
    Input(String),
    /// The work failed for another reason (I/O while writing, a solver).
    Failure(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failure(_) => 1,
        }
    }

    pub fn input(msg: impl fmt::Display) -> Self {
        CliError::Input(msg.to_string())
    }

    pub fn failure(msg: impl fmt::Display) -> Self {
        CliError::Failure(msg.to_string())
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Failure(m) => f.write_str(m),
        }
    }
}

impl From<crate::data::DataError> for CliError {
    fn from(e: crate::data::DataError) -> Self {
        CliError::Input(e.to_string())
    }
}

impl From<crate::effects::EffectSpecError> for CliError {
    fn from(e: crate::effects::EffectSpecError) -> Self {
        CliError::Input(e.to_string())
    }
}

/// A model that cannot be evaluated for a case is a problem of the input
/// (geometry, fluid, effect settings), so it exits with 2 as well.
impl From<crate::model::ModelError> for CliError {
    fn from(e: crate::model::ModelError) -> Self {
        CliError::Input(e.to_string())
    }
}
