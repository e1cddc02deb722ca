//! Input uncertainty -> prediction uncertainty (GUM law of propagation).
//!
//! Linearised: for each input `x_j` with standard uncertainty `u_j` (the
//! dataset's `uncertainty` tables, [`crate::data::uncertainty`]), the
//! sensitivity `c_j = dy/dx_j` of each output `y` (U, Omega_b and their
//! dimensionless forms) is a central finite difference of
//! [`Model::predict`] with the relative step `h_j = 1e-4 max(|x_j|, u_j)`,
//! and the inputs of one case are taken as uncorrelated:
//! `u_c(y)^2 = sum_j (c_j u_j)^2` (GUM eq. 10). The largest `|c_j u_j|` is
//! the input that dominates the case's band.
//!
//! The Monte-Carlo check (GUM Supplement 1) draws every uncertain input
//! from a normal distribution (seeded, one generator per draw so that the
//! result does not depend on the thread count; draws with a non-positive
//! length or rate are redrawn) and compares the spread of the predictions
//! with the linear band: a ratio away from 1 by more than 10 % marks the
//! linearisation as poor for that case.
//!
//! Combined with the measurement ([`combine`]): the standard errors add in
//! quadrature, `s_c^2 = s_m^2 + u_in^2`, and the effective degrees of
//! freedom follow Welch-Satterthwaite (GUM G.4.1) with the type-B input
//! uncertainty taken as exactly known (infinite degrees of freedom):
//! `nu_eff = nu_m (s_c / s_m)^4`, truncated down to an integer as GUM
//! prescribes. The combined value is stored as a [`Measured`] (CI at the
//! same confidence, `trials = nu_eff + 1`) so that everything downstream
//! (residuals in standard errors, noise floors, weighted fits) uses it
//! unchanged.
//!
//! References: JCGM 100:2008 (GUM) eqs. 10, G.2b and G.4.1; JCGM 101:2008
//! (GUM Supplement 1, propagation of distributions by Monte Carlo).

use crate::data::uncertainty::{scope_of, set_field, Scope};
use crate::data::{Case, Dataset, Measured};
use crate::model::{Model, ModelError, Prediction};
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rayon::prelude::*;
use serde::Serialize;

/// Relative finite-difference step of the sensitivities.
const REL_STEP: f64 = 1e-4;
/// Cap on the effective degrees of freedom (beyond it t is normal anyway).
const MAX_DOF: f64 = 10_000.0;

/// One input's share of a case's band.
#[derive(Debug, Clone, Serialize)]
pub struct Contribution {
    pub field: &'static str,
    pub scope: Scope,
    /// The input's standard uncertainty, in its own unit.
    pub standard: f64,
    /// `c_j u_j` for U (mm/s) and Omega_b (Hz), signed.
    pub u_mm_s: f64,
    pub omega_hz: f64,
}

/// A case's input-uncertainty band (standard uncertainties, k = 1).
#[derive(Debug, Clone, Serialize)]
pub struct Band {
    pub id: String,
    pub u_sd_mm_s: f64,
    pub omega_sd_hz: f64,
    pub u_over_u_wave_sd: f64,
    pub omega_ratio_sd: f64,
    /// The part of the band from inputs recorded case by case (the rest is
    /// shared by all cases and cancels to first order in ratios).
    pub u_per_case_sd_mm_s: f64,
    pub omega_per_case_sd_hz: f64,
    pub dominant_u: Option<&'static str>,
    pub dominant_omega: Option<&'static str>,
    pub contributions: Vec<Contribution>,
}

fn outputs(p: &Prediction) -> [f64; 4] {
    [p.u_mm_s, p.omega_body_hz, p.u_over_u_wave, p.omega_ratio]
}

