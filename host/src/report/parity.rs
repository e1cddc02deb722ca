//! Parity plots: predicted against measured U and Omega_b, one point per case.

use super::plots::{chart, Series, PALETTE};
use crate::workbench::compare::Comparison;

pub fn parity(cmp: &Comparison, omega: bool) -> Result<String, String> {
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
    let s = Series::measured("cases", PALETTE[0], pts);
    chart(
        title,
        &format!("measured ({unit})"),
        &format!("predicted ({unit})"),
        &[s],
        true,
    )
}
