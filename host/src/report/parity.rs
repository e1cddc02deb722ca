//! Parity plots: predicted against measured U and Omega_b, one labelled
//! point per case, the measured 95 % CI as horizontal bars, the
//! prediction's input band (k = 2) as vertical bars, and the line y = x;
//! log axes when the values span more than a decade.

use crate::chart::Rgb;
use crate::chart::{Axis, Chart, Glyph, Series, PALETTE};
use crate::workbench::compare::{Comparison, Quantity};

/// The colour of the legend's error-bar entries (they stand for every series).
const REF: Rgb = Rgb(80, 80, 80);

/// The parity plot of one comparison.
pub fn parity(cmp: &Comparison, q: Quantity) -> crate::chart::PlotResult {
    parity_of(&[("case: predicted vs measured", PALETTE[0], cmp)], q)
}

/// The parity plot of several models `(label, colour, comparison)` on one
/// chart: the first labelled by case, all with both kinds of error bar.
pub fn parity_of(
    models: &[(&str, Rgb, &Comparison)],
    quantity: Quantity,
) -> crate::chart::PlotResult {
    let (q, unit) = (quantity.label(), quantity.unit());
    let mut series = Vec::new();
    let mut has_band = false;
    let mut all = Vec::new();
    for (i, (label, color, cmp)) in models.iter().enumerate() {
        let mut pts = Vec::new();
        let mut x_err = Vec::new();
        let mut labels = Vec::new();
        let mut names = Vec::new();
        for k in &cmp.cases {
            let c = &k[quantity];
            let (obs, ci, pred, sd) = (c.obs, c.ci, c.pred, c.input_sd);
            let Some(obs) = obs else { continue };
            pts.push((obs, pred, 2.0 * sd.unwrap_or(0.0)));
            x_err.push(ci.unwrap_or(0.0));
            names.push(k.id.clone());
            labels.push(if i + 1 == models.len() {
                k.id.clone()
            } else {
                String::new()
            });
        }
        has_band |= pts.iter().any(|p| p.2 > 0.0);
        all.extend(pts.iter().flat_map(|p| [p.0, p.1]));
        let s = if models.len() == 1 {
            Series::measured(*label, *color, pts)
        } else {
            Series::model(*label, *color, pts)
        };
        series.push(s.x_errors(x_err).labels(labels).names(names));
    }
    let log = Axis::spans_decade(all.into_iter());
    let mut chart = Chart::new(
        &format!("Parity: {q}"),
        &format!("{q} measured ({unit})"),
        &format!("{q} predicted ({unit})"),
    )
    .diagonal()
    .legend_entry(Glyph::HBar, REF, "measured 95 % CI");
    if has_band {
        chart = chart.legend_entry(Glyph::VBar, REF, "prediction ± 2u from inputs");
    }
    if log {
        chart = chart.log_x().log_y();
    }
    chart.render(&series)
}