/// The linearised band of one case.
pub fn linear_band(model: &Model, case: &Case) -> Result<Band, ModelError> {
    let mut contributions = Vec::new();
    let (mut var, mut var_own) = ([0.0f64; 4], [0.0f64; 2]);
    for (field, u) in case.inputs.nonzero(case) {
        let x = crate::data::uncertainty::field_value(case, field).unwrap_or(0.0);
        let h = REL_STEP * x.abs().max(u);
        let at = |v: f64| -> Result<[f64; 4], ModelError> {
            let mut c = case.clone();
            set_field(&mut c, field, v);
            Ok(outputs(&model.predict(&c)?))
        };
        let (hi, lo) = (at(x + h)?, at(x - h)?);
        let d: Vec<f64> = (0..4).map(|k| (hi[k] - lo[k]) / (2.0 * h) * u).collect();
        for k in 0..4 {
            var[k] += d[k] * d[k];
        }
        if scope_of(field) == Scope::PerCase {
            var_own[0] += d[0] * d[0];
            var_own[1] += d[1] * d[1];
        }
        contributions.push(Contribution {
            field,
            scope: scope_of(field),
            standard: u,
            u_mm_s: d[0],
            omega_hz: d[1],
        });
    }
    let dominant = |f: fn(&Contribution) -> f64| {
        contributions
            .iter()
            .filter(|c| f(c) != 0.0)
            .max_by(|a, b| f(a).abs().total_cmp(&f(b).abs()))
            .map(|c| c.field)
    };
    Ok(Band {
        id: case.id.clone(),
        u_sd_mm_s: var[0].sqrt(),
        omega_sd_hz: var[1].sqrt(),
        u_over_u_wave_sd: var[2].sqrt(),
        omega_ratio_sd: var[3].sqrt(),
        u_per_case_sd_mm_s: var_own[0].sqrt(),
        omega_per_case_sd_hz: var_own[1].sqrt(),
        dominant_u: dominant(|c| c.u_mm_s),
        dominant_omega: dominant(|c| c.omega_hz),
        contributions,
    })
}

/// The bands of every case (in parallel).
pub fn bands(model: &Model, data: &Dataset) -> Result<Vec<Band>, ModelError> {
    data.cases
        .par_iter()
        .map(|c| linear_band(model, c))
        .collect()
}

/// Whether any case of the dataset declares an input uncertainty.
pub fn has_input_uncertainty(data: &Dataset) -> bool {
    data.cases.iter().any(|c| !c.inputs.is_empty())
}

/// Whether bands come cheaply with every comparison: true for local models.
/// Each uncertain input of each case costs two more predictions, and every
/// perturbed geometry is a new cold solve for a non-local tail or a costly
/// (wall-resolved) effect: seconds to a minute each. Such models get bands
/// only when the user asks for them (`--input-uncertainty`).
pub fn affordable(model: &Model) -> bool {
    use crate::model::TailMethod;
    matches!(
        model.tail_method,
        TailMethod::Exact | TailMethod::Quadrature { .. }
    ) && model.effects.iter().all(|e| !e.effect.costly())
}

/// The Monte-Carlo check of one case's linear band.
#[derive(Debug, Clone, Serialize)]
pub struct MonteCarloCheck {
    pub id: String,
    pub draws: usize,
    /// Draws whose prediction failed (not counted in the spread).
    pub failed: usize,
    pub u_sd_mm_s: f64,
    pub omega_sd_hz: f64,
    /// Monte-Carlo spread over the linear band (1 where linear).
    pub u_sd_ratio: f64,
    pub omega_sd_ratio: f64,
    /// Mean of the draws minus the nominal prediction, in linear bands.
    pub u_bias_in_bands: f64,
    pub omega_bias_in_bands: f64,
    /// Some ratio is off by more than 10 %: the linear band is poor here.
    pub nonlinear: bool,
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, var.sqrt())
}

