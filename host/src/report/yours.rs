//! The section on the model the command was given (`--preset`,
//! `--effect`, `--effect-file`), rendered from the path the workbench
//! computed once ([`crate::workbench::path`]): every step with its
//! statistics and the change against the step before, its Fig. 4
//! analogue, parity and residual plots and the per-case table, each
//! showing the model before the last step beside the model after it.

use super::figure4::models::{layers, Fitted};
use super::figure4::GREEN;
use super::html::{figure, html, omega_b, table, Head, Markup};
use super::page::Part;
use super::path_chart::{chart, Metric};
use super::wording::{describe, pct, signed_pct, stat, value_unc};
use crate::chart::Rgb;
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::compare::{CaseComparison, Comparison, Quantity};
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
pub fn steps_table(path: &Path, noise_mare: f64) -> (Vec<Head>, Vec<Vec<Markup>>) {
    let header = vec![
        "<step".into(),
        "<model (cumulative)".into(),
        "free parameters".into(),
        "MARE".into(),
        "MARE of U".into(),
        Head::num(html! { "MARE of " (omega_b()) }),
        "max |error|".into(),
        "reduced χ²".into(),
        "degrees of freedom".into(),
        "<MARE against the step before".into(),
    ];
    let rows = path
        .steps
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let m = s.summary();
            let (u, w) = super::paper::mare_by_quantity(&s.comparison);
            let change = match i.checked_sub(1).map(|j| &path.steps[j]) {
                None => html! { "-" },
                Some(p) => {
                    let (a, b) = (p.summary().mare, m.mare);
                    let class = match super::wording::Change::of(a, b, noise_mare) {
                        super::wording::Change::Falls => "fall",
                        super::wording::Change::Rises => "rise",
                        super::wording::Change::Flat => "flat",
                    };
                    html! { span class=(class) { (describe(a, b, noise_mare, pct)) } }
                }
            };
            vec![
                html! { (s.label) },
                html! { code { (s.spec) } },
                html! { (m.free_params) },
                html! { (pct(m.mare)) },
                html! { (pct(u)) },
                html! { (pct(w)) },
                html! { (pct(m.max_abs_rel_err)) },
                html! { (stat(m.chi2_reduced)) },
                html! { (dof_note(m)) },
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
            if flips(k.u().pred, k.u().obs) {
                v.push(format!(
                    "{}: U = {} mm/s against {} measured ({})",
                    k.id,
                    fmt_sig(k.u().pred, 3),
                    fmt_sig(k.u().obs.unwrap_or(f64::NAN), 3),
                    signed_pct(k.u().rel_err)
                ));
            }
            if flips(k.omega().pred, k.omega().obs) {
                v.push(format!(
                    "{}: Ω_b = {} Hz against {} measured ({})",
                    k.id,
                    fmt_sig(k.omega().pred, 3),
                    fmt_sig(k.omega().obs.unwrap_or(f64::NAN), 3),
                    signed_pct(k.omega().rel_err)
                ));
            }
            v
        })
        .collect()
}

/// A warning paragraph naming the impossible predictions of `name`, or nothing.
pub fn impossible_note(name: &str, cmp: &Comparison) -> Markup {
    let bad = impossible(cmp);
    if bad.is_empty() {
        return html! {};
    }
    html! {
        p.err {
            b { "Impossible predictions." } " " (name) " predicts a sign opposite to the \
            measurement (the robot swimming backwards, or its body turning with the tail) in "
            (bad.len()) " of " (cmp.cases.len()) " cases: " (bad.join("; ")) ". Such a model \
            is wrong in kind there, not only in size."
        }
    }
}

fn cell_pred(k: &CaseComparison, q: Quantity) -> Markup {
    let (v, sd, e) = (k[q].pred, k[q].input_sd, k[q].rel_err);
    let v = match sd {
        Some(s) if s > 0.0 => value_unc(v, 2.0 * s),
        _ => fmt_sig(v, 4),
    };
    // two lines, so the table stays within the page's width
    html! { (v) br; "(" (signed_pct(e)) ")" }
}

fn cell_obs(m: Option<f64>, ci: Option<f64>) -> Markup {
    html! { (m.zip(ci).map_or("-".into(), |(m, c)| value_unc(m, c))) }
}

