//! The static HTML report: the comparison table and its charts, each an
//! inline SVG, in one self-contained page.

use super::figure4::figure4;
use super::parity::parity;
use super::path::error_falls;
use super::residuals::residual_plots;
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::compare::compare;
use crate::workbench::diagnose::Diagnosis;
use crate::workbench::propagate;
use std::fmt::Write;

fn svg_or_note(r: Result<String, String>) -> String {
    r.unwrap_or_else(|e| format!("<p class=\"err\">chart failed: {}</p>", escape(&e)))
}

pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The whole page.
pub fn page(
    model: &Model,
    data: &Dataset,
    diagnosis: Option<&Diagnosis>,
) -> Result<String, crate::model::ModelError> {
    let mut cmp = compare(model, data, 0)?;
    let with_bands = propagate::has_input_uncertainty(data) && propagate::affordable(model);
    if with_bands {
        cmp = cmp.with_bands(data, &propagate::bands(model, data)?);
    }
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>swimbot report</title><style>\
         body{{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}} table{{border-collapse:collapse}} \
         td,th{{padding:3px 8px;border-bottom:1px solid #ddd;text-align:right}} .figs{{display:flex;flex-wrap:wrap;gap:12px}} \
         .err{{color:#b00}} code{{background:#f4f4f4;padding:1px 4px}}</style></head><body>\
         <h1>swimbot: model against measurement</h1><p>model: <code>{}</code><br>data: <code>{}</code> ({})</p>",
        escape(&cmp.model),
        escape(&data.name),
        escape(&data.source)
    );
    let _ = write!(
        h,
        "<p>MARE {:.1} %, max |relative error| {:.1} %, reduced chi-square {}.</p>",
        100.0 * cmp.summary.mare,
        100.0 * cmp.summary.max_abs_rel_err,
        cmp.summary
            .chi2_reduced
            .map_or("n/a".into(), |x| format!("{x:.4}"))
    );
    h.push_str("<table><tr><th>case</th><th>f (Hz)</th><th>U pred</th><th>U obs ± CI</th><th>U err</th><th>Ω pred</th><th>Ω obs ± CI</th><th>Ω err</th></tr>");
    for k in &cmp.cases {
        let obs = |m: Option<f64>, c: Option<f64>| {
            m.zip(c)
                .map_or("-".into(), |(m, c)| format!("{m:.4} ± {c:.4}"))
        };
        let pct = |e: Option<f64>| e.map_or("-".into(), |e| format!("{:+.1} %", 100.0 * e));
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{:.3}</td><td>{:.4}</td><td>{}</td><td>{}</td><td>{:.4}</td><td>{}</td><td>{}</td></tr>",
            escape(&k.id),
            k.frequency_hz,
            k.u_pred_mm_s,
            obs(k.u_obs_mm_s, k.u_ci_mm_s),
            pct(k.u_rel_err),
            k.omega_pred_hz,
            obs(k.omega_obs_hz, k.omega_ci_hz),
            pct(k.omega_rel_err)
        );
    }
    h.push_str("</table><p>U in mm/s, Ω = body counter-rotation in Hz.</p>");
    if let Some(d) = diagnosis {
        let _ = write!(
            h,
            "<h2>Diagnosis</h2><p><b>{}</b></p>",
            escape(&d.verdict.note)
        );
    }
    h.push_str("<h2>Dimensionless speed and rotation against the number of waves</h2><p>Filled: measured (95 % CI); hollow: the model at the measured cases; lines: the model at each group's mean chord length, varying the wavelength (cases without measurements, so an observed-U back-flow falls back to the predicted U).</p>");
    if let (true, Some(sc)) = (with_bands, &cmp.summary_combined) {
        let _ = write!(
            h,
            "<p>Bars on the model's points (here and in the parity plots): ± 2 standard uncertainties of the prediction from the dataset's input uncertainties. Against measurement and inputs combined in quadrature the reduced chi-square is {}.</p>",
            sc.chi2_reduced.map_or("n/a".into(), |x| format!("{x:.4}"))
        );
    }
    h.push_str("<div class=\"figs\">");
    h.push_str(&svg_or_note(figure4(model, data, &cmp, false)));
    h.push_str(&svg_or_note(figure4(model, data, &cmp, true)));
    h.push_str("</div><h2>Parity</h2><div class=\"figs\">");
    h.push_str(&svg_or_note(parity(&cmp, false)));
    h.push_str(&svg_or_note(parity(&cmp, true)));
    h.push_str(
        "</div><h2>Where the model fails: residuals against case features</h2><div class=\"figs\">",
    );
    for r in residual_plots(data, &cmp) {
        h.push_str(&svg_or_note(r));
    }
    h.push_str("</div><h2>Watch the error fall</h2><div class=\"figs\">");
    for r in error_falls(model, data, diagnosis) {
        h.push_str(&svg_or_note(r));
    }
    h.push_str("</div></body></html>\n");
    Ok(h)
}
