//! The score of a fitted model variant, as `diagnose` ranks it: the same
//! numbers for a catalogue candidate ([`super::diagnosis::Candidate`]), a
//! located law ([`super::discovery::Located`]) and a set's step, so
//! that they read the same in the JSON, the tables and the page (each holds
//! one, flattened).
//!
//! **One rule for every ranking**: a model is ranked by the AICc
//! of the deviance its fit minimised ([`Deviance`]),
//! `AICc = D + 2k + 2k(k+1)/(n-k-1)`, where `D` is the chi-square under the
//! Gaussian likelihood (the default) and the Student-t deviance
//! `sum (nu + 1) ln(1 + z^2/nu)` under `--likelihood student-t`, both on
//! the same residuals in standard errors. The noise floor stays a test of
//! the chi-square: it is a quantile of the chi-square of a right model
//! ([`super::noise`]), and no such quantile of the t deviance is drawn.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2 (AICc); C. M. Hurvich &
//! C.-L. Tsai, Biometrika 76 (1989) 297; K. L. Lange, R. J. A. Little &
//! J. M. G. Taylor, J. Am. Stat. Assoc. 84 (1989) 881 (the t deviance).

use super::fit::FitResult;
use super::robust::{deviance_of, Likelihood};
use crate::data::Dataset;
use crate::model::{Model, ModelError};
use crate::stats::FitSummary;
use serde::Serialize;

/// A fitted model's chi-square and the deviance its fit minimised: what it
/// is ranked by ([`Self::ranked`]) and what its noise floor is judged on
/// ([`Self::chi2`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviance {
    pub chi2: f64,
    /// The minimised deviance when it is not the chi-square (the
    /// Student-t's); `None` under the Gaussian.
    pub minimised: Option<f64>,
}

impl Deviance {
    /// What `fit` reached: its chi-square and the deviance it minimised.
    pub fn of_fit(f: &FitResult) -> Self {
        Deviance {
            chi2: f.chi2,
            minimised: f.t_deviance,
        }
    }

    /// `model`'s deviance on `data` under `lik`, beside its chi-square
    /// `chi2` (not recomputed, so that the Gaussian's is `chi2` exactly).
    pub fn of_model(
        model: &Model,
        data: &Dataset,
        chi2: f64,
        lik: Likelihood,
    ) -> Result<Self, ModelError> {
        let minimised = match lik {
            Likelihood::Gaussian => None,
            _ => Some(deviance_of(model, data, lik)?),
        };
        Ok(Deviance { chi2, minimised })
    }

    /// The figure every ranking of `diagnose` is taken on.
    pub fn ranked(&self) -> f64 {
        self.minimised.unwrap_or(self.chi2)
    }

    /// Its AICc with `k` free parameters over `n` quantities.
    pub fn aicc(&self, n: usize, k: usize) -> Option<f64> {
        aicc(self.ranked(), n, k)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FitScore {
    /// Mean absolute relative error over every measured quantity.
    pub mare: f64,
    /// The same, each fold's cases predicted by a fit without them.
    pub cv_mare: f64,
    pub chi2: f64,
    pub chi2_reduced: Option<f64>,
    /// The deviance the fit minimised when it is not the chi-square (under
    /// `--likelihood student-t`); absent under the Gaussian, whose
    /// deviance is `chi2`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub deviance: Option<f64>,
    /// AICc of the minimised deviance, with every free parameter fitted so
    /// far counted: what `diagnose` ranks by.
    pub aicc: Option<f64>,
    /// The chi-square is at or below the noise floor for its parameters.
    pub at_noise_floor: bool,
}

impl FitScore {
    /// The score of a fit with `k` free parameters and deviance `d` over
    /// the quantities `summary` counts: its AICc, and whether its
    /// chi-square is at or below `floor`, the noise floor for `k`.
    pub fn of(
        summary: &FitSummary,
        cv_mare: f64,
        d: Deviance,
        k: usize,
        floor: Option<f64>,
    ) -> Self {
        FitScore {
            mare: summary.mare,
            cv_mare,
            chi2: d.chi2,
            chi2_reduced: summary.chi2_reduced,
            deviance: d.minimised,
            aicc: d.aicc(summary.n, k),
            at_noise_floor: floor.is_some_and(|f| d.chi2 <= f),
        }
    }

    /// The chi-square and minimised deviance it was scored on.
    pub fn deviance(&self) -> Deviance {
        Deviance {
            chi2: self.chi2,
            minimised: self.deviance,
        }
    }
}

/// The small-sample Akaike criterion of a deviance `d` (the chi-square
/// under the Gaussian) with `k` free parameters over `n` quantities
/// (Hurvich & Tsai 1989); `None` when `n <= k + 1`.
pub fn aicc(d: f64, n: usize, k: usize) -> Option<f64> {
    let denom = n as i64 - k as i64 - 1;
    (denom > 0).then(|| d + 2.0 * k as f64 + 2.0 * (k * (k + 1)) as f64 / denom as f64)
}
