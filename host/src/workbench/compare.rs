//! Model against measurement, case by case: predicted and observed swimming
//! speed `U` and body rotation rate `Omega_b`, their relative errors and
//! errors in standard errors, and the summary statistics (MARE, max
//! relative error, reduced chi-square).

use super::input_covariance::{correlated_chi2_of, CorrelatedChi2};
use crate::data::{Case, Dataset, Measured};
use crate::model::{Model, ModelError, Prediction};
use crate::stats::{summarise, FitSummary, Residual};
use serde::Serialize;

/// One case of a comparison.
#[derive(Debug, Clone, Serialize)]
pub struct CaseComparison {
    pub id: String,
    pub frequency_hz: f64,
    pub n_waves: f64,
    pub amplitude_ratio: f64,
    pub u_pred_mm_s: f64,
    pub u_obs_mm_s: Option<f64>,
    pub u_ci_mm_s: Option<f64>,
    pub omega_pred_hz: f64,
    pub omega_obs_hz: Option<f64>,
    pub omega_ci_hz: Option<f64>,
    pub u_rel_err: Option<f64>,
    pub omega_rel_err: Option<f64>,
    /// Error in standard errors of the measured mean.
    pub u_err_sigma: Option<f64>,
    pub omega_err_sigma: Option<f64>,
    pub u_over_u_wave_pred: f64,
    pub omega_ratio_pred: f64,
    /// Input-uncertainty band of the prediction (standard uncertainty,
    /// [`super::propagate`]); `None` until [`Comparison::with_bands`].
    pub u_input_sd_mm_s: Option<f64>,
    pub omega_input_sd_hz: Option<f64>,
    pub u_over_u_wave_input_sd: Option<f64>,
    pub omega_ratio_input_sd: Option<f64>,
    /// The input that dominates each band.
    pub u_dominant_input: Option<String>,
    pub omega_dominant_input: Option<String>,
    /// Error in combined standard errors (measurement and inputs in quadrature).
    pub u_err_sigma_combined: Option<f64>,
    pub omega_err_sigma_combined: Option<f64>,
    /// What the lab recorded beside the case (temperature, date, ...),
    /// carried so that a residual can be read against it.
    #[serde(skip_serializing_if = "crate::data::Recorded::is_empty")]
    pub recorded: crate::data::Recorded,
}

#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    pub model: String,
    pub dataset: String,
    pub cases: Vec<CaseComparison>,
    pub summary: FitSummary,
    /// The summary against the combined uncertainty, with bands attached,
    /// every quantity taken as independent: its chi-square is
    /// [`CorrelatedChi2::chi2_independent`], not the statistic to judge
    /// with ([`Self::chi2_correlated`] is).
    pub summary_combined: Option<FitSummary>,
    /// How many quantities lie within [`COVERAGE_SIGMAS`] combined
    /// standard deviations, with bands attached.
    pub coverage: Option<Coverage>,
    /// The chi-square with the inputs' covariance across cases (shared
    /// inputs correlate every case they span), its p-value and the shared
    /// inputs' pulls, with bands attached ([`super::input_covariance`]).
    pub chi2_correlated: Option<CorrelatedChi2>,
}

/// The coverage factor of [`Coverage`]: 2 combined standard deviations,
/// about 95 % for a normal error (GUM 6.2-6.3), the width the page draws.
pub const COVERAGE_SIGMAS: f64 = 2.0;

/// One quantity outside the coverage interval.
#[derive(Debug, Clone, Serialize)]
pub struct Outside {
    pub case: String,
    pub quantity: Quantity,
    /// The error in combined standard deviations (signed).
    pub sigmas: f64,
}

/// The measured quantities within [`COVERAGE_SIGMAS`] combined standard
/// deviations (measurement and inputs in quadrature) of the prediction.
#[derive(Debug, Clone, Serialize)]
pub struct Coverage {
    pub within: usize,
    pub of: usize,
    pub sigmas: f64,
    /// The rest, in case order (U before Omega_b).
    pub outside: Vec<Outside>,
}

impl Coverage {
    /// The one wording `compare` and the page print.
    pub fn describe(&self) -> String {
        format!(
            "{} of {} quantities within {} combined standard deviations",
            self.within, self.of, self.sigmas
        )
    }

    fn of_cases(cases: &[CaseComparison]) -> Self {
        let mut outside = Vec::new();
        let mut of = 0;
        for k in cases {
            for (q, e) in [
                (Quantity::U, k.u_err_sigma_combined),
                (Quantity::Omega, k.omega_err_sigma_combined),
            ] {
                let Some(e) = e else { continue };
                of += 1;
                if e.abs() > COVERAGE_SIGMAS {
                    outside.push(Outside {
                        case: k.id.clone(),
                        quantity: q,
                        sigmas: e,
                    });
                }
            }
        }
        Coverage {
            within: of - outside.len(),
            of,
            sigmas: COVERAGE_SIGMAS,
            outside,
        }
    }
}

