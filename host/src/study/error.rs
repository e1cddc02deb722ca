//! What can go wrong with a study, as data: the file, the step and the
//! field each error concerns, so that a caller (the command line, a Python
//! binding) can say where without parsing a message.

use std::path::PathBuf;

/// A study error. Every variant names the study file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The file cannot be read or written.
    #[error("{file}: {message}")]
    Io { file: PathBuf, message: String },
    /// The file is not a study this version understands: a TOML error, an
    /// unknown field, a schema version from elsewhere.
    #[error("{file}: field `{field}`: {message}")]
    Format {
        file: PathBuf,
        field: String,
        message: String,
    },
    /// No study file where one was looked for.
    #[error("{file}: no study here; start one with `swimbot init --data FILE`")]
    NotFound { file: PathBuf },
    /// `init` would overwrite a study.
    #[error("{file}: a study is already here; `swimbot init --force` starts it again (its steps are lost), or give another file with --study")]
    Exists { file: PathBuf },
    /// The dataset's bytes are not the ones the study was built on.
    #[error("{file}: the dataset {data} changed since the study was made (SHA-256 {expected}, now {found}): its steps were calibrated on other numbers. Start the study again on the new data with `swimbot init --force --data {data}`, or restore the file")]
    DatasetChanged {
        file: PathBuf,
        data: PathBuf,
        expected: String,
        found: String,
    },
    /// A file the dataset reads (a CSV's setup file) is not the one the
    /// study pinned, or is not pinned at all.
    #[error("{file}: {message}")]
    InputChanged {
        file: PathBuf,
        input: PathBuf,
        message: String,
    },
    /// What the study stores is not what its model computes: a number
    /// edited by hand, a step deleted or moved, a study from a swimbot
    /// whose physics differs.
    #[error("{file}: {at}, field `{field}`: {message}")]
    Unverified {
        file: PathBuf,
        /// `the start` or `step N (`effect`)`.
        at: String,
        field: String,
        message: String,
    },
    /// The dataset cannot be loaded.
    #[error("{file}: dataset: {message}")]
    Data { file: PathBuf, message: String },
    /// A step cannot be rebuilt (its effect unknown, a definition that no
    /// longer parses, a parameter the effect does not have).
    #[error("{file}: step {step} (`{effect}`), field `{field}`: {message}")]
    Step {
        file: PathBuf,
        step: usize,
        effect: String,
        field: String,
        message: String,
    },
    /// The effect to add is not known or cannot join the model.
    #[error("{file}: cannot add `{effect}`: {message}")]
    Effect {
        file: PathBuf,
        effect: String,
        message: String,
    },
    /// The step was calibrated but makes the error rise; `add --force`
    /// records it anyway.
    #[error("{file}: `{effect}` makes the error rise: MARE {before_pct:.2} % -> {after_pct:.2} % (chi-square {chi2_before:.4} -> {chi2_after:.4}){tried}; not added (add --force records it anyway)")]
    ErrorRises {
        file: PathBuf,
        effect: String,
        before_pct: f64,
        after_pct: f64,
        chi2_before: f64,
        chi2_after: f64,
        /// The calibrations tried, in words (empty when only one was).
        tried: String,
    },
    /// `undo` with no step.
    #[error("{file}: no step to undo")]
    NothingToUndo { file: PathBuf },
    /// Another command replaced the study while this one worked on it.
    #[error("{file}: another swimbot command changed the study while this one ran (two `add`s at once?); nothing was recorded: run it again on the study as it is now")]
    Changed { file: PathBuf },
    /// The model cannot predict a case, or the fit failed.
    #[error("{file}: {message}")]
    Model { file: PathBuf, message: String },
    /// A run sheet's row cannot join the study's data.
    #[error("{file}: the run sheet cannot join the study (nothing was changed): {error}")]
    Sheet {
        file: PathBuf,
        error: super::data_add::SheetError,
    },
}

/// A recorded parameter value that does not fit its effect (a step's
/// field, [`StudyError::Step`], says where).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamValueError {
    /// The effect has no parameter of this name (echoed as read).
    #[error("`{effect}` has no parameter `{param}`")]
    Unknown { effect: String, param: String },
    /// The value is not finite or leaves the parameter's range.
    #[error("{effect}.{param} = {value} is outside its range {min}..={max}")]
    OutOfRange {
        effect: String,
        param: String,
        value: f64,
        min: f64,
        max: f64,
    },
}

impl StudyError {
    /// Whether the command is refused (exit code 2: the input, the
    /// folder or the disk is the user's to fix, as for every other output
    /// swimbot writes) rather than failed (exit code 1: a bug). Every
    /// study error is a refusal.
    pub fn is_input(&self) -> bool {
        true
    }
}
