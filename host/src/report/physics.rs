//! The section on the best model without a fitted parameter (`--preset
//! physics`: the tail as regularized Stokeslets inside the closed tube, the
//! body's profile solved exactly in the tube, the coupler), against the
//! measurements and against the paper's fitted model: its errors per
//! quantity and per case, and its markers in the Fig. 4 layout.

use super::figure4::models::{layers, Fitted};
use super::figure4::{BLACK, GREEN};
use super::html::{html, omega_b, table, Head, Markup, Render};
use super::page::Part;
use super::paper::{fitted_by_paper, summary_header, summary_row, table_iii, PaperModels};
use super::story::ZeroParam;
use super::wording::{describe, pct, signed_pct, stat, value_unc};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::model::ModelError;
use crate::workbench::audit::Audit;
use crate::workbench::compare::{compare_with_input_bands, CaseComparison};
use crate::workbench::diagnose::Diagnosis;

/// `v ± 2u (error)`, or `v (error)` without a band.
fn predicted(v: f64, sd: Option<f64>, err: Option<f64>) -> String {
    let v = match sd {
        Some(u) if u > 0.0 => value_unc(v, 2.0 * u),
        _ => fmt_sig(v, 4),
    };
    format!("{v} ({})", signed_pct(err))
}

fn measured(m: Option<f64>, ci: Option<f64>) -> String {
    m.zip(ci).map_or("-".into(), |(m, c)| value_unc(m, c))
}

fn sigmas(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| fmt_sig(v, 3))
}

/// One tail: measured, predicted ± 2u with its error and the error in
/// combined standard deviations, the paper's error; U then Omega_b.
fn case_row(z: &CaseComparison, p: &CaseComparison) -> Vec<String> {
    vec![
        z.id.clone(),
        measured(z.u().obs, z.u().ci),
        predicted(z.u().pred, z.u().input_sd, z.u().rel_err),
        sigmas(z.u().err_sigma_combined),
        signed_pct(p.u().rel_err),
        measured(z.omega().obs, z.omega().ci),
        predicted(z.omega().pred, z.omega().input_sd, z.omega().rel_err),
        sigmas(z.omega().err_sigma_combined),
        signed_pct(p.omega().rel_err),
    ]
}

pub fn section(
    data: &Dataset,
    zero: &ZeroParam,
    paper: &PaperModels,
    d: Option<&Diagnosis>,
    audit: Option<&Audit>,
) -> Result<Part, ModelError> {
    let (name, model) = match zero {
        ZeroParam::Skipped(why) => {
            return Ok(html! { p.note { "Left out of this page: " (why) "." } }.into())
        }
        ZeroParam::Model { name, model } => (name, *model),
    };
    // The band of the zero-parameter prediction: its whole point is that
    // nothing was fitted, so only the inputs' uncertainty can widen it.
    let cmp = compare_with_input_bands(model, data)?;
    let fitted: usize = model.effects.iter().map(|e| e.free_indices().len()).sum();
    let noise = super::path::noise_mare(data);
    let intro = html! {
        p {
            code { (name) } " = " code { (model.describe()) } ", " (fitted) " fitted parameter"
            (if fitted == 1 { "" } else { "s" }) ": each effect is a stated piece of physics \
            computed for the robot's geometry, nothing is adjusted to the data. Against the \
            paper's Gray-Hancock model (with the factors the paper fitted: "
            (table_iii(&paper.gray_hancock)) "), MARE "
            (describe(paper.gh.summary.mare, cmp.summary.mare, noise, pct)) "; the reduced χ² "
            (describe(
                paper.gh.summary.chi2_reduced.unwrap_or(f64::NAN),
                cmp.summary.chi2_reduced.unwrap_or(f64::NAN),
                d.and_then(|d| d.baseline.noise_floor_chi2_reduced)
                    .unwrap_or(0.0),
                |x| stat(Some(x))
            ))
            "."
        }
    };
    let mut rows = vec![
        summary_row(
            html! { "paper, Gray-Hancock, " (table_iii(&paper.gray_hancock)) },
            &fitted_by_paper(&paper.gray_hancock),
            &paper.gh,
        ),
        summary_row(
            html! { "paper, Lighthill, " (table_iii(&paper.lighthill)) },
            &fitted_by_paper(&paper.lighthill),
            &paper.li,
        ),
        summary_row(name, &fitted.to_string(), &cmp),
    ];
    if let Some(l) = d.and_then(|d| d.verdict.located.first()) {
        let k: usize = l.model.effects.iter().map(|e| e.free_indices().len()).sum();
        rows.push(
            [
                format!("diagnose's best: {}", l.describe()),
                format!("{k}, fitted"),
                pct(l.score.mare),
                "-".into(),
                "-".into(),
                "-".into(),
                stat(l.score.chi2_reduced),
            ]
            .iter()
            .map(Render::render)
            .collect(),
        );
    }
    let case_rows: Vec<Vec<String>> = cmp
        .cases
        .iter()
        .zip(&paper.gh.cases)
        .map(|(z, p)| case_row(z, p))
        .collect();
    let ci = super::intro::confidence(data);
    let w = |rest: Markup| Head::num(html! { (omega_b()) " " (rest) });
    let case_header: [Head; 9] = [
        "<tail".into(),
        format!("U measured ± {ci} CI").into(),
        format!("U {name} ± 2u (error)").into(),
        "U error (combined σ)".into(),
        "U error, paper".into(),
        w(html! { "measured ± " (ci) " CI" }),
        w(html! { (name) " ± 2u (error)" }),
        w(html! { "error (combined σ)" }),
        w(html! { "error, paper" }),
    ];
    let models = [
        ("paper (Gray-Hancock)".to_string(), &paper.gh),
        ("paper (Lighthill)".to_string(), &paper.li),
    ];
    let fitted = [
        Fitted {
            label: "paper (Gray-Hancock)".into(),
            model: &paper.gray_hancock,
            comparison: &paper.gh,
            color: BLACK,
            curve: true,
        },
        Fitted {
            label: name.clone(),
            model,
            comparison: &cmp,
            color: GREEN,
            curve: false,
        },
    ];
    let fig = layers(data, &fitted);
    let n_lambda = html! { "N" sub { "λ" } };
    let caption = html! {
        b { "The zero-parameter model in the layout of Fig. 4." } " Measurements (red, " (ci)
        " CI), the paper's Gray-Hancock model (black, markers and curve) and " code { (name) }
        " (green markers at the measured cases, ± 2u where its input bands were computed; no \
        curve: each point between the cases would need its own solve of the tail in the \
        tube). An error bar smaller than its marker is hidden by it. The models sit side by \
        side, each shifted with its bars and line by " (super::figure4::dodge_percent())
        " % of the panel's width left or right of the case's " (n_lambda) " in turn, so that \
        bars at one case do not hide each other; the measurements stay at their " (n_lambda)
        "."
    };
    let mut out = Part::from(intro);
    out.push(table(&summary_header(), &rows));
    out.push(table(&case_header, &case_rows));
    out.push(html! {
        @if cmp.coverage.is_some() {
            p {
                "U in mm/s, " (omega_b()) " in Hz. ± 2u: twice the prediction's standard \
                uncertainty from the dataset's stated input uncertainties (geometry, rate, \
                viscosity, the body's section lengths, the trim, the coupler's gap); combined \
                σ: the error in standard deviations of measurement and inputs in quadrature."
            }
        }
        (super::physics_misses::list(data, &cmp, &models, d, audit))
    });
    out.push(super::correlated::pulls(&cmp));
    out.push(super::figure4::figure("fig4-physics", &fig, caption));
    Ok(out)
}
