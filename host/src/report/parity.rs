//! Parity plots: predicted against measured U and Omega_b, one labelled
//! point per case, the measured 95 % CI as horizontal bars, the
//! prediction's input band (k = 2) as vertical bars, and the line y = x;
//! log axes when the values span more than a decade.

use super::plots::{Axis, Chart, Glyph, Series, PALETTE};
use crate::workbench::compare::Comparison;

pub fn parity(cmp: &Comparison, omega: bool) -> Result<String, String> {
    let mut pts = Vec::new();
    let mut x_err = Vec::new();
    let mut labels = Vec::new();
    for k in &cmp.cases {
        let (obs, ci, pred, sd) = if omega {
            (
                k.omega_obs_hz,
                k.omega_ci_hz,
                k.omega_pred_hz,
                k.omega_input_sd_hz,
            )
        } else {
            (k.u_obs_mm_s, k.u_ci_mm_s, k.u_pred_mm_s, k.u_input_sd_mm_s)
        };
        let Some(obs) = obs else { continue };
        pts.push((obs, pred, 2.0 * sd.unwrap_or(0.0)));
        x_err.push(ci.unwrap_or(0.0));
        labels.push(k.id.clone());
    }
    let (q, unit) = if omega {
        ("Omega_b", "Hz")
    } else {
        ("U", "mm/s")
    };
    let has_band = pts.iter().any(|p| p.2 > 0.0);
    let log = Axis::spans_decade(pts.iter().flat_map(|p| [p.0, p.1]));
    let color = PALETTE[0];
    let mut chart = Chart::new(
        &format!("Parity: {q}"),
        &format!("{q} measured ({unit})"),
        &format!("{q} predicted ({unit})"),
    )
    .diagonal()
    .legend_entry(Glyph::HBar, color, "measured 95 % CI");
    if has_band {
        chart = chart.legend_entry(Glyph::VBar, color, "prediction ± 2σ from inputs");
    }
    if log {
        chart = chart.log_x().log_y();
    }
    let s = Series::measured("case: predicted vs measured", color, pts)
        .x_errors(x_err)
        .labels(labels);
    chart.render(&[s])
}
