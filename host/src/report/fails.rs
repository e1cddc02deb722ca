//! The section on where the paper's model (Gray-Hancock, Table III) fails,
//! case by case (prediction, measurement with its CI, relative error, error
//! in standard errors of the measured mean), as parity plots and as
//! residuals against the case features.

use super::html::{escape, figure, table};
use super::paper::PaperModels;
use super::parity::parity;
use super::residuals::residual_plots;
use super::wording::{signed_pct, stat, value_unc};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::compare::CaseComparison;

fn pred(v: f64, sd: Option<f64>) -> String {
    match sd {
        Some(s) if s > 0.0 => value_unc(v, s),
        _ => fmt_sig(v, 4),
    }
}

fn obs(m: Option<f64>, ci: Option<f64>) -> String {
    m.zip(ci).map_or("-".into(), |(m, c)| value_unc(m, c))
}

fn sigma(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| fmt_sig(v, 3))
}

/// One measured quantity's error: `(case, "U" or "Ω_b", relative error, error in σ)`.
pub type QuantityError = (String, &'static str, f64, Option<f64>);

/// Every measured quantity's error, U and Ω_b of each case, largest first.
pub fn quantity_errors(cases: &[CaseComparison]) -> Vec<QuantityError> {
    let mut errs: Vec<QuantityError> = cases
        .iter()
        .flat_map(|k| {
            [
                k.u_rel_err.map(|e| (k.id.clone(), "U", e, k.u_err_sigma)),
                k.omega_rel_err
                    .map(|e| (k.id.clone(), "Ω<sub>b</sub>", e, k.omega_err_sigma)),
            ]
        })
        .flatten()
        .collect();
    errs.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    errs
}

/// The quantity with the largest |relative error|.
fn worst(cases: &[CaseComparison]) -> Option<QuantityError> {
    quantity_errors(cases).into_iter().next()
}

pub fn section(data: &Dataset, paper: &PaperModels) -> Result<String, crate::model::ModelError> {
    let cmp = &paper.gh;
    let bands = cmp.cases.iter().any(|k| k.u_input_sd_mm_s.is_some());
    let rows: Vec<Vec<String>> = cmp
        .cases
        .iter()
        .map(|k| {
            vec![
                escape(&k.id),
                pred(k.u_pred_mm_s, k.u_input_sd_mm_s),
                obs(k.u_obs_mm_s, k.u_ci_mm_s),
                signed_pct(k.u_rel_err),
                sigma(k.u_err_sigma),
                pred(k.omega_pred_hz, k.omega_input_sd_hz),
                obs(k.omega_obs_hz, k.omega_ci_hz),
                signed_pct(k.omega_rel_err),
                sigma(k.omega_err_sigma),
            ]
        })
        .collect();
    let pred_head = if bands {
        "predicted ± inputs"
    } else {
        "predicted"
    };
    let mut h = format!(
        "<p>The paper's model with Gray-Hancock's coefficients and {}, case by case. \
         U in mm/s, Ω<sub>b</sub> (the body's counter-rotation) in Hz; measured: mean ± {} CI; \
         error in σ: the error in standard errors of the measured mean.{}</p>",
        super::paper::table_iii(&paper.gray_hancock),
        super::intro::confidence(data),
        if bands {
            " ± inputs: the prediction's standard uncertainty from the dataset's stated input \
             uncertainties (geometry, rate, viscosity)."
        } else {
            ""
        }
    );
    h.push_str(&table(
        &[
            "<tail",
            &format!("U {pred_head}"),
            "U measured",
            "U error",
            "U error (σ)",
            &format!("Ω<sub>b</sub> {pred_head}"),
            "Ω<sub>b</sub> measured",
            "Ω<sub>b</sub> error",
            "Ω<sub>b</sub> error (σ)",
        ],
        &rows,
    ));
    h.push_str(&super::yours::impossible_note(
        "The paper's model (Gray-Hancock)",
        cmp,
    ));
    h.push_str(&super::yours::impossible_note(
        "The paper's model with Lighthill's coefficients",
        &paper.li,
    ));
    if let Some((case, q, e, s)) = worst(&cmp.cases) {
        h.push_str(&format!(
            "<p>The largest error is {}'s {q}: {} ({} standard errors). Over all quantities: MARE \
             {}, reduced χ² {}: a root-mean-square error of {} standard errors of the measured \
             means.",
            escape(&case),
            signed_pct(Some(e)),
            sigma(s),
            super::wording::pct(cmp.summary.mare),
            stat(cmp.summary.chi2_reduced),
            cmp.summary
                .chi2_reduced
                .map_or("n/a".into(), |c| fmt_sig(c.sqrt(), 2)),
        ));
        if cmp.summary_combined.is_some() {
            h.push_str(&format!(
                " Judged against the measurement and the inputs' uncertainty: {}.",
                super::correlated::statistic(cmp)
            ));
        }
        h.push_str("</p>");
    }
    h.push_str(&figure(
        "parity",
        &[parity(cmp, false), parity(cmp, true)],
        2,
        "<b>Parity.</b> Predicted against measured U and Ω<sub>b</sub>, one point per tail; \
         on the diagonal the model would be exact.",
    ));
    let residuals = residual_plots(data, cmp);
    if !residuals.is_empty() {
        h.push_str(&figure(
            "residuals",
            &residuals,
            2,
            "<b>Residuals.</b> The relative error of each quantity against the case features \
             it correlates with most (r: Pearson's correlation): a trend says which property \
             of the tail the missing physics follows.",
        ));
    }
    Ok(h)
}
