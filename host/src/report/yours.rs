//! The section on the model the command was given (`--preset`,
//! `--effect`, `--effect-file`), rendered from the path the workbench
//! computed once ([`crate::workbench::path`]): every step with its
//! statistics and the change against the step before, its Fig. 4
//! analogue, parity and residual plots and the per-case table, each
//! showing the model before the last step beside the model after it.

use super::figure4::{figure4, Layer, GREEN};
use super::html::{escape, figure, figure_flow, table};
use super::path_chart::{chart, Metric};
use super::wording::{describe, pct, signed_pct, stat, value_unc};
use crate::chart::Rgb;
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::compare::{CaseComparison, Comparison};
use crate::workbench::path::{Path, Step};

/// The step before the last: grey, so the last step stands out.
pub const BEFORE: Rgb = Rgb(120, 120, 120);
/// Intermediate steps of a longer path.
const MIDDLE: [Rgb; 3] = [Rgb(148, 103, 189), Rgb(255, 127, 14), Rgb(23, 190, 207)];

/// Each step's colour: the last green, the one before it grey, the
/// start of a longer path and the steps between in the palette.
pub fn colors(n: usize) -> Vec<Rgb> {
    (0..n)
        .map(|i| match n - 1 - i {
            0 => GREEN,
            1 => BEFORE,
            k => MIDDLE[(k - 2) % MIDDLE.len()],
        })
        .collect()
}

/// "12 − 4 = 8": the stated degrees of freedom of a reduced chi-square.
pub fn dof_note(s: &crate::stats::FitSummary) -> String {
    match s.dof() {
        Some(d) => format!("{} − {} = {d}", s.n, s.free_params),
        None => format!("{} − {}: none left", s.n, s.free_params),
    }
}

/// The steps' table: one row per step, each against the step before.
pub fn steps_table(path: &Path, noise_mare: f64) -> (Vec<&'static str>, Vec<Vec<String>>) {
    let header = vec![
        "<step",
        "<model (cumulative)",
        "free parameters",
        "MARE",
        "MARE of U",
        "MARE of Ω<sub>b</sub>",
        "max |error|",
        "reduced χ²",
        "degrees of freedom",
        "<MARE against the step before",
    ];
    let rows = path
        .steps
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let m = s.summary();
            let (u, w) = super::paper::mare_by_quantity(&s.comparison);
            let change = match i.checked_sub(1).map(|j| &path.steps[j]) {
                None => "-".to_string(),
                Some(p) => {
                    let (a, b) = (p.summary().mare, m.mare);
                    let class = match super::wording::Change::of(a, b, noise_mare) {
                        super::wording::Change::Falls => "fall",
                        super::wording::Change::Rises => "rise",
                        super::wording::Change::Flat => "flat",
                    };
                    format!(
                        "<span class=\"{class}\">{}</span>",
                        describe(a, b, noise_mare, pct)
                    )
                }
            };
            vec![
                escape(&s.label),
                format!("<code>{}</code>", escape(&s.spec)),
                m.free_params.to_string(),
                pct(m.mare),
                pct(u),
                pct(w),
                pct(m.max_abs_rel_err),
                stat(m.chi2_reduced),
                dof_note(m),
                change,
            ]
        })
        .collect();
    (header, rows)
}

/// The cases where `cmp` predicts what this robot cannot do: a speed or
/// a body rate of the opposite sign to the measured one (swimming
/// backwards, the body turning with the tail).
pub fn impossible(cmp: &Comparison) -> Vec<String> {
    let flips = |pred: f64, obs: Option<f64>| obs.is_some_and(|o| o * pred < 0.0);
    cmp.cases
        .iter()
        .flat_map(|k| {
            let mut v = Vec::new();
            if flips(k.u_pred_mm_s, k.u_obs_mm_s) {
                v.push(format!(
                    "{}: U = {} mm/s against {} measured ({})",
                    k.id,
                    fmt_sig(k.u_pred_mm_s, 3),
                    fmt_sig(k.u_obs_mm_s.unwrap_or(f64::NAN), 3),
                    signed_pct(k.u_rel_err)
                ));
            }
            if flips(k.omega_pred_hz, k.omega_obs_hz) {
                v.push(format!(
                    "{}: Ω_b = {} Hz against {} measured ({})",
                    k.id,
                    fmt_sig(k.omega_pred_hz, 3),
                    fmt_sig(k.omega_obs_hz.unwrap_or(f64::NAN), 3),
                    signed_pct(k.omega_rel_err)
                ));
            }
            v
        })
        .collect()
}

