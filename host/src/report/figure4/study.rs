//! The study page's layers of Fig. 4 ([`super`]), for data of the paper's
//! design: the measurements (red, their CIs), the model before the step
//! (grey, hollow) and after it (blue, filled) at each case. Drawn from the
//! study's stored predictions alone ([`CaseRow`]): markers at the cases,
//! no curve between them (a curve would be a prediction the study does not
//! hold), a logarithmic y axis where a panel's values span more than a
//! factor of four.
//!
//! The layout is the paper's when the data are: one tube and one oil (the
//! figure's axes hold nothing else), two to four amplitude groups (a row
//! of panels fits the page), and `N_lambda` varying within a group. Other
//! designs get the parity plot and the residual against the step's
//! feature ([`crate::report::study_page`]).

use super::{dodge_percent, letters, Group, Layers, Marker, Marks, ModelLayer, Point};
use crate::chart::{Rgb, PALETTE};
use crate::data::Dataset;
use crate::report::html::{html, omega_b};
use crate::report::page::Part;
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
) -> Vec<Point> {
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

/// The measured values of `rows` with their CIs.
fn measured(data: &Dataset, rows: &[&CaseRow], omega: bool) -> Vec<Point> {
    points(data, rows, omega, |r| {
        if omega {
            Some((r.omega_obs_hz?, r.omega_ci_hz.unwrap_or(0.0)))
        } else {
            Some((r.u_obs_mm_s?, r.u_ci_mm_s.unwrap_or(0.0)))
        }
    })
}

/// The stored predictions of `rows`, as markers without a bar.
fn predicted(data: &Dataset, rows: &[&CaseRow], omega: bool) -> Marks {
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
    Marks {
        points: points(data, rows, omega, pred),
        curve: Vec::new(),
    }
}

/// The layers of a step: the groups of the rows `after` it, the model
/// before it (`before`, the group at the same place) and after it.
pub fn layers(data: &Dataset, before: &[CaseRow], after: &[CaseRow]) -> Layers {
    let g_after = groups(after);
    let g_before = groups(before);
    // the rows before the step in the after-groups' places
    let prior: Vec<Vec<&CaseRow>> = (0..g_after.len())
        .map(|i| g_before.get(i).map(|x| x.1.clone()).unwrap_or_default())
        .collect();
    let later: Vec<Vec<&CaseRow>> = g_after.iter().map(|x| x.1.clone()).collect();
    let model = |label: &str, color, marker, rows: &[Vec<&CaseRow>]| ModelLayer {
        label: label.into(),
        color,
        marker,
        groups: rows
            .iter()
            .map(|r| [predicted(data, r, false), predicted(data, r, true)])
            .collect(),
    };
    Layers {
        ci: crate::report::intro::confidence(data),
        groups: g_after
            .iter()
            .map(|(ratio, rows)| Group {
                ratio: *ratio,
                n_waves: rows.iter().map(|r| r.n_waves).collect(),
                measured: [measured(data, rows, false), measured(data, rows, true)],
            })
            .collect(),
        models: vec![
            model("before the step", BEFORE, Marker::Hollow, &prior),
            model("after the step", PALETTE[0], Marker::Filled, &later),
        ],
        log_y_when_wide: true,
    }
}

/// The figure of step `n` (`name` the effect it adds), before and after
/// on every panel.
pub fn figure(data: &Dataset, n: usize, name: &str, before: &[CaseRow], after: &[CaseRow]) -> Part {
    let layers = layers(data, before, after);
    let (last_u, first_w, last_w) = letters(layers.groups.len());
    let ci = &layers.ci;
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
    super::figure(&format!("fig-step-{n}"), &layers, caption)
}
