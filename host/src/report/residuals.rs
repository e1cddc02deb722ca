//! Residual plots: the relative error of U and of Omega_b, each against the
//! case features it correlates with most (ranked by
//! [`crate::workbench::features::trends`]): where the model fails.

use super::yours::BEFORE;
use crate::chart::Rgb;
use crate::chart::{unit, Chart, Series, PALETTE};
use crate::data::Dataset;
use crate::workbench::compare::{Comparison, Quantity};
use crate::workbench::features::{trends, FEATURES};

/// Plots per quantity.
const PER_QUANTITY: usize = 2;

pub fn residual_plots(data: &Dataset, cmp: &Comparison) -> Vec<crate::chart::PlotResult> {
    residual_plots_of(data, ("cases", cmp), None, PALETTE[1])
}

/// The residual plots of `(label, cmp)` in `color`, with `before`'s
/// residuals beside them (grey, hollow) on the same features.
pub fn residual_plots_of(
    data: &Dataset,
    (label, cmp): (&str, &Comparison),
    before: Option<(&str, &Comparison)>,
    color: Rgb,
) -> Vec<crate::chart::PlotResult> {
    let all = trends(data, cmp);
    [Quantity::U, Quantity::Omega]
        .into_iter()
        .flat_map(|q| {
            all.iter()
                .filter(move |t| t.quantity == q)
                .take(PER_QUANTITY)
        })
        .map(|t| {
            let f = FEATURES
                .iter()
                .find(|f| f.id == t.feature_id)
                .ok_or_else(|| crate::chart::ChartError::UnknownFeature {
                    id: t.feature_id.to_string(),
                })?;
            let points = |cmp: &Comparison| -> (Vec<_>, Vec<_>) {
                data.cases
                    .iter()
                    .zip(&cmp.cases)
                    .filter_map(|(c, k)| {
                        let e = match t.quantity {
                            Quantity::U => k.u().rel_err,
                            Quantity::Omega => k.omega().rel_err,
                        }?;
                        Some(((f.of(c), 100.0 * e, 0.0), k.id.clone()))
                    })
                    .unzip()
            };
            let (pts, labels) = points(cmp);
            let symbol = f.name.split(" = ").next().unwrap_or(f.name);
            let x_desc = match unit(f.unit) {
                Some(u) => format!("{} ({u})", f.name),
                None => f.name.to_string(),
            };
            let q = t.quantity.label();
            let mut series = Vec::new();
            if let Some((before_label, b)) = before {
                let (pts, _) = points(b);
                series.push(Series::model(before_label, BEFORE, pts));
            }
            series.push(
                Series::measured(format!("{label} (r = {:+.2})", t.r), color, pts).labels(labels),
            );
            Chart::new(
                &format!("{q} error against {symbol}"),
                &x_desc,
                &format!("{q}: (predicted - measured)/measured (%)"),
            )
            .zero_line()
            .render(&series)
        })
        .collect()
}
