//! The score of a fitted model variant, as `diagnose` ranks it: the same
//! six numbers for a catalogue candidate ([`super::diagnosis::Candidate`])
//! and a located law ([`super::discovery::Located`]), so that they read the
//! same in the JSON, the tables and the page (each holds one, flattened).
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2 (AICc); C. M. Hurvich &
//! C.-L. Tsai, Biometrika 76 (1989) 297.

use crate::stats::FitSummary;
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

impl FitScore {
    /// The score of a fit with `k` free parameters and chi-square `chi2`
    /// over the quantities `summary` counts: its AICc, and whether it is at
    /// or below `floor`, the noise floor for `k` parameters.
    pub fn of(summary: &FitSummary, cv_mare: f64, chi2: f64, k: usize, floor: Option<f64>) -> Self {
        FitScore {
            mare: summary.mare,
            cv_mare,
            chi2,
            chi2_reduced: summary.chi2_reduced,
            aicc: aicc(chi2, summary.n, k),
            at_noise_floor: floor.is_some_and(|f| chi2 <= f),
        }
    }
}

/// The small-sample Akaike criterion of a chi-square with `k` free
/// parameters over `n` quantities (Hurvich & Tsai 1989); `None` when
/// `n <= k + 1`.
pub fn aicc(chi2: f64, n: usize, k: usize) -> Option<f64> {
    let denom = n as i64 - k as i64 - 1;
    (denom > 0).then(|| chi2 + 2.0 * k as f64 + 2.0 * (k * (k + 1)) as f64 / denom as f64)
}