/// Per case: measured, the step before and the last step, with errors.
fn case_table(before: Option<&Step>, last: &Step, ci: &str) -> Part {
    let band = |s: &Step| {
        if s.comparison.summary_combined.is_some() {
            " ± 2u"
        } else {
            ""
        }
    };
    let (b, l) = (before.map_or("", band), band(last));
    let w = |rest: String| Head::num(html! { (omega_b()) " " (rest) });
    let mut header: Vec<Head> = vec!["<tail".into(), format!("U measured ± {ci} CI").into()];
    if before.is_some() {
        header.push(format!("U before the step{b} (error)").into());
    }
    header.push(format!("U predicted{l} (error)").into());
    header.push(w(format!("measured ± {ci} CI")));
    if before.is_some() {
        header.push(w(format!("before the step{b} (error)")));
    }
    header.push(w(format!("predicted{l} (error)")));
    let rows: Vec<Vec<Markup>> = last
        .comparison
        .cases
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let b = before.map(|b| &b.comparison.cases[i]);
            let mut r = vec![html! { (k.id) }, cell_obs(k.u().obs, k.u().ci)];
            r.extend(b.map(|b| cell_pred(b, Quantity::U)));
            r.push(cell_pred(k, Quantity::U));
            r.push(cell_obs(k.omega().obs, k.omega().ci));
            r.extend(b.map(|b| cell_pred(b, Quantity::Omega)));
            r.push(cell_pred(k, Quantity::Omega));
            r
        })
        .collect();
    table(&header, &rows)
}

/// The opening paragraph: the model asked for and what its last step does.
fn opening(path: &Path, noise: f64) -> Markup {
    let last = path.last();
    html! {
        p {
            "The model this page was asked for: " code { (last.spec) } ". "
            @match path.before_last() {
                Some(b) => {
                    "It is taken apart into " (path.steps.len()) " cumulative steps: \"+ X\" \
                    means X added on top of the step before, with every parameter as given. \
                    Its last step, " b { (last.label) } ", "
                    (describe(b.summary().mare, last.summary().mare, noise, pct)) " MARE ("
                    (if super::wording::Change::of(b.summary().mare, last.summary().mare, noise)
                        == super::wording::Change::Flat
                    {
                        "within the noise"
                    } else {
                        "beyond the noise"
                    })
                    ") and takes the reduced χ² from " (stat(b.summary().chi2_reduced)) " to "
                    (stat(last.summary().chi2_reduced)) "."
                }
                None => {
                    "No effect was added to it: the figures show this model alone (add effects \
                    with " code { "--effect" } " or " code { "--effect-file" } " to see each \
                    step against the one before)."
                }
            }
        }
    }
}

