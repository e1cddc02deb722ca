//! The static HTML report: the comparison table and its charts, each an
//! inline SVG, in one self-contained page.

use super::plots::{chart, steps, Series, PALETTE};
use crate::data::{Case, Dataset};
use crate::model::Model;
use crate::workbench::compare::{compare, Comparison};
use crate::workbench::diagnose::Diagnosis;
use crate::workbench::features::{trends, FEATURES};
use crate::workbench::propagate;
use std::fmt::Write;

/// Amplitude groups `(B_o, cases)` in the order of first appearance.
fn amplitude_groups(data: &Dataset) -> Vec<(f64, Vec<&Case>)> {
    let mut groups: Vec<(f64, Vec<&Case>)> = Vec::new();
    for c in &data.cases {
        match groups
            .iter_mut()
            .find(|g| (g.0 - c.amplitude_mm).abs() < 1e-9)
        {
            Some(g) => g.1.push(c),
            None => groups.push((c.amplitude_mm, vec![c])),
        }
    }
    groups
}

/// The model's curve for one amplitude group at the group's mean chord
/// length and rate, over the wavelengths around the measured ones (the
/// paper kept the chord length fixed and varied the wavelength).
fn model_curve(
    model: &Model,
    cases: &[&Case],
    ratio_of: fn(&crate::model::Prediction) -> f64,
) -> Vec<(f64, f64, f64)> {
    let chord = cases
        .iter()
        .map(|c| c.helix().arc_length_m() * 1e3)
        .sum::<f64>()
        / cases.len() as f64;
    let (lmin, lmax) = cases.iter().fold((f64::MAX, f64::MIN), |(a, b), c| {
        (a.min(c.wavelength_mm), b.max(c.wavelength_mm))
    });
    let mut template = cases[0].clone();
    template.u_mm_s = None;
    template.omega_body_hz = None;
    (0..40)
        .filter_map(|i| {
            let lambda = 0.7 * lmin + (1.3 * lmax - 0.7 * lmin) * i as f64 / 39.0;
            let k = 2.0 * std::f64::consts::PI * template.amplitude_mm / lambda;
            let length = chord / (1.0 + k * k).sqrt();
            let c = Case {
                wavelength_mm: lambda,
                tail_length_mm: length,
                ..template.clone()
            };
            let p = model.predict(&c).ok()?;
            Some((c.n_waves(), ratio_of(&p), 0.0))
        })
        .collect()
}

fn figure4(model: &Model, data: &Dataset, cmp: &Comparison, omega: bool) -> Result<String, String> {
    let mut series = Vec::new();
    for (gi, (b, cases)) in amplitude_groups(data).iter().enumerate() {
        let color = PALETTE[gi % PALETTE.len()];
        let label = format!("B_o/R_body = {:.2}", b / (0.5 * cases[0].body_diameter_mm));
        let measured: Vec<(f64, f64, f64)> = cases
            .iter()
            .filter_map(|c| {
                let wave = if omega {
                    c.frequency_hz
                } else {
                    c.wavelength_mm * c.frequency_hz
                };
                let m = if omega { c.omega_body_hz } else { c.u_mm_s }?;
                Some((c.n_waves(), m.mean / wave, m.ci_half_width / wave))
            })
            .collect();
        let predicted: Vec<(f64, f64, f64)> = cases
            .iter()
            .filter_map(|c| {
                let k = cmp.cases.iter().find(|k| k.id == c.id)?;
                // k = 2 input band (about 95 %), comparable with the measured CI.
                let band = if omega {
                    k.omega_ratio_input_sd
                } else {
                    k.u_over_u_wave_input_sd
                };
                Some((
                    c.n_waves(),
                    if omega {
                        k.omega_ratio_pred
                    } else {
                        k.u_over_u_wave_pred
                    },
                    2.0 * band.unwrap_or(0.0),
                ))
            })
            .collect();
        let ratio: fn(&crate::model::Prediction) -> f64 = if omega {
            |p| p.omega_ratio
        } else {
            |p| p.u_over_u_wave
        };
        series.push(Series {
            label: format!("{label} measured"),
            color,
            points: measured,
            line: false,
            hollow: false,
        });
        series.push(Series {
            label: format!("{label} model"),
            color,
            points: predicted,
            line: false,
            hollow: true,
        });
        series.push(Series {
            label: String::new(),
            color,
            points: model_curve(model, cases, ratio),
            line: true,
            hollow: false,
        });
    }
    let (title, y) = if omega {
        ("Body rotation (cf. paper Fig. 4 d-f)", "Omega_b / omega")
    } else {
        ("Swimming speed (cf. paper Fig. 4 a-c)", "U / U_wave")
    };
    chart(title, "number of waves N_lambda", y, &series, false)
}

