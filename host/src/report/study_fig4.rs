//! The paper's Fig. 4 layout on the study page, for data of the paper's
//! design: `U/U_wave` and `Omega_b/omega` against the number of waves
//! `N_lambda`, one panel per amplitude group `B_o/R_body`, with the
//! measurements (red, their CIs), the model before the step (grey, hollow)
//! and after it (blue, filled) at each case. Drawn from the study's stored
//! predictions alone: markers at the cases, no curve between them (a curve
//! would be a prediction the study does not hold).
//!
//! The layout is the paper's when the data are: one tube and one oil (the
//! figure's axes hold nothing else), two to four amplitude groups (a row
//! of panels fits the page), and `N_lambda` varying within a group. Other
//! designs get the parity plot and the residual against the step's
//! feature ([`super::study_page`]).
//!
//! Reference: the paper's Fig. 4 ("In-channel experiments on vertical
//! swimming with bacteria-like robots"; host/data/paper.csv).

use super::figure4::{dodge, dodge_percent, n_waves_range, panel_width, MEASURED};
use super::html::{figure_flow, html, omega_b};
use crate::chart::Rgb;
use crate::chart::{legend_only, Chart, Series, PALETTE};
use crate::data::Dataset;
use crate::study::CaseRow;

const BEFORE: Rgb = Rgb(150, 150, 150);

/// Amplitude groups `(B_o/R_body, rows)` in the order of first appearance.
fn groups(rows: &[CaseRow]) -> Vec<(f64, Vec<&CaseRow>)> {
    let mut g: Vec<(f64, Vec<&CaseRow>)> = Vec::new();
    for r in rows {
        match g
            .iter_mut()
            .find(|x| (x.0 - r.amplitude_ratio).abs() < 1e-9)
        {
            Some(x) => x.1.push(r),
            None => g.push((r.amplitude_ratio, vec![r])),
        }
    }
    g
}

/// Whether the data are of the paper's design (module docs).
pub fn applies(data: &Dataset, rows: &[CaseRow]) -> bool {
    let first = match data.cases.first() {
        Some(c) => c,
        None => return false,
    };
    let one_rig = data.cases.iter().all(|c| {
        c.channel_diameter_mm == first.channel_diameter_mm
            && c.viscosity_pa_s == first.viscosity_pa_s
    });
    let g = groups(rows);
    let spread = g.iter().any(|(_, r)| {
        r.iter()
            .any(|x| (x.n_waves - r[0].n_waves).abs() > 1e-6 * r[0].n_waves.abs())
    });
    one_rig && (2..=4).contains(&g.len()) && spread
}

/// `(x, y, error)` of one quantity of `rows`, scaled to the paper's
/// ratios; `which` picks `(value, error)` of a row.
fn points(
    data: &Dataset,
    rows: &[&CaseRow],
    omega: bool,
    which: impl Fn(&CaseRow) -> Option<(f64, f64)>,
) -> Vec<(f64, f64, f64)> {
    rows.iter()
        .filter_map(|r| {
            let case = data.cases.iter().find(|c| c.id == r.id)?;
            let scale = if omega {
                r.frequency_hz
            } else {
                case.wavelength_mm * r.frequency_hz
            };
            let (v, e) = which(r)?;
            Some((r.n_waves, v / scale, e / scale))
        })
        .collect()
}

/// The figure of step `n` (HTML), before and after on every panel.
pub fn figure(
    data: &Dataset,
    n: usize,
    name: &str,
    before: &[CaseRow],
    after: &[CaseRow],
) -> super::page::Part {
    let g_after = groups(after);
    let g_before = groups(before);
    let ci = super::intro::confidence(data);
    let mut panels = Vec::new();
    let mut legend = Err(crate::chart::ChartError::NoPanel);
    let mut letter = b'a';
    for omega in [false, true] {
        for (i, (ratio, rows)) in g_after.iter().enumerate() {
            let prior: Vec<&CaseRow> = g_before.get(i).map(|x| x.1.clone()).unwrap_or_default();
            let measured = points(data, rows, omega, |r| {
                if omega {
                    Some((r.omega_obs_hz?, r.omega_ci_hz.unwrap_or(0.0)))
                } else {
                    Some((r.u_obs_mm_s?, r.u_ci_mm_s.unwrap_or(0.0)))
                }
            });
            let pred = |r: &CaseRow| {
                Some((
                    if omega {
                        r.omega_pred_hz
                    } else {
                        r.u_pred_mm_s
                    },
                    0.0,
                ))
            };
            let series = vec![
                Series::measured(format!("measured ({ci} CI)"), MEASURED, measured),
                Series::model("before the step", BEFORE, points(data, &prior, omega, pred))
                    .dodged(dodge(0)),
                Series::measured(
                    "after the step",
                    PALETTE[0],
                    points(data, rows, omega, pred),
                )
                .dodged(dodge(1)),
            ];
            let title = format!(
                "({}) B_o/R_body = {}",
                letter as char,
                crate::format::fmt_sig(*ratio, 2)
            );
            let ns: Vec<f64> = rows.iter().map(|r| r.n_waves).collect();
            let (lo, hi) = n_waves_range(&ns);
            let y = if omega {
                "Omega_b / omega"
            } else {
                "U / U_wave"
            };
            let mut chart = Chart::new(&title, "N_lambda", y)
                .size(panel_width(g_after.len()), 330)
                .x_range(lo, hi)
                .without_hidden_note()
                .without_legend();
            // A base model several times off would squash the measurements
            // and the model after the step into a strip: a log axis keeps
            // both readable.
            let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
            let (y_lo, y_hi) = ys.fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
            if y_lo > 0.0 && y_hi / y_lo > 4.0 {
                chart = chart.log_y();
            }
            if panels.is_empty() {
                legend = legend_only(&chart, &series);
            }
            panels.push(chart.render(&series));
            letter = letter.wrapping_add(1);
        }
    }
    let k = g_after.len();
    let last_u = (b'a' + k as u8 - 1) as char;
    let (first_w, last_w) = ((b'a' + k as u8) as char, (b'a' + 2 * k as u8 - 1) as char);
    let n_lambda = html! { "N" sub { "λ" } };
    let caption = html! {
        b { "Step " (n) ", + " (name) ", in the layout of the paper's Fig. 4." } " (a)-("
        (last_u) ") U/U" sub { "wave" } ", U" sub { "wave" } " = λf; (" (first_w) ")-(" (last_w)
        ") " (omega_b()) "/ω, against " (n_lambda) " = L" sub { "t" } "/λ, one panel per \
        amplitude group: measured (red, " (ci) " CI), the model before the step (grey, hollow) \
        and after it (blue, filled) at each case, the study's stored predictions (no curve \
        between the cases; a logarithmic y axis where they span more than a factor of four). \
        The models sit " (dodge_percent()) " % of the panel's width left and right of the \
        case's " (n_lambda) "; an error bar smaller than its marker is hidden by it."
    };
    figure_flow(
        &format!("fig-step-{n}"),
        Some(&legend),
        &panels,
        k.max(1),
        caption,
    )
}
