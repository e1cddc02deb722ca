//! The model against the data at one moment of the study: the summary
//! statistics a step is judged by (MARE, cross-validated MARE, chi-square,
//! its reduced value and the noise floor a right model stays below) and
//! every case's prediction beside its measurement. Stored in the study so
//! that `steps` and the page print these numbers and compute none.

use crate::data::Dataset;
use crate::model::{Model, ModelError};
use crate::workbench::compare::{carried_free_params, compare};
use crate::workbench::fit::FreeParam;
use crate::workbench::noise::{chi2_noise_floor, error_dofs};
use serde::{Deserialize, Serialize};

/// The quantile of a right model's chi-square taken as the noise floor,
/// as `diagnose` takes it by default.
pub const NOISE_LEVEL: f64 = 0.95;

/// Summary statistics of a model on a dataset.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Mean absolute relative error over every measured quantity.
    pub mare: f64,
    /// The same, each case predicted by a fit without it (leave-one-out up
    /// to ten cases, ten folds above); equal to `mare` when nothing was
    /// fitted.
    pub cv_mare: f64,
    /// Sum of squared residuals in standard errors.
    pub chi2: f64,
    /// `chi2 / (n - k)`; absent when `n <= k`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chi2_reduced: Option<f64>,
    /// The chi-square a right model stays below with probability 0.95,
    /// `k` parameters fitted ([`crate::workbench::noise`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_floor_chi2: Option<f64>,
    pub at_noise_floor: bool,
    /// Measured quantities.
    pub n: usize,
    /// Fitted parameters the model carries.
    pub free_params: usize,
}

/// One case: measurement and prediction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseRow {
    pub id: String,
    /// `N_lambda`, turns of the helix.
    pub n_waves: f64,
    /// `B_o / R_body`.
    pub amplitude_ratio: f64,
    pub frequency_hz: f64,
    pub u_pred_mm_s: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_obs_mm_s: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_ci_mm_s: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_rel_err: Option<f64>,
    pub omega_pred_hz: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega_obs_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega_ci_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega_rel_err: Option<f64>,
}

/// Statistics and cases together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    pub stats: Stats,
    #[serde(default, rename = "case")]
    pub cases: Vec<CaseRow>,
}

impl Snapshot {
    /// `model` on `data`; `fitted` are the parameters calibrated on these
    /// data (their cross-validation refits them; empty: `cv_mare = mare`).
    pub fn of(model: &Model, data: &Dataset, fitted: &[FreeParam]) -> Result<Self, ModelError> {
        let k = carried_free_params(model);
        let cmp = compare(model, data, k)?;
        let cv_mare = if fitted.is_empty() {
            cmp.summary.mare
        } else {
            // Least squares: the MARE a snapshot reports is a least-squares
            // figure whatever likelihood calibrated the model.
            crate::workbench::candidate::cross_validated_mare(
                model,
                data,
                fitted,
                crate::workbench::robust::Likelihood::Gaussian,
            )
        };
        let floor = chi2_noise_floor(&error_dofs(data), k, NOISE_LEVEL);
        let stats = Stats {
            mare: cmp.summary.mare,
            cv_mare,
            chi2: cmp.summary.chi2,
            chi2_reduced: cmp.summary.chi2_reduced,
            noise_floor_chi2: floor,
            at_noise_floor: floor.is_some_and(|f| cmp.summary.chi2 <= f),
            n: cmp.summary.n,
            free_params: k,
        };
        let cases = cmp
            .cases
            .iter()
            .map(|c| CaseRow {
                id: c.id.clone(),
                n_waves: c.n_waves,
                amplitude_ratio: c.amplitude_ratio,
                frequency_hz: c.frequency_hz,
                u_pred_mm_s: c.u().pred,
                u_obs_mm_s: c.u().obs,
                u_ci_mm_s: c.u().ci,
                u_rel_err: c.u().rel_err,
                omega_pred_hz: c.omega().pred,
                omega_obs_hz: c.omega().obs,
                omega_ci_hz: c.omega().ci,
                omega_rel_err: c.omega().rel_err,
            })
            .collect();
        Ok(Snapshot { stats, cases })
    }

    /// Every number finite (a NaN would not survive TOML and means a
    /// prediction failed silently).
    pub fn is_finite(&self) -> bool {
        let s = &self.stats;
        let opt = |v: Option<f64>| v.is_none_or(f64::is_finite);
        s.mare.is_finite()
            && s.cv_mare.is_finite()
            && s.chi2.is_finite()
            && opt(s.chi2_reduced)
            && opt(s.noise_floor_chi2)
            && self.cases.iter().all(|c| {
                c.u_pred_mm_s.is_finite()
                    && c.omega_pred_hz.is_finite()
                    && opt(c.u_rel_err)
                    && opt(c.omega_rel_err)
            })
    }
}