/// A warning paragraph naming the impossible predictions of `name`, or nothing.
pub fn impossible_note(name: &str, cmp: &Comparison) -> String {
    let bad = impossible(cmp);
    if bad.is_empty() {
        return String::new();
    }
    format!(
        "<p class=\"err\"><b>Impossible predictions.</b> {} predicts a sign opposite to the \
         measurement (the robot swimming backwards, or its body turning with the tail) in {} of \
         {} cases: {}. Such a model is wrong in kind there, not only in size.</p>",
        escape(name),
        bad.len(),
        cmp.cases.len(),
        escape(&bad.join("; "))
    )
}

fn cell_pred(k: &CaseComparison, omega: bool) -> String {
    let (v, sd, e) = if omega {
        (k.omega_pred_hz, k.omega_input_sd_hz, k.omega_rel_err)
    } else {
        (k.u_pred_mm_s, k.u_input_sd_mm_s, k.u_rel_err)
    };
    let v = match sd {
        Some(s) if s > 0.0 => value_unc(v, 2.0 * s),
        _ => fmt_sig(v, 4),
    };
    // two lines, so the table stays within the page's width
    format!("{v}<br>({})", signed_pct(e))
}

fn cell_obs(m: Option<f64>, ci: Option<f64>) -> String {
    m.zip(ci).map_or("-".into(), |(m, c)| value_unc(m, c))
}

/// Per case: measured, the step before and the last step, with errors.
fn case_table(before: Option<&Step>, last: &Step, ci: &str) -> String {
    let band = |s: &Step| {
        if s.comparison.summary_combined.is_some() {
            " ± 2u"
        } else {
            ""
        }
    };
    let (b, l) = (before.map_or("", band), band(last));
    let mut header = vec![format!("<tail"), format!("U measured ± {ci} CI")];
    if before.is_some() {
        header.push(format!("U before the step{b} (error)"));
    }
    header.push(format!("U predicted{l} (error)"));
    header.push(format!("Ω<sub>b</sub> measured ± {ci} CI"));
    if before.is_some() {
        header.push(format!("Ω<sub>b</sub> before the step{b} (error)"));
    }
    header.push(format!("Ω<sub>b</sub> predicted{l} (error)"));
    let rows: Vec<Vec<String>> = last
        .comparison
        .cases
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let b = before.map(|b| &b.comparison.cases[i]);
            let mut r = vec![escape(&k.id), cell_obs(k.u_obs_mm_s, k.u_ci_mm_s)];
            r.extend(b.map(|b| cell_pred(b, false)));
            r.push(cell_pred(k, false));
            r.push(cell_obs(k.omega_obs_hz, k.omega_ci_hz));
            r.extend(b.map(|b| cell_pred(b, true)));
            r.push(cell_pred(k, true));
            r
        })
        .collect();
    let head: Vec<&str> = header.iter().map(String::as_str).collect();
    table(&head, &rows)
}