impl Comparison {
    /// Attach the input-uncertainty bands (one per case, in order) and
    /// judge the residuals against the combined uncertainty too.
    pub fn with_bands(mut self, data: &Dataset, bands: &[super::propagate::Band]) -> Self {
        let mut all = Vec::new();
        for ((k, case), b) in self.cases.iter_mut().zip(&data.cases).zip(bands) {
            k.u_input_sd_mm_s = Some(b.u_sd_mm_s);
            k.omega_input_sd_hz = Some(b.omega_sd_hz);
            k.u_over_u_wave_input_sd = Some(b.u_over_u_wave_sd);
            k.omega_ratio_input_sd = Some(b.omega_ratio_sd);
            k.u_dominant_input = b.dominant_u.map(str::to_string);
            k.omega_dominant_input = b.dominant_omega.map(str::to_string);
            let combined = |pred: f64, m: &Measured, u_in: f64| {
                let c = super::propagate::combine(m, u_in);
                Residual {
                    predicted: pred,
                    observed: c.mean,
                    sigma: c.standard_error(),
                }
            };
            if let Some(m) = &case.u_mm_s {
                let r = combined(k.u_pred_mm_s, m, b.u_sd_mm_s);
                k.u_err_sigma_combined = Some(r.normalised());
                all.push(r);
            }
            if let Some(m) = &case.omega_body_hz {
                let r = combined(k.omega_pred_hz, m, b.omega_sd_hz);
                k.omega_err_sigma_combined = Some(r.normalised());
                all.push(r);
            }
        }
        self.summary_combined = Some(summarise(&all, self.summary.free_params));
        self.coverage = Some(Coverage::of_cases(&self.cases));
        let predicted: Vec<(f64, f64)> = self
            .cases
            .iter()
            .map(|k| (k.u_pred_mm_s, k.omega_pred_hz))
            .collect();
        self.chi2_correlated =
            correlated_chi2_of(data, &predicted, bands, self.summary.free_params);
        self
    }
}

/// Which measured quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    U,
    Omega,
}

impl Quantity {
    pub fn label(self) -> &'static str {
        match self {
            Quantity::U => "U",
            Quantity::Omega => "Omega_b",
        }
    }
}

/// The residuals of one case's measured quantities.
pub fn case_residuals(case: &Case, p: &Prediction) -> Vec<(Quantity, Residual)> {
    let mut out = Vec::with_capacity(2);
    let mk = |pred: f64, m: &Measured| Residual {
        predicted: pred,
        observed: m.mean,
        sigma: m.standard_error(),
    };
    if let Some(m) = &case.u_mm_s {
        out.push((Quantity::U, mk(p.u_mm_s, m)));
    }
    if let Some(m) = &case.omega_body_hz {
        out.push((Quantity::Omega, mk(p.omega_body_hz, m)));
    }
    out
}

/// Every free parameter `model` carries (the paper's Table III factors,
/// a written law's coefficients): whoever set them fitted them to data.
pub fn carried_free_params(model: &Model) -> usize {
    model.effects.iter().map(|e| e.free_indices().len()).sum()
}

/// Compare `model` with every case of `data`. The reduced chi-square's
/// degrees of freedom are `n - k` with `k` every free parameter the model
/// carries ([`carried_free_params`]), or `free_params` when a caller
/// counts more: one model reads the same in every command and on the page.
pub fn compare(
    model: &Model,
    data: &Dataset,
    free_params: usize,
) -> Result<Comparison, ModelError> {
    let free_params = free_params.max(carried_free_params(model));
    let mut cases = Vec::with_capacity(data.cases.len());
    let mut all = Vec::new();
    for case in &data.cases {
        let p = model.predict(case)?;
        let res = case_residuals(case, &p);
        let get = |q: Quantity| res.iter().find(|(k, _)| *k == q).map(|(_, r)| *r);
        let (ru, ro) = (get(Quantity::U), get(Quantity::Omega));
        cases.push(CaseComparison {
            id: case.id.clone(),
            frequency_hz: case.frequency_hz,
            n_waves: case.n_waves(),
            amplitude_ratio: case.amplitude_ratio(),
            u_pred_mm_s: p.u_mm_s,
            u_obs_mm_s: case.u_mm_s.map(|m| m.mean),
            u_ci_mm_s: case.u_mm_s.map(|m| m.ci_half_width),
            omega_pred_hz: p.omega_body_hz,
            omega_obs_hz: case.omega_body_hz.map(|m| m.mean),
            omega_ci_hz: case.omega_body_hz.map(|m| m.ci_half_width),
            u_rel_err: ru.map(|r| r.relative_error()),
            omega_rel_err: ro.map(|r| r.relative_error()),
            u_err_sigma: ru.map(|r| r.normalised()),
            omega_err_sigma: ro.map(|r| r.normalised()),
            u_over_u_wave_pred: p.u_over_u_wave,
            omega_ratio_pred: p.omega_ratio,
            u_input_sd_mm_s: None,
            omega_input_sd_hz: None,
            u_over_u_wave_input_sd: None,
            omega_ratio_input_sd: None,
            u_dominant_input: None,
            omega_dominant_input: None,
            u_err_sigma_combined: None,
            omega_err_sigma_combined: None,
            recorded: case.recorded.clone(),
        });
        all.extend(res.into_iter().map(|(_, r)| r));
    }
    Ok(Comparison {
        model: model.describe(),
        dataset: data.name.clone(),
        cases,
        summary: summarise(&all, free_params),
        summary_combined: None,
        coverage: None,
        chi2_correlated: None,
    })
}

/// [`compare`] with the input bands attached whenever the data declare
/// input uncertainties, however costly the model: what the zero-parameter
/// model on the page and `compare --input-uncertainty` show. Each shared
/// input costs one solve per perturbed geometry (memoised, the same for
/// every case), each per-case input two per case.
pub fn compare_with_input_bands(model: &Model, data: &Dataset) -> Result<Comparison, ModelError> {
    let cmp = compare(model, data, carried_free_params(model))?;
    if super::propagate::has_input_uncertainty(data) {
        Ok(cmp.with_bands(data, &super::propagate::bands(model, data)?))
    } else {
        Ok(cmp)
    }
}
