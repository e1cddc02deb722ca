//! The section on where the paper's model (Gray-Hancock, Table III) fails,
//! case by case (prediction, measurement with its CI, relative error, error
//! in standard errors of the measured mean), as parity plots and as
//! residuals against the case features.

use super::html::{figure, html, omega_b, rich, table, Head};
use super::page::Part;
use super::paper::PaperModels;
use super::parity::parity;
use super::residuals::residual_plots;
use super::wording::{signed_pct, stat, value_unc};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::compare::{CaseComparison, Quantity};

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

/// One measured quantity's error: `(case, "U" or "Ω_b" (physics notation:
/// [`super::html::rich`] draws it), relative error, error in σ)`.
pub type QuantityError = (String, &'static str, f64, Option<f64>);

/// Every measured quantity's error, U and Ω_b of each case, largest first.
pub fn quantity_errors(cases: &[CaseComparison]) -> Vec<QuantityError> {
    let mut errs: Vec<QuantityError> = cases
        .iter()
        .flat_map(|k| {
            [
                k.u()
                    .rel_err
                    .map(|e| (k.id.clone(), "U", e, k.u().err_sigma)),
                k.omega()
                    .rel_err
                    .map(|e| (k.id.clone(), "Ω_b", e, k.omega().err_sigma)),
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

pub fn section(data: &Dataset, paper: &PaperModels) -> Result<Part, crate::model::ModelError> {
    let cmp = &paper.gh;
    let bands = cmp.cases.iter().any(|k| k.u().input_sd.is_some());
    let rows: Vec<Vec<String>> = cmp
        .cases
        .iter()
        .map(|k| {
            vec![
                k.id.clone(),
                pred(k.u().pred, k.u().input_sd),
                obs(k.u().obs, k.u().ci),
                signed_pct(k.u().rel_err),
                sigma(k.u().err_sigma),
                pred(k.omega().pred, k.omega().input_sd),
                obs(k.omega().obs, k.omega().ci),
                signed_pct(k.omega().rel_err),
                sigma(k.omega().err_sigma),
            ]
        })
        .collect();
    let pred_head = if bands {
        "predicted ± inputs"
    } else {
        "predicted"
    };
    let w = |rest: &str| Head::num(html! { (omega_b()) " " (rest) });
    let header: [Head; 9] = [
        "<tail".into(),
        format!("U {pred_head}").into(),
        "U measured".into(),
        "U error".into(),
        "U error (σ)".into(),
        w(pred_head),
        w("measured"),
        w("error"),
        w("error (σ)"),
    ];
    let residuals = residual_plots(data, cmp);
    let mut out = Part::from(html! {
        p {
            "The paper's model with Gray-Hancock's coefficients and "
            (super::paper::table_iii(&paper.gray_hancock)) ", case by case. U in mm/s, "
            (omega_b()) " (the body's counter-rotation) in Hz; measured: mean ± "
            (super::intro::confidence(data)) " CI; error in σ: the error in standard errors \
            of the measured mean."
            @if bands {
                " ± inputs: the prediction's standard uncertainty from the dataset's stated \
                input uncertainties (geometry, rate, viscosity)."
            }
        }
    });
    out.push(table(&header, &rows));
    out.push(html! {
        (super::yours::impossible_note("The paper's model (Gray-Hancock)", cmp))
        (super::yours::impossible_note(
            "The paper's model with Lighthill's coefficients",
            &paper.li,
        ))
        @if let Some((case, q, e, s)) = worst(&cmp.cases) {
            p {
                "The largest error is " (case) "'s " (rich(q)) ": " (signed_pct(Some(e))) " ("
                (sigma(s)) " standard errors). Over all quantities: MARE "
                (super::wording::pct(cmp.summary.mare)) ", reduced χ² "
                (stat(cmp.summary.chi2_reduced)) ": a root-mean-square error of "
                (cmp.summary.chi2_reduced.map_or("n/a".into(), |c| fmt_sig(c.sqrt(), 2)))
                " standard errors of the measured means."
                @if cmp.summary_combined.is_some() {
                    " Judged against the measurement and the inputs' uncertainty: "
                    (super::correlated::statistic(cmp)) "."
                }
            }
        }
    });
    out.push(figure(
        "parity",
        &[parity(cmp, Quantity::U), parity(cmp, Quantity::Omega)],
        2,
        html! {
            b { "Parity." } " Predicted against measured U and " (omega_b()) ", one point \
            per tail; on the diagonal the model would be exact."
        },
    ));
    if !residuals.is_empty() {
        out.push(figure(
            "residuals",
            &residuals,
            2,
            html! {
                b { "Residuals." } " The relative error of each quantity against the case \
                features it correlates with most (r: Pearson's correlation): a trend says \
                which property of the tail the missing physics follows."
            },
        ));
    }
    Ok(out)
}
