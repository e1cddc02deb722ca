//! The opening section: the robot, the data (the paper's Tables II and IV: geometry,
//! observed tail rate, measured speed and body rate with their CIs) and the
//! question, all read from the dataset.

use super::html::{html, omega_b, rich, table, Head};
use super::page::Part;
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

/// A setup field, its table header (physics notation) and its value in a case.
type SetupField = (&'static str, fn(&Case) -> f64);

/// The setup fields (tube, oil, body, wire) that differ between cases.
fn varying_setup(data: &Dataset) -> Vec<SetupField> {
    const FIELDS: [SetupField; 7] = [
        ("D_ch (mm)", |c| c.channel_diameter_mm),
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

pub fn section(data: &Dataset) -> Part {
    let Some(c0) = data.cases.first() else {
        return html! { p { "The dataset has no case." } }.into();
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
    let of = |f: fn(&Case) -> f64| span(data.cases.iter().map(f));
    let swims = match c0.orientation {
        crate::data::Orientation::Vertical => "upwards in",
        crate::data::Orientation::Horizontal => "along",
    };
    let closed = if c0.channel_closed { "closed" } else { "open" };
    let varying = varying_setup(data);
    let rows: Vec<Vec<String>> = data
        .cases
        .iter()
        .map(|c| {
            let mut row = vec![
                c.id.clone(),
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
    let mut header: Vec<Head> = vec![
        "<tail".into(),
        "λ (mm)".into(),
        Head::num(rich("B_o (mm)")),
        Head::num(rich("L_t (mm)")),
        "f (Hz)".into(),
        Head::num(rich("N_λ = L_t/λ")),
        Head::num(rich("B_o/R_body")),
        format!("U (mm/s) ± {ci} CI").into(),
        Head::num(html! { (omega_b()) " (Hz) ± " (ci) " CI" }),
    ];
    header.extend(varying.iter().map(|(name, _)| Head::num(rich(name))));
    Part::from(html! {
        p {
            "A centimetre-scale, bacteria-like robot: a sealed body ("
            (of(|c| c.body_length_mm)) " mm long, " (of(|c| c.body_diameter_mm))
            " mm across) with a DC motor turning a rigid helical tail of "
            (of(|c| c.wire_diameter_mm)) " mm copper wire; body and tail turn in opposite \
            directions. It swims " (swims) " a " (closed) " glass tube "
            (of(|c| c.channel_diameter_mm)) " mm across and " (of(|c| c.channel_length_mm))
            " mm long, filled with silicone oil of viscosity " (of(|c| c.viscosity_pa_s))
            " Pa s (Reynolds number far below one: viscous forces only). The dataset has "
            (n) " tails: wavelength λ " (of(|c| c.wavelength_mm)) " mm, amplitude B"
            sub { "o" } " " (of(|c| c.amplitude_mm)) " mm, axial length L" sub { "t" } " "
            (of(|c| c.tail_length_mm)) " mm, each with its observed tail rate f ("
            (of(|c| c.frequency_hz)) " Hz), and " (measured_n) " measured quantities: the \
            swimming speed U and the body's counter-rotation rate " (omega_b()) ", means of "
            (trials) " trials with " (ci) " confidence intervals."
        }
    })
    .with(table(&header, &rows))
    .with(html! {
        @if !varying.is_empty() {
            p.note {
                "The setup differs between cases: the columns after the measurements give \
                each case's own values (the ranges above span them)."
            }
        }
        p {
            b { "The question." } " Resistive-force theory (RFT) predicts U and " (omega_b())
            " from the geometry and the observed f alone. Does it reproduce these \
            measurements? The paper needed two fitted factors on the body's resistance to get \
            close. Where does the model fail, what do those factors stand for, and what is \
            still missing?"
        }
    })
}
