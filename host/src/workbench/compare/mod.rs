//! Model against measurement, case by case: predicted and observed swimming
//! speed `U` and body rotation rate `Omega_b`, their relative errors and
//! errors in standard errors, and the summary statistics (MARE, max
//! relative error, reduced chi-square).

pub mod case;

pub use self::case::{CaseComparison, Quantity, QuantityComparison};
use super::input_covariance::{correlated_chi2_of, CorrelatedChi2};
use crate::data::{Case, Dataset, Measured};
use crate::model::{Model, ModelError, Prediction};
use crate::stats::{summarise, FitSummary, Residual};
use serde::Serialize;

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
            for q in Quantity::BOTH {
                let Some(e) = k[q].err_sigma_combined else {
                    continue;
                };
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
            let bands = [
                (Quantity::U, b.u_sd_mm_s, b.u_over_u_wave_sd, b.dominant_u),
                (
                    Quantity::Omega,
                    b.omega_sd_hz,
                    b.omega_ratio_sd,
                    b.dominant_omega,
                ),
            ];
            for (q, sd, ratio_sd, dominant) in bands {
                k[q].input_sd = Some(sd);
                k[q].ratio_input_sd = Some(ratio_sd);
                k[q].dominant_input = dominant.map(str::to_string);
            }
            let combined = |pred: f64, m: &Measured, u_in: f64| {
                let c = super::propagate::combine(m, u_in);
                Residual {
                    predicted: pred,
                    observed: c.mean,
                    sigma: c.standard_error(),
                }
            };
            if let Some(m) = &case.u_mm_s {
                let r = combined(k.u().pred, m, b.u_sd_mm_s);
                k[Quantity::U].err_sigma_combined = Some(r.normalised());
                all.push(r);
            }
            if let Some(m) = &case.omega_body_hz {
                let r = combined(k.omega().pred, m, b.omega_sd_hz);
                k[Quantity::Omega].err_sigma_combined = Some(r.normalised());
                all.push(r);
            }
        }
        self.summary_combined = Some(summarise(&all, self.summary.free_params));
        self.coverage = Some(Coverage::of_cases(&self.cases));
        let predicted: Vec<(f64, f64)> = self
            .cases
            .iter()
            .map(|k| (k.u().pred, k.omega().pred))
            .collect();
        self.chi2_correlated =
            correlated_chi2_of(data, &predicted, bands, self.summary.free_params);
        self
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
            quantities: [
                QuantityComparison {
                    pred: p.u_mm_s,
                    obs: case.u_mm_s.map(|m| m.mean),
                    ci: case.u_mm_s.map(|m| m.ci_half_width),
                    rel_err: ru.map(|r| r.relative_error()),
                    err_sigma: ru.map(|r| r.normalised()),
                    ratio_pred: p.u_over_u_wave,
                    ..QuantityComparison::default()
                },
                QuantityComparison {
                    pred: p.omega_body_hz,
                    obs: case.omega_body_hz.map(|m| m.mean),
                    ci: case.omega_body_hz.map(|m| m.ci_half_width),
                    rel_err: ro.map(|r| r.relative_error()),
                    err_sigma: ro.map(|r| r.normalised()),
                    ratio_pred: p.omega_ratio,
                    ..QuantityComparison::default()
                },
            ],
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
