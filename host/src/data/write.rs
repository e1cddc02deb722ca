//! [`Dataset`] -> TOML in the documented format (used by `swimbot synth`).
//! Every case is written in full, so the file does not depend on a [setup].

use super::{Dataset, Measured, Orientation};
use std::fmt::Write;

pub fn to_toml(data: &Dataset) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "name = {}", quoted(&data.name));
    let _ = writeln!(out, "source = {}", quoted(&data.source));
    for c in &data.cases {
        let _ = writeln!(out, "\n[[case]]");
        let _ = writeln!(out, "id = {}", quoted(&c.id));
        let num = |out: &mut String, k: &str, v: f64| {
            let _ = writeln!(out, "{k} = {v:?}");
        };
        num(&mut out, "wavelength_mm", c.wavelength_mm);
        num(&mut out, "amplitude_mm", c.amplitude_mm);
        num(&mut out, "tail_length_mm", c.tail_length_mm);
        num(&mut out, "wire_diameter_mm", c.wire_diameter_mm);
        let _ = writeln!(
            out,
            "handedness = {}",
            quoted(&format!("{:?}", c.handedness).to_lowercase())
        );
        num(&mut out, "frequency_hz", c.frequency_hz);
        num(&mut out, "channel_diameter_mm", c.channel_diameter_mm);
        num(&mut out, "channel_length_mm", c.channel_length_mm);
        let _ = writeln!(out, "channel_closed = {}", c.channel_closed);
        let orientation = match c.orientation {
            Orientation::Vertical => "vertical",
            Orientation::Horizontal => "horizontal",
        };
        let _ = writeln!(out, "orientation = {}", quoted(orientation));
        num(&mut out, "viscosity_pa_s", c.viscosity_pa_s);
        num(&mut out, "density_kg_m3", c.density_kg_m3);
        num(&mut out, "body_diameter_mm", c.body_diameter_mm);
        num(&mut out, "body_length_mm", c.body_length_mm);
        num(&mut out, "coupler_diameter_mm", c.coupler_diameter_mm);
        num(&mut out, "coupler_length_mm", c.coupler_length_mm);
        if c.coupler_gap_mm != super::DEFAULT_COUPLER_GAP_MM {
            num(&mut out, "coupler_gap_mm", c.coupler_gap_mm);
        }
        if let Some(crate::physics::profile::BodyProfile::Sections {
            sections,
            rounded_mm,
        }) = &c.body_profile
        {
            let pairs: Vec<String> = sections
                .iter()
                .map(|s| format!("[{:?}, {:?}]", s.length_mm, s.diameter_mm))
                .collect();
            let _ = writeln!(out, "body_profile = [{}]", pairs.join(", "));
            num(&mut out, "body_rounded_mm", *rounded_mm);
        }
        if c.net_weight_g != 0.0 {
            num(&mut out, "net_weight_g", c.net_weight_g);
        }
        let measured = |out: &mut String, mean_key: &str, ci_key: &str, m: &Option<Measured>| {
            if let Some(m) = m {
                let _ = writeln!(
                    out,
                    "{mean_key} = {:?}\n{ci_key} = {:?}",
                    m.mean, m.ci_half_width
                );
                let _ = writeln!(
                    out,
                    "confidence = {:?}\ntrials = {}",
                    m.confidence, m.trials
                );
            }
        };
        // The amplitude is written as the centre-line radius (the parser
        // converted it), so no amplitude convention is written.
        if let Some(l) = c.inputs.chord_length_mm {
            num(&mut out, "chord_length_mm", l);
        } else if c.inputs.chord_fixed {
            let _ = writeln!(out, "chord_fixed = true");
        }
        if !c.inputs.uncertainties.is_empty() {
            let kv: Vec<String> = c
                .inputs
                .uncertainties
                .iter()
                .map(|(k, u)| format!("{k} = {}", u.to_toml()))
                .collect();
            let _ = writeln!(out, "uncertainty = {{ {} }}", kv.join(", "));
        }
        measured(&mut out, "u_mm_s", "u_ci_mm_s", &c.u_mm_s);
        if c.u_mm_s.is_some() {
            if let Some(m) = &c.omega_body_hz {
                let _ = writeln!(
                    out,
                    "omega_body_hz = {:?}\nomega_body_ci_hz = {:?}",
                    m.mean, m.ci_half_width
                );
            }
        } else {
            measured(
                &mut out,
                "omega_body_hz",
                "omega_body_ci_hz",
                &c.omega_body_hz,
            );
        }
    }
    out.push_str(&super::rig::to_toml(&data.rig));
    out
}

fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}