/// Draw the case's uncertain inputs `draws` times (seeded) and compare.
pub fn monte_carlo(
    model: &Model,
    case: &Case,
    band: &Band,
    draws: usize,
    seed: u64,
) -> Result<MonteCarloCheck, ModelError> {
    let nominal = model.predict(case)?;
    let inputs = case.inputs.nonzero(case);
    let samples: Vec<Option<[f64; 2]>> = (0..draws)
        .into_par_iter()
        .map(|k| {
            let mut rng = StdRng::seed_from_u64(
                seed.wrapping_add(0x9e37_79b9_7f4a_7c15u64.wrapping_mul(k as u64 + 1)),
            );
            let mut c = case.clone();
            for (field, u) in &inputs {
                let x = crate::data::uncertainty::field_value(case, field).unwrap_or(0.0);
                let normal = Normal::new(x, *u).expect("u > 0 is finite");
                // Lengths and rates are positive; a draw below zero is
                // redrawn. The trim is signed: every draw stands.
                let signed = crate::data::uncertainty::is_signed(field) || x <= 0.0;
                let v = (0..100)
                    .map(|_| normal.sample(&mut rng))
                    .find(|v| *v > 0.0 || signed)
                    .unwrap_or(x);
                set_field(&mut c, field, v);
            }
            model.predict(&c).ok().map(|p| [p.u_mm_s, p.omega_body_hz])
        })
        .collect();
    let ok: Vec<[f64; 2]> = samples.iter().flatten().copied().collect();
    let (mu, su) = mean_sd(&ok.iter().map(|s| s[0]).collect::<Vec<_>>());
    let (mo, so) = mean_sd(&ok.iter().map(|s| s[1]).collect::<Vec<_>>());
    let ratio = |mc: f64, lin: f64| if lin > 0.0 { mc / lin } else { f64::NAN };
    let bias = |m: f64, nom: f64, lin: f64| if lin > 0.0 { (m - nom) / lin } else { 0.0 };
    let (ru, ro) = (ratio(su, band.u_sd_mm_s), ratio(so, band.omega_sd_hz));
    let off = |r: f64| r.is_finite() && (r - 1.0).abs() > 0.10;
    Ok(MonteCarloCheck {
        id: case.id.clone(),
        draws,
        failed: draws - ok.len(),
        u_sd_mm_s: su,
        omega_sd_hz: so,
        u_sd_ratio: ru,
        omega_sd_ratio: ro,
        u_bias_in_bands: bias(mu, nominal.u_mm_s, band.u_sd_mm_s),
        omega_bias_in_bands: bias(mo, nominal.omega_body_hz, band.omega_sd_hz),
        nonlinear: off(ru) || off(ro),
    })
}

/// A measurement with an input uncertainty `u_in` (same unit) combined in
/// quadrature, degrees of freedom by Welch-Satterthwaite (module docs).
pub fn combine(m: &Measured, u_in: f64) -> Measured {
    if u_in.is_nan() || u_in <= 0.0 {
        return *m;
    }
    let s_m = m.standard_error();
    let s_c = (s_m * s_m + u_in * u_in).sqrt();
    let nu_m = f64::from(m.trials.max(2) - 1);
    let nu_eff = (nu_m * (s_c / s_m).powi(4)).min(MAX_DOF).floor().max(1.0);
    let trials = nu_eff as u32 + 1;
    Measured {
        mean: m.mean,
        ci_half_width: crate::stats::student_t_quantile(m.confidence, trials) * s_c,
        confidence: m.confidence,
        trials,
    }
}

/// The dataset with every measured CI widened by the input uncertainty of
/// the prediction `model` makes for it: what `compare --input-uncertainty`
/// and `diagnose --input-uncertainty` judge residuals against.
pub fn with_input_uncertainty(model: &Model, data: &Dataset) -> Result<Dataset, ModelError> {
    let bands = bands(model, data)?;
    let mut out = data.clone();
    for (c, b) in out.cases.iter_mut().zip(&bands) {
        c.u_mm_s = c.u_mm_s.map(|m| combine(&m, b.u_sd_mm_s));
        c.omega_body_hz = c.omega_body_hz.map(|m| combine(&m, b.omega_sd_hz));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_and_welch_satterthwaite() {
        let m = Measured {
            mean: 1.0,
            ci_half_width: crate::stats::student_t_quantile(0.95, 5) * 0.3,
            confidence: 0.95,
            trials: 5,
        };
        let c = combine(&m, 0.4);
        assert!((c.standard_error() - 0.5).abs() < 1e-12);
        // nu = 4 (0.5/0.3)^4 = 30.86 -> 30 -> 31 trials
        assert_eq!(c.trials, 31);
        assert_eq!(combine(&m, 0.0), m);
    }
}
