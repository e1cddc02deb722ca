//! The paper's Fig. 4 (U/U_wave and Omega_b/omega against the number of
//! waves N_lambda, per amplitude group): measurements with their 95 % CIs,
//! the model at the measured cases and the model's curves.

use super::plots::{chart, Series, PALETTE};
use crate::data::{Case, Dataset};
use crate::model::Model;
use crate::workbench::compare::Comparison;

/// Amplitude groups `(B_o, cases)` in the order of first appearance.
pub fn amplitude_groups(data: &Dataset) -> Vec<(f64, Vec<&Case>)> {
    let mut groups: Vec<(f64, Vec<&Case>)> = Vec::new();
    for c in &data.cases {
        match groups
            .iter_mut()
            .find(|g| (g.0 - c.amplitude_mm).abs() < 1e-9)
        {
            Some(g) => g.1.push(c),
            None => groups.push((c.amplitude_mm, vec![c])),
        }
    }
    groups
}

/// The model's curve for one amplitude group at the group's mean chord
/// length and rate, over the wavelengths around the measured ones (the
/// paper kept the chord length fixed and varied the wavelength).
fn model_curve(
    model: &Model,
    cases: &[&Case],
    ratio_of: fn(&crate::model::Prediction) -> f64,
) -> Vec<(f64, f64, f64)> {
    let chord = cases
        .iter()
        .map(|c| c.helix().arc_length_m() * 1e3)
        .sum::<f64>()
        / cases.len() as f64;
    let (lmin, lmax) = cases.iter().fold((f64::MAX, f64::MIN), |(a, b), c| {
        (a.min(c.wavelength_mm), b.max(c.wavelength_mm))
    });
    let mut template = cases[0].clone();
    template.u_mm_s = None;
    template.omega_body_hz = None;
    (0..40)
        .filter_map(|i| {
            let lambda = 0.7 * lmin + (1.3 * lmax - 0.7 * lmin) * i as f64 / 39.0;
            let k = 2.0 * std::f64::consts::PI * template.amplitude_mm / lambda;
            let length = chord / (1.0 + k * k).sqrt();
            let c = Case {
                wavelength_mm: lambda,
                tail_length_mm: length,
                ..template.clone()
            };
            let p = model.predict(&c).ok()?;
            Some((c.n_waves(), ratio_of(&p), 0.0))
        })
        .collect()
}

pub fn figure4(
    model: &Model,
    data: &Dataset,
    cmp: &Comparison,
    omega: bool,
) -> Result<String, String> {
    let mut series = Vec::new();
    for (gi, (b, cases)) in amplitude_groups(data).iter().enumerate() {
        let color = PALETTE[gi % PALETTE.len()];
        let label = format!("B_o/R_body = {:.2}", b / (0.5 * cases[0].body_diameter_mm));
        let measured: Vec<(f64, f64, f64)> = cases
            .iter()
            .filter_map(|c| {
                let wave = if omega {
                    c.frequency_hz
                } else {
                    c.wavelength_mm * c.frequency_hz
                };
                let m = if omega { c.omega_body_hz } else { c.u_mm_s }?;
                Some((c.n_waves(), m.mean / wave, m.ci_half_width / wave))
            })
            .collect();
        let predicted: Vec<(f64, f64, f64)> = cases
            .iter()
            .filter_map(|c| {
                let k = cmp.cases.iter().find(|k| k.id == c.id)?;
                // k = 2 input band (about 95 %), comparable with the measured CI.
                let band = if omega {
                    k.omega_ratio_input_sd
                } else {
                    k.u_over_u_wave_input_sd
                };
                Some((
                    c.n_waves(),
                    if omega {
                        k.omega_ratio_pred
                    } else {
                        k.u_over_u_wave_pred
                    },
                    2.0 * band.unwrap_or(0.0),
                ))
            })
            .collect();
        let ratio: fn(&crate::model::Prediction) -> f64 = if omega {
            |p| p.omega_ratio
        } else {
            |p| p.u_over_u_wave
        };
        series.push(Series::measured(
            format!("{label} measured"),
            color,
            measured,
        ));
        series.push(Series::model(format!("{label} model"), color, predicted));
        series.push(Series::curve(
            String::new(),
            color,
            model_curve(model, cases, ratio),
        ));
    }
    let (title, y) = if omega {
        ("Body rotation (cf. paper Fig. 4 d-f)", "Omega_b / omega")
    } else {
        ("Swimming speed (cf. paper Fig. 4 a-c)", "U / U_wave")
    };
    chart(title, "number of waves N_lambda", y, &series, false)
}
