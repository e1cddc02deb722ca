//! The study page's figures for data of any design, drawn from the study's
//! stored predictions: a parity plot of a step (before and after on one
//! chart; with more than [`LABEL_ALL_UP_TO`] cases only the
//! [`LABELLED_WORST`] worst after the step are named, the step's table
//! holds every case) and the relative error against the step's feature
//! (the quantity its law names, else the geometry that varies across the
//! cases), before and after in panels of their own when the error before
//! is many times the error after (one axis would flatten the after-values
//! onto zero). Each panel is drawn at the width it is shown at, two to a
//! row of the page, so that its text is the size it was drawn.

use crate::chart::{Axis, Chart, Series, PALETTE};
use crate::data::quantities::{by_id, FEATURES};
use crate::data::Dataset;
use crate::study::CaseRow;

/// Every case is named up to this many; above, only the worst few.
pub const LABEL_ALL_UP_TO: usize = 12;
/// How many cases are named above [`LABEL_ALL_UP_TO`]: those with the
/// largest relative error after the step.
pub const LABELLED_WORST: usize = 5;
/// A panel's size: two to a row of the page's 1240 px (16 px apart).
pub const PANEL_PX: (u32, u32) = (600, 400);
/// Before and after get panels of their own when the largest error before
/// is more than this many times the largest after.
pub const SPLIT_RATIO: f64 = 5.0;

/// The ids to name in a parity plot of `after`: every one, or the worst.
pub fn named_cases(after: &[CaseRow], omega: bool) -> Vec<String> {
    let err = |c: &CaseRow| if omega { c.omega_rel_err } else { c.u_rel_err }.map_or(0.0, f64::abs);
    let mut ids: Vec<&CaseRow> = after.iter().collect();
    if ids.len() > LABEL_ALL_UP_TO {
        ids.sort_by(|a, b| err(b).total_cmp(&err(a)));
        ids.truncate(LABELLED_WORST);
    }
    ids.iter().map(|c| c.id.clone()).collect()
}

pub fn parity(before: &[CaseRow], after: &[CaseRow], omega: bool) -> crate::chart::PlotResult {
    let named = named_cases(after, omega);
    let (q, unit) = if omega {
        ("Omega_b", "Hz")
    } else {
        ("U", "mm/s")
    };
    let pick = |c: &CaseRow| {
        if omega {
            (c.omega_obs_hz, c.omega_ci_hz, c.omega_pred_hz)
        } else {
            (c.u_obs_mm_s, c.u_ci_mm_s, c.u_pred_mm_s)
        }
    };
    let mut series = Vec::new();
    let mut all = Vec::new();
    for (label, rows, color, measured) in [
        ("before", before, crate::chart::Rgb(150, 150, 150), false),
        ("after", after, PALETTE[0], true),
    ] {
        let mut pts = Vec::new();
        let mut xe = Vec::new();
        let mut ids = Vec::new();
        let mut all_ids = Vec::new();
        for c in rows {
            let (Some(obs), ci, pred) = pick(c) else {
                continue;
            };
            pts.push((obs, pred, 0.0));
            xe.push(ci.unwrap_or(0.0));
            ids.push(if measured && named.contains(&c.id) {
                c.id.clone()
            } else {
                String::new()
            });
            all_ids.push(c.id.clone());
            all.extend([obs, pred]);
        }
        // The measured interval is drawn once, on the points after the
        // step; the points before are named by case in the figure's notes
        // as the labelled ones are.
        let s = if measured {
            Series::measured(label, color, pts)
                .x_errors(xe)
                .labels(ids)
                .names(all_ids)
        } else {
            Series::model(label, color, pts).names(all_ids)
        };
        series.push(s);
    }
    let mut chart = Chart::new(
        &format!("Parity: {q}"),
        &format!("{q} measured ({unit})"),
        &format!("{q} predicted ({unit})"),
    )
    .diagonal()
    .size(PANEL_PX.0, PANEL_PX.1);
    if Axis::spans_decade(all.into_iter()) {
        chart = chart.log_x().log_y();
    }
    chart.render(&series)
}

/// The quantity a step's law names (the first case quantity in its
/// formula), else the first of `N_lambda`, `B_o/R_body`, `f` that varies
/// across the cases (one shared value would collapse the axis).
pub fn feature_of(
    data: &Dataset,
    formula: &[String],
) -> &'static crate::data::quantities::Quantity {
    let named = formula.iter().find_map(|f| {
        f.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .filter_map(by_id)
            .find(|q| varies(data, q))
    });
    named.unwrap_or_else(|| {
        ["n_waves", "amplitude_ratio", "frequency"]
            .iter()
            .filter_map(|id| by_id(id))
            .find(|q| varies(data, q))
            .unwrap_or(&FEATURES[0])
    })
}

fn varies(data: &Dataset, q: &crate::data::quantities::Quantity) -> bool {
    let v: Vec<f64> = data.cases.iter().map(|c| q.of(c)).collect();
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(*x), h.max(*x))
        });
    hi - lo > 1e-9 * hi.abs().max(1.0)
}

/// The relative error against `q`: one panel with before and after, or
/// two (before, then after) when one axis would flatten the after-values
/// ([`SPLIT_RATIO`]).
pub fn residuals(
    data: &Dataset,
    q: &crate::data::quantities::Quantity,
    before: &[CaseRow],
    after: &[CaseRow],
) -> Vec<crate::chart::PlotResult> {
    let largest = |rows: &[CaseRow]| {
        rows.iter()
            .flat_map(|c| [c.u_rel_err, c.omega_rel_err])
            .flatten()
            .fold(0.0_f64, |m, e| m.max(e.abs()))
    };
    if largest(before) > SPLIT_RATIO * largest(after) {
        vec![
            residual_panel(data, q, Some(before), None),
            residual_panel(data, q, None, Some(after)),
        ]
    } else {
        vec![residual_panel(data, q, Some(before), Some(after))]
    }
}

fn residual_panel(
    data: &Dataset,
    q: &crate::data::quantities::Quantity,
    before: Option<&[CaseRow]>,
    after: Option<&[CaseRow]>,
) -> crate::chart::PlotResult {
    let x_of = |id: &str| data.cases.iter().find(|c| c.id == id).map(|c| q.of(c));
    let mut series = Vec::new();
    for (label, rows, color, hollow) in [
        ("U before", before, crate::chart::Rgb(150, 150, 150), true),
        ("U after", after, PALETTE[0], false),
        ("Ω_b before", before, crate::chart::Rgb(230, 170, 170), true),
        ("Ω_b after", after, PALETTE[1], false),
    ] {
        let Some(rows) = rows else {
            continue;
        };
        let omega = label.starts_with('Ω');
        let pts: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter_map(|c| {
                let e = if omega { c.omega_rel_err } else { c.u_rel_err }?;
                Some((x_of(&c.id)?, 100.0 * e, 0.0))
            })
            .collect();
        series.push(if hollow {
            Series::model(label, color, pts)
        } else {
            Series::measured(label, color, pts)
        });
    }
    let unit = if q.unit.is_empty() || q.unit == "1" {
        String::new()
    } else {
        format!(" ({})", q.unit)
    };
    let when = match (before, after) {
        (Some(_), None) => " before the step",
        (None, Some(_)) => " after the step",
        _ => "",
    };
    Chart::new(
        &format!("Relative error{when} against {}", q.name),
        &format!("{}{unit}", q.name),
        "relative error (%)",
    )
    .size(PANEL_PX.0, PANEL_PX.1)
    .zero_line()
    .render(&series)
}
