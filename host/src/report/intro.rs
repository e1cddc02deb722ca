//! The opening section: the robot, the data (the paper's Tables II and IV: geometry,
//! observed tail rate, measured speed and body rate with their CIs) and the
//! question, all read from the dataset.

use super::html::{escape, table};
use super::wording::value_unc;
use crate::data::{Case, Dataset, Measured};
use crate::format::fmt_sig;

fn span(values: impl Iterator<Item = f64>) -> String {
    let v: Vec<f64> = values.collect();
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if (hi - lo).abs() <= 1e-12 * hi.abs() {
        fmt_sig(lo, 3)
    } else {
        format!("{}-{}", fmt_sig(lo, 3), fmt_sig(hi, 3))
    }
}

/// The dataset's confidence level as printed (`95 %`), from its first measurement.
pub fn confidence(data: &Dataset) -> String {
    data.cases
        .iter()
        .find_map(|c| c.u_mm_s.or(c.omega_body_hz))
        .map(|m| format!("{:.0} %", 100.0 * m.confidence))
        .unwrap_or_else(|| "-".into())
}

/// A setup field, its table header and its value in a case.
type SetupField = (&'static str, fn(&Case) -> f64);

/// The setup fields (tube, oil, body, wire) that differ between cases.
fn varying_setup(data: &Dataset) -> Vec<SetupField> {
    const FIELDS: [SetupField; 7] = [
        ("D<sub>ch</sub> (mm)", |c| c.channel_diameter_mm),
        ("channel length (mm)", |c| c.channel_length_mm),
        ("μ (Pa s)", |c| c.viscosity_pa_s),
        ("wire (mm)", |c| c.wire_diameter_mm),
        ("body length (mm)", |c| c.body_length_mm),
        ("body diameter (mm)", |c| c.body_diameter_mm),
        ("ρ (kg/m³)", |c| c.density_kg_m3),
    ];
    FIELDS
        .into_iter()
        .filter(|(_, of)| {
            let v: Vec<f64> = data.cases.iter().map(of).collect();
            v.iter().any(|x| (x - v[0]).abs() > 1e-12 * v[0].abs())
        })
        .collect()
}

fn measured(m: Option<Measured>) -> String {
    m.map_or("-".into(), |m| value_unc(m.mean, m.ci_half_width))
}

pub fn section(data: &Dataset) -> String {
    let Some(c0) = data.cases.first() else {
        return "<p>The dataset has no case.</p>".into();
    };
    let n = data.cases.len();
    let measured_n = data
        .cases
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum::<usize>();
    let ci = confidence(data);
    let trials = data
        .cases
        .iter()
        .find_map(|c| c.u_mm_s.or(c.omega_body_hz))
        .map_or(0, |m| m.trials);
    let mut h = format!(
        "<p>A centimetre-scale, bacteria-like robot: a sealed body ({} mm long, {} mm across) \
         with a DC motor turning a rigid helical tail of {} mm copper wire; body and tail turn in \
         opposite directions. It swims {} a {} glass tube {} mm across and {} mm long, filled with \
         silicone oil of viscosity {} Pa s (Reynolds number far below one: viscous forces only). \
         The dataset has {n} tails: wavelength λ {} mm, amplitude B<sub>o</sub> {} mm, \
         axial length L<sub>t</sub> {} mm, each with its observed tail rate f ({} Hz), and \
         {measured_n} measured quantities: the swimming speed U and the body's counter-rotation \
         rate Ω<sub>b</sub>, means of {trials} trials with {ci} confidence intervals.</p>",
        span(data.cases.iter().map(|c| c.body_length_mm)),
        span(data.cases.iter().map(|c| c.body_diameter_mm)),
        span(data.cases.iter().map(|c| c.wire_diameter_mm)),
        match c0.orientation {
            crate::data::Orientation::Vertical => "upwards in",
            crate::data::Orientation::Horizontal => "along",
        },
        if c0.channel_closed { "closed" } else { "open" },
        span(data.cases.iter().map(|c| c.channel_diameter_mm)),
        span(data.cases.iter().map(|c| c.channel_length_mm)),
        span(data.cases.iter().map(|c| c.viscosity_pa_s)),
        span(data.cases.iter().map(|c| c.wavelength_mm)),
        span(data.cases.iter().map(|c| c.amplitude_mm)),
        span(data.cases.iter().map(|c| c.tail_length_mm)),
        span(data.cases.iter().map(|c| c.frequency_hz)),
    );
    let varying = varying_setup(data);
    let rows: Vec<Vec<String>> = data
        .cases
        .iter()
        .map(|c| {
            let mut row = vec![
                escape(&c.id),
                fmt_sig(c.wavelength_mm, 3),
                fmt_sig(c.amplitude_mm, 3),
                fmt_sig(c.tail_length_mm, 3),
                fmt_sig(c.frequency_hz, 3),
                fmt_sig(c.n_waves(), 3),
                fmt_sig(c.amplitude_ratio(), 2),
                measured(c.u_mm_s),
                measured(c.omega_body_hz),
            ];
            row.extend(varying.iter().map(|(_, of)| fmt_sig(of(c), 3)));
            row
        })
        .collect();
    let mut header = vec![
        "<tail".to_string(),
        "λ (mm)".into(),
        "B<sub>o</sub> (mm)".into(),
        "L<sub>t</sub> (mm)".into(),
        "f (Hz)".into(),
        "N<sub>λ</sub> = L<sub>t</sub>/λ".into(),
        "B<sub>o</sub>/R<sub>body</sub>".into(),
        format!("U (mm/s) ± {ci} CI"),
        format!("Ω<sub>b</sub> (Hz) ± {ci} CI"),
    ];
    header.extend(varying.iter().map(|(name, _)| name.to_string()));
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    h.push_str(&table(&header, &rows));
    if !varying.is_empty() {
        h.push_str(
            "<p class=\"note\">The setup differs between cases: the columns after the \
             measurements give each case's own values (the ranges above span them).</p>",
        );
    }
    h.push_str(
        "<p><b>The question.</b> Resistive-force theory (RFT) predicts U and Ω<sub>b</sub> from \
         the geometry and the observed f alone. Does it reproduce these measurements? The paper \
         needed two fitted factors on the body's resistance to get close. Where does the model \
         fail, what do those factors stand for, and what is still missing?</p>",
    );
    h
}