/// The section: `path` is the user's model taken apart into its steps.
pub fn section(data: &Dataset, path: &Path) -> String {
    let last = path.last();
    let before = path.before_last();
    let noise = super::path::noise_mare(data);
    let ci = super::intro::confidence(data);
    let mut h = format!(
        "<p>The model this page was asked for: <code>{}</code>. ",
        escape(&last.spec)
    );
    match before {
        Some(b) => h.push_str(&format!(
            "It is taken apart into {} cumulative steps: \"+ X\" means X added on top of the \
             step before, with every parameter as given. Its last step, <b>{}</b>, {} MARE \
             ({}) and takes the reduced χ² from {} to {}.</p>",
            path.steps.len(),
            escape(&last.label),
            describe(b.summary().mare, last.summary().mare, noise, pct),
            if super::wording::Change::of(b.summary().mare, last.summary().mare, noise)
                == super::wording::Change::Flat
            {
                "within the noise"
            } else {
                "beyond the noise"
            },
            stat(b.summary().chi2_reduced),
            stat(last.summary().chi2_reduced)
        )),
        None => h.push_str(
            "No effect was added to it: the figures show this model alone (add effects with \
             <code>--effect</code> or <code>--effect-file</code> to see each step against the \
             one before).</p>",
        ),
    }
    let (header, rows) = steps_table(path, noise);
    h.push_str(&table(&header, &rows));
    h.push_str(&format!(
        "<p class=\"note\">Reduced χ²: the squared errors in standard errors of the measured \
         means over n − k degrees of freedom, k every free parameter the model carries (fitted \
         by whoever set it); the same numbers as <code>swimbot compare</code> prints for each \
         step's model. A change of MARE below {} (the noise of the measured means) or below \
         {:.0} % of its value is no change.</p>",
        pct(noise),
        100.0 * super::wording::FLAT_SHARE
    ));
    if let Some(cov) = &last.comparison.coverage {
        h.push_str(&format!(
            "<p id=\"yours-coverage\">{}, judged against measurement and inputs combined: \
             <b>{}</b>; {} (<code>swimbot compare --input-uncertainty</code> prints the \
             same).</p>",
            escape(&last.label),
            escape(&cov.describe()),
            super::correlated::statistic(&last.comparison)
        ));
    }
    for s in &path.steps {
        h.push_str(&impossible_note(&s.label, &s.comparison));
    }
    if path.steps.len() >= 2 {
        let steps: Vec<super::path::Step> = path.steps.iter().map(as_path_step).collect();
        h.push_str(&figure(
            "yours-path",
            &[
                chart(&steps, Metric::Mare, None, noise),
                chart(&steps, Metric::Chi2, None, noise),
            ],
            2,
            "<b>The steps.</b> MARE and reduced χ² (log scale) of each step, each arrow from \
             the step before: green where it falls, red where it rises, grey within the noise.",
        ));
    }
    h.push_str(&fig4(data, path));
    h.push_str(&case_table(before, last, &ci));
    let shown: Vec<(&str, Rgb, &Comparison)> = match before {
        Some(b) => vec![
            (b.label.as_str(), super::yours::BEFORE, &b.comparison),
            (last.label.as_str(), GREEN, &last.comparison),
        ],
        None => vec![("the model", GREEN, &last.comparison)],
    };
    let (parity_caption, residual_caption) = if before.is_some() {
        (
            "<b>Parity.</b> Predicted against measured U and Ω<sub>b</sub> before the last \
             step (grey) and after it (green); on the diagonal the model would be exact.",
            "<b>Residuals.</b> The relative error against the case features the last step's \
             error correlates with most, after the step (green) and before it (grey).",
        )
    } else {
        (
            "<b>Parity.</b> Predicted against measured U and Ω<sub>b</sub>; on the diagonal \
             the model would be exact.",
            "<b>Residuals.</b> The relative error against the case features it correlates with \
             most.",
        )
    };
    h.push_str(&figure(
        "yours-parity",
        &[
            super::parity::parity_of(&shown, false),
            super::parity::parity_of(&shown, true),
        ],
        2,
        parity_caption,
    ));
    let residuals = super::residuals::residual_plots_of(
        data,
        (last.label.as_str(), &last.comparison),
        before.map(|b| (b.label.as_str(), &b.comparison)),
        GREEN,
    );
    if !residuals.is_empty() {
        h.push_str(&figure("yours-residuals", &residuals, 2, residual_caption));
    }
    h
}

fn as_path_step(s: &Step) -> super::path::Step {
    super::path::Step {
        label: s.label.clone(),
        what: s.spec.clone(),
        fitted: s.summary().free_params,
        mare: s.summary().mare,
        cv_mare: None,
        chi2_reduced: s.summary().chi2_reduced,
    }
}

fn fig4(data: &Dataset, path: &Path) -> String {
    let colors = colors(path.steps.len());
    let layers: Vec<Layer> = path
        .steps
        .iter()
        .zip(&colors)
        .map(|(s, c)| Layer {
            label: s.label.clone(),
            model: &s.model,
            comparison: &s.comparison,
            color: *c,
            curve: crate::workbench::propagate::affordable(&s.model),
        })
        .collect();
    let charts = figure4(data, &layers);
    let groups = super::figure4::amplitude_groups(data).len();
    figure_flow(
        "fig4-yours",
        Some(&charts.legend),
        &charts.panels,
        groups.max(1),
        &format!(
            "<b>Fig. 4 with the model asked for.</b> Measurements (red, {} CIs) against each \
             step: {}. Upper row U/U<sub>wave</sub>, lower row Ω<sub>b</sub>/ω, against \
             N<sub>λ</sub>, one panel per amplitude group; hollow markers: the step's model at \
             each case (with ± 2u bars where the dataset states input uncertainties); lines: the \
             same model between the cases of a group (none for a group of one case); an error \
             bar smaller than its marker is hidden by it. The models sit side by side, each \
             shifted with its bars and line by {dodge} % of the panel's width left or right of \
             the case's N<sub>λ</sub> in turn, so that bars at one case do not hide each other; \
             the measurements stay at their N<sub>λ</sub>.",
            super::intro::confidence(data),
            path.steps
                .iter()
                .zip(&colors)
                .map(|(s, c)| format!(
                    "{} ({}; MARE {})",
                    escape(&s.label),
                    color_name(*c),
                    pct(s.summary().mare)
                ))
                .collect::<Vec<_>>()
                .join(", "),
            dodge = super::figure4::dodge_percent(),
        ),
    )
}

fn color_name(c: Rgb) -> &'static str {
    match (c.0, c.1, c.2) {
        (44, 160, 44) => "green",
        (120, 120, 120) => "grey",
        (148, 103, 189) => "purple",
        (255, 127, 14) => "orange",
        _ => "cyan",
    }
}
