//! Section 5: the best model without a fitted parameter (`--preset
//! physics`: the tail as regularized Stokeslets inside the closed tube, the
//! body's profile solved exactly in the tube, the coupler), against the
//! measurements and against the paper's fitted model: its errors per
//! quantity and per case, and its markers in the Fig. 4 layout.

use super::figure4::{figure4, Layer, BLACK, GREEN};
use super::html::{escape, figure_flow, table};
use super::paper::{fitted_by_paper, summary_row, table_iii, PaperModels, SUMMARY_HEADER};
use super::story::ZeroParam;
use super::wording::{describe, pct, signed_pct, stat};
use crate::data::Dataset;
use crate::model::ModelError;
use crate::workbench::diagnose::Diagnosis;
use crate::workbench::path::compare_with_bands;

pub fn section(
    data: &Dataset,
    zero: &ZeroParam,
    paper: &PaperModels,
    d: Option<&Diagnosis>,
) -> Result<String, ModelError> {
    let (name, model) = match zero {
        ZeroParam::Skipped(why) => {
            return Ok(format!(
                "<p class=\"note\">Left out of this page: {}.</p>",
                escape(why)
            ))
        }
        ZeroParam::Model { name, model } => (name, *model),
    };
    let cmp = compare_with_bands(model, data)?;
    let fitted: usize = model.effects.iter().map(|e| e.free_indices().len()).sum();
    let noise = super::path::noise_mare(data);
    let mut h = format!(
        "<p><code>{}</code> = <code>{}</code>, {} fitted parameter{}: each effect is a stated \
         piece of physics computed for the robot's geometry, nothing is adjusted to the data. \
         Against the paper's Gray-Hancock model (with the factors the paper fitted: {}), MARE \
         {}; the reduced χ² {}.</p>",
        escape(name),
        escape(&model.describe()),
        fitted,
        if fitted == 1 { "" } else { "s" },
        table_iii(&paper.gray_hancock),
        describe(paper.gh.summary.mare, cmp.summary.mare, noise, pct),
        describe(
            paper.gh.summary.chi2_reduced.unwrap_or(f64::NAN),
            cmp.summary.chi2_reduced.unwrap_or(f64::NAN),
            d.and_then(|d| d.baseline.noise_floor_chi2_reduced)
                .unwrap_or(0.0),
            |x| stat(Some(x))
        ),
    );
    let mut rows = vec![
        summary_row(
            &format!("paper, Gray-Hancock, {}", table_iii(&paper.gray_hancock)),
            &fitted_by_paper(&paper.gray_hancock),
            &paper.gh,
        ),
        summary_row(
            &format!("paper, Lighthill, {}", table_iii(&paper.lighthill)),
            &fitted_by_paper(&paper.lighthill),
            &paper.li,
        ),
        summary_row(&escape(name), &fitted.to_string(), &cmp),
    ];
    if let Some(l) = d.and_then(|d| d.verdict.located.first()) {
        let k: usize = l.model.effects.iter().map(|e| e.free_indices().len()).sum();
        rows.push(vec![
            format!("diagnose's best: {}", escape(&l.describe())),
            format!("{k}, fitted"),
            pct(l.mare),
            "-".into(),
            "-".into(),
            "-".into(),
            stat(l.chi2_reduced),
        ]);
    }
    h.push_str(&table(&SUMMARY_HEADER, &rows));
    let case_rows: Vec<Vec<String>> = cmp
        .cases
        .iter()
        .zip(&paper.gh.cases)
        .map(|(z, p)| {
            vec![
                escape(&z.id),
                signed_pct(z.u_rel_err),
                signed_pct(p.u_rel_err),
                signed_pct(z.omega_rel_err),
                signed_pct(p.omega_rel_err),
            ]
        })
        .collect();
    h.push_str(&table(
        &[
            "<tail",
            &format!("U error, {}", escape(name)),
            "U error, paper",
            &format!("Ω<sub>b</sub> error, {}", escape(name)),
            "Ω<sub>b</sub> error, paper",
        ],
        &case_rows,
    ));
    let layers = [
        Layer {
            label: "paper (Gray-Hancock)".into(),
            model: &paper.gray_hancock,
            comparison: &paper.gh,
            color: BLACK,
            curve: true,
        },
        Layer {
            label: name.clone(),
            model,
            comparison: &cmp,
            color: GREEN,
            curve: false,
        },
    ];
    let groups = super::figure4::amplitude_groups(data).len();
    h.push_str(&figure_flow(
        "fig4-physics",
        &figure4(data, &layers),
        groups.max(1),
        &format!(
            "<b>The zero-parameter model in the layout of Fig. 4.</b> Measurements (red, {} \
             CI), the paper's Gray-Hancock model (black, markers and curve) and <code>{}</code> \
             (green markers at the measured cases, ± 2u where its input bands were computed; no \
             curve: each point between the cases would need its own solve of the tail in the \
             tube). An error bar smaller than its marker is hidden by it.",
            super::intro::confidence(data),
            escape(name)
        ),
    ));
    Ok(h)
}
