//! The score of a fitted model variant, as `diagnose` ranks it: the same
//! six numbers for a catalogue candidate ([`super::diagnosis::Candidate`])
//! and a located law ([`super::discovery::Located`]), so that they read the
//! same in the JSON, the tables and the page (each holds one, flattened).
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2 (AICc); C. M. Hurvich &
//! C.-L. Tsai, Biometrika 76 (1989) 297.

use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FitScore {
    /// Mean absolute relative error over every measured quantity.
    pub mare: f64,
    /// The same, each fold's cases predicted by a fit without them.
    pub cv_mare: f64,
    pub chi2: f64,
    pub chi2_reduced: Option<f64>,
    /// AICc with every free parameter fitted so far counted.
    pub aicc: Option<f64>,
    /// The chi-square is at or below the noise floor for its parameters.
    pub at_noise_floor: bool,
}