fn parity(cmp: &Comparison, omega: bool) -> Result<String, String> {
    let pts: Vec<(f64, f64, f64)> = cmp
        .cases
        .iter()
        .filter_map(|k| {
            // Vertical bars: the prediction's k = 2 input band.
            if omega {
                Some((
                    k.omega_obs_hz?,
                    k.omega_pred_hz,
                    2.0 * k.omega_input_sd_hz.unwrap_or(0.0),
                ))
            } else {
                Some((
                    k.u_obs_mm_s?,
                    k.u_pred_mm_s,
                    2.0 * k.u_input_sd_mm_s.unwrap_or(0.0),
                ))
            }
        })
        .collect();
    let (title, unit) = if omega {
        ("Parity: Omega_b", "Hz")
    } else {
        ("Parity: U", "mm/s")
    };
    let s = Series {
        label: "cases".into(),
        color: PALETTE[0],
        points: pts,
        line: false,
        hollow: false,
    };
    chart(
        title,
        &format!("measured ({unit})"),
        &format!("predicted ({unit})"),
        &[s],
        true,
    )
}

fn residual_plots(data: &Dataset, cmp: &Comparison) -> Vec<Result<String, String>> {
    trends(data, cmp)
        .iter()
        .take(4)
        .map(|t| {
            let f = FEATURES
                .iter()
                .find(|f| f.name == t.feature)
                .expect("trend features come from FEATURES");
            let pts = data
                .cases
                .iter()
                .zip(&cmp.cases)
                .filter_map(|(c, k)| {
                    let e = match t.quantity {
                        crate::workbench::compare::Quantity::U => k.u_rel_err,
                        crate::workbench::compare::Quantity::Omega => k.omega_rel_err,
                    }?;
                    Some(((f.value)(c), e, 0.0))
                })
                .collect();
            let s = Series {
                label: format!("r = {:+.2}", t.r),
                color: PALETTE[1],
                points: pts,
                line: false,
                hollow: false,
            };
            chart(
                &format!("{} error vs {}", t.quantity.label(), t.feature),
                t.feature,
                "relative error",
                &[s],
                false,
            )
        })
        .collect()
}

/// MARE and reduced chi-square as the model's effects are added one by one
/// (then `diagnose`'s proposal, when given).
fn error_falls(
    model: &Model,
    data: &Dataset,
    diagnosis: Option<&Diagnosis>,
) -> Vec<Result<String, String>> {
    let mut labels = vec![model.coefficients.to_string()];
    let mut mare = Vec::new();
    let mut chi2 = Vec::new();
    let mut m = Model {
        effects: Vec::new(),
        ..model.clone()
    };
    let push = |m: &Model, mare: &mut Vec<f64>, chi2: &mut Vec<f64>| {
        let c = compare(m, data, 0).ok();
        mare.push(c.as_ref().map_or(f64::NAN, |c| 100.0 * c.summary.mare));
        chi2.push(c.and_then(|c| c.summary.chi2_reduced).unwrap_or(f64::NAN));
    };
    push(&m, &mut mare, &mut chi2);
    for e in &model.effects {
        m.effects.push(e.clone());
        labels.push(format!("+{}", e.name()));
        push(&m, &mut mare, &mut chi2);
    }
    if let Some(d) = diagnosis {
        let proposal = d
            .pairs
            .first()
            .filter(|_| d.ranking.first().is_none_or(|c| !c.at_noise_floor))
            .or(d.ranking.first());
        if let Some(c) = proposal {
            labels.push(format!("+{} (fitted)", c.effect));
            push(&c.model, &mut mare, &mut chi2);
        }
    }
    vec![
        steps("Watch the error fall: MARE", "MARE (%)", &labels, &mare),
        steps(
            "... and the reduced chi-square",
            "chi-square / dof",
            &labels,
            &chi2,
        ),
    ]
}

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
