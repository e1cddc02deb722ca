//! The study page's figures for data of any design, drawn from the study's
//! stored predictions: a parity plot of a step (before and after on one
//! chart, both labelled by case) and the relative error against the step's
//! feature (the quantity its law names, else the geometry that varies
//! across the cases).

use crate::chart::{Axis, Chart, Series, PALETTE};
use crate::data::quantities::{by_id, FEATURES};
use crate::data::Dataset;
use crate::study::CaseRow;

pub fn parity(before: &[CaseRow], after: &[CaseRow], omega: bool) -> crate::chart::PlotResult {
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
        for c in rows {
            let (Some(obs), ci, pred) = pick(c) else {
                continue;
            };
            pts.push((obs, pred, 0.0));
            xe.push(ci.unwrap_or(0.0));
            ids.push(if measured {
                c.id.clone()
            } else {
                String::new()
            });
            all.extend([obs, pred]);
        }
        // The measured interval is drawn once, on the points after the
        // step; the points before are named by case in the figure's notes
        // as the labelled ones are.
        let s = if measured {
            Series::measured(label, color, pts).x_errors(xe).labels(ids)
        } else {
            Series::model(label, color, pts).names(ids)
        };
        series.push(s);
    }
    let mut chart = Chart::new(
        &format!("Parity: {q}"),
        &format!("{q} measured ({unit})"),
        &format!("{q} predicted ({unit})"),
    )
    .diagonal();
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

pub fn residuals(
    data: &Dataset,
    q: &crate::data::quantities::Quantity,
    before: &[CaseRow],
    after: &[CaseRow],
) -> crate::chart::PlotResult {
    let x_of = |id: &str| data.cases.iter().find(|c| c.id == id).map(|c| q.of(c));
    let mut series = Vec::new();
    for (label, rows, color, hollow) in [
        ("U before", before, crate::chart::Rgb(150, 150, 150), true),
        ("U after", after, PALETTE[0], false),
        ("Ω_b before", before, crate::chart::Rgb(230, 170, 170), true),
        ("Ω_b after", after, PALETTE[1], false),
    ] {
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
    Chart::new(
        &format!("Relative error against {}", q.name),
        &format!("{}{unit}", q.name),
        "relative error (%)",
    )
    .zero_line()
    .render(&series)
}
