//! Which new experiment would tell two models apart: variations of the
//! existing cases (channel diameter, open or closed channel, tail rate,
//! amplitude, tail length), scored by how far the two fitted models'
//! predictions differ in units of the data's typical relative uncertainty.

use crate::data::{Case, Dataset};
use crate::model::Model;
use serde::Serialize;

#[derive(Debug, Clone, Serialize)]
pub struct Suggestion {
    pub base_case: String,
    pub change: String,
    /// Largest relative difference of U or Omega_b between the models.
    pub rel_difference: f64,
    pub quantity: &'static str,
    /// That difference in the data's median relative standard errors.
    pub in_sigma: f64,
}

fn variants(c: &Case) -> Vec<(String, Case)> {
    let mut v = Vec::new();
    for factor in [0.7, 1.5, 2.5] {
        let d = c.channel_diameter_mm * factor;
        let fits =
            c.amplitude_mm + 0.5 * c.wire_diameter_mm < 0.45 * d && c.body_diameter_mm < 0.95 * d;
        if fits {
            v.push((
                format!("channel_diameter_mm = {d:.1}"),
                Case {
                    channel_diameter_mm: d,
                    ..c.clone()
                },
            ));
        }
    }
    v.push((
        format!("channel_closed = {}", !c.channel_closed),
        Case {
            channel_closed: !c.channel_closed,
            ..c.clone()
        },
    ));
    for factor in [0.5, 2.0] {
        let f = c.frequency_hz * factor;
        v.push((
            format!("frequency_hz = {f:.3}"),
            Case {
                frequency_hz: f,
                ..c.clone()
            },
        ));
    }
    for factor in [0.6, 1.4] {
        let b = c.amplitude_mm * factor;
        if b + 0.5 * c.wire_diameter_mm < 0.45 * c.channel_diameter_mm {
            v.push((
                format!("amplitude_mm = {b:.2}"),
                Case {
                    amplitude_mm: b,
                    ..c.clone()
                },
            ));
        }
    }
    for factor in [0.5, 1.8] {
        let l = c.tail_length_mm * factor;
        v.push((
            format!("tail_length_mm = {l:.1}"),
            Case {
                tail_length_mm: l,
                ..c.clone()
            },
        ));
    }
    v
}

/// Median relative standard error of the data's measurements.
pub fn median_rel_se(data: &Dataset) -> f64 {
    let mut v: Vec<f64> = data
        .cases
        .iter()
        .flat_map(|c| [c.u_mm_s, c.omega_body_hz])
        .flatten()
        .map(|m| (m.standard_error() / m.mean).abs())
        .filter(|x| x.is_finite())
        .collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The single new case that best separates `a` from `b`.
pub fn best_discriminating_case(data: &Dataset, a: &Model, b: &Model) -> Option<Suggestion> {
    let se = median_rel_se(data);
    let mut best: Option<Suggestion> = None;
    for c in &data.cases {
        for (change, v) in variants(c) {
            let (Ok(pa), Ok(pb)) = (a.predict(&v), b.predict(&v)) else {
                continue;
            };
            for (q, x, y) in [
                ("U", pa.u_mm_s, pb.u_mm_s),
                ("Omega_b", pa.omega_body_hz, pb.omega_body_hz),
            ] {
                let rel = (x - y).abs() / (0.5 * (x.abs() + y.abs())).max(1e-300);
                if rel.is_finite() && best.as_ref().is_none_or(|s| rel > s.rel_difference) {
                    best = Some(Suggestion {
                        base_case: c.id.clone(),
                        change: change.clone(),
                        rel_difference: rel,
                        quantity: q,
                        in_sigma: rel / se,
                    });
                }
            }
        }
    }
    best
}