/// The section: `path` is the user's model taken apart into its steps.
pub fn section(data: &Dataset, path: &Path) -> Part {
    let last = path.last();
    let before = path.before_last();
    let noise = super::path::noise_mare(data);
    let ci = super::intro::confidence(data);
    let (header, rows) = steps_table(path, noise);
    let shown: Vec<(&str, Rgb, &Comparison)> = match before {
        Some(b) => vec![
            (b.label.as_str(), super::yours::BEFORE, &b.comparison),
            (last.label.as_str(), GREEN, &last.comparison),
        ],
        None => vec![("the model", GREEN, &last.comparison)],
    };
    let parity_caption = match before {
        Some(_) => html! {
            b { "Parity." } " Predicted against measured U and " (omega_b()) " before the last \
            step (grey) and after it (green); on the diagonal the model would be exact."
        },
        None => html! {
            b { "Parity." } " Predicted against measured U and " (omega_b()) "; on the \
            diagonal the model would be exact."
        },
    };
    let residual_caption = match before {
        Some(_) => html! {
            b { "Residuals." } " The relative error against the case features the last step's \
            error correlates with most, after the step (green) and before it (grey)."
        },
        None => html! {
            b { "Residuals." } " The relative error against the case features it correlates \
            with most."
        },
    };
    let residuals = super::residuals::residual_plots_of(
        data,
        (last.label.as_str(), &last.comparison),
        before.map(|b| (b.label.as_str(), &b.comparison)),
        GREEN,
    );
    let mut out = Part::from(opening(path, noise));
    out.push(table(&header, &rows));
    out.push(html! {
        p.note {
            "Reduced χ²: the squared errors in standard errors of the measured means over n − k \
            degrees of freedom, k every free parameter the model carries (fitted by whoever set \
            it); the same numbers as " code { "swimbot compare" } " prints for each step's \
            model. A change of MARE below " (pct(noise)) " (the noise of the measured means) or \
            below " (format!("{:.0}", 100.0 * super::wording::FLAT_SHARE)) " % of its value is \
            no change."
        }
        @if let Some(cov) = &last.comparison.coverage {
            p id="yours-coverage" {
                (last.label) ", judged against measurement and inputs combined: "
                b { (cov.describe()) } "; " (super::correlated::statistic(&last.comparison))
                " (" code { "swimbot compare --input-uncertainty" } " prints the same)."
            }
        }
        @for s in &path.steps {
            (impossible_note(&s.label, &s.comparison))
        }
    });
    if path.steps.len() >= 2 {
        out.push(steps_figure(path, noise));
    }
    out.push(fig4(data, path));
    out.push(case_table(before, last, &ci));
    out.push(figure(
        "yours-parity",
        &[
            super::parity::parity_of(&shown, Quantity::U),
            super::parity::parity_of(&shown, Quantity::Omega),
        ],
        2,
        parity_caption,
    ));
    if !residuals.is_empty() {
        out.push(figure("yours-residuals", &residuals, 2, residual_caption));
    }
    out
}

/// MARE and reduced chi-square along the steps, as the path charts.
fn steps_figure(path: &Path, noise: f64) -> Part {
    let steps: Vec<super::path::ChartStep> = path.steps.iter().map(as_path_step).collect();
    figure(
        "yours-path",
        &[
            chart(&steps, Metric::Mare, None, noise),
            chart(&steps, Metric::Chi2, None, noise),
        ],
        2,
        html! {
            b { "The steps." } " MARE and reduced χ² (log scale) of each step, each arrow from \
            the step before: green where it falls, red where it rises, grey within the noise."
        },
    )
}

fn as_path_step(s: &Step) -> super::path::ChartStep {
    super::path::ChartStep {
        label: s.label.clone(),
        what: s.spec.clone(),
        fitted: s.summary().free_params,
        mare: s.summary().mare,
        cv_mare: None,
        chi2_reduced: s.summary().chi2_reduced,
    }
}

fn fig4(data: &Dataset, path: &Path) -> Part {
    let colors = colors(path.steps.len());
    let fitted: Vec<Fitted> = path
        .steps
        .iter()
        .zip(&colors)
        .map(|(s, c)| Fitted {
            label: s.label.clone(),
            model: &s.model,
            comparison: &s.comparison,
            color: *c,
            curve: crate::workbench::propagate::affordable(&s.model),
        })
        .collect();
    let fig = layers(data, &fitted);
    let n_lambda = html! { "N" sub { "λ" } };
    let caption = html! {
        b { "Fig. 4 with the model asked for." } " Measurements (red, "
        (super::intro::confidence(data)) " CIs) against each step: "
        @for (i, (s, c)) in path.steps.iter().zip(&colors).enumerate() {
            @if i > 0 { ", " }
            (s.label) " (" (color_name(*c)) "; MARE " (pct(s.summary().mare)) ")"
        }
        ". Upper row U/U" sub { "wave" } ", lower row " (omega_b()) "/ω, against " (n_lambda)
        ", one panel per amplitude group; hollow markers: the step's model at each case (with \
        ± 2u bars where the dataset states input uncertainties); lines: the same model between \
        the cases of a group (none for a group of one case); an error bar smaller than its \
        marker is hidden by it. The models sit side by side, each shifted with its bars and \
        line by " (super::figure4::dodge_percent()) " % of the panel's width left or right of \
        the case's " (n_lambda) " in turn, so that bars at one case do not hide each other; the \
        measurements stay at their " (n_lambda) "."
    };
    super::figure4::figure("fig4-yours", &fig, caption)
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
