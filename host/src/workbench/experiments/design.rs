//! What a design cannot separate: a field held at one value in every case
//! turns every effect of that field into a constant, and a dependence on
//! it into a dependence on whatever else varies. One tube cannot tell a
//! wall effect from a dependence on the helix or body geometry (every wall
//! feature, `R_h/gap` and the like, is a function of the geometry at one
//! diameter); one rate cannot tell a rate-dependent effect from a
//! constant; one oil cannot tell a viscous effect from a constant.
//!
//! **Predicted difference.** For a second tube, with a found model and
//! the model it corrects: the found correction, the relative change of U
//! or Omega_b it makes, is evaluated in the case's tube and in the other
//! tube. Read as a wall effect it follows the tube; read as a geometry
//! effect it keeps its value from the first tube. Their difference in the
//! case's relative standard errors is what the second tube would show.

use super::rig::{feasible, Field, Rig};
use crate::data::Dataset;
use crate::format::{fmt_sig, fmt_trim};
use crate::model::Model;
use serde::Serialize;

/// One field the design holds fixed, and the experiment that would free it.
#[derive(Debug, Clone, Serialize)]
pub struct DesignLimit {
    /// The dataset key held fixed.
    pub field: &'static str,
    pub value: f64,
    /// What the design cannot separate, in words.
    pub cannot_separate: &'static str,
    /// The experiment that would, in words.
    pub experiment: String,
    /// For a second tube: the predicted difference between the wall and
    /// the geometry reading of the found correction, in standard errors.
    pub predicted_in_sigma: Option<f64>,
}

impl DesignLimit {
    pub fn sentence(&self) -> String {
        let predicted = self
            .predicted_in_sigma
            .map(|s| {
                format!(
                    " (the two readings of the found correction then differ by about {} standard errors)",
                    fmt_sig(s, 2)
                )
            })
            .unwrap_or_default();
        format!(
            "every case has {} = {}, so this design cannot separate {}; {}{predicted}",
            self.field,
            fmt_trim(self.value, 4),
            self.cannot_separate,
            self.experiment
        )
    }
}

fn fixed(data: &Dataset, get: impl Fn(&crate::data::Case) -> f64) -> Option<f64> {
    let first = get(data.cases.first()?);
    data.cases
        .iter()
        .all(|c| (get(c) - first).abs() <= 1e-12 * first.abs())
        .then_some(first)
}

/// Every field `data` holds fixed, with the experiment that would free it;
/// `found` (the found model, and the model beneath it) sets the second
/// tube's predicted difference.
pub fn limits(data: &Dataset, found: Option<(&Model, &Model)>) -> Vec<DesignLimit> {
    if data.cases.len() < 2 {
        return Vec::new();
    }
    let rig = Rig::of(data);
    let mut out = Vec::new();
    if let Some(d) = fixed(data, |c| c.channel_diameter_mm) {
        let other = rig
            .tubes_mm
            .iter()
            .copied()
            .find(|t| (t - d).abs() > 1e-9 * d);
        let (experiment, predicted) = match other {
            Some(t) => (
                format!(
                    "a case run in the {} mm tube the rig has would separate them",
                    fmt_trim(t, 4)
                ),
                found.and_then(|(f, b)| second_tube(data, f, b, t)),
            ),
            None => (
                "a case in a second tube would separate them (the rig states none: list the tubes the lab has as `rig.channel_diameter_mm`)".to_string(),
                None,
            ),
        };
        out.push(DesignLimit {
            field: "channel_diameter_mm",
            value: d,
            cannot_separate: "a wall effect from a dependence on the helix or body geometry",
            experiment,
            predicted_in_sigma: predicted,
        });
    }
    if let Some(f) = fixed(data, |c| c.frequency_hz) {
        let r = rig.frequency_hz;
        let experiment = if r.hi > r.lo {
            format!(
                "a case at a second rate, within the {}-{} Hz the firmware holds, would separate them",
                fmt_sig(r.lo, 3),
                fmt_sig(r.hi, 3)
            )
        } else {
            "a case at a second rate would separate them (state the rates the firmware holds as `rig.frequency_hz`)"
                .to_string()
        };
        out.push(DesignLimit {
            field: "frequency_hz",
            value: f,
            cannot_separate: "an effect that grows with the rate from a constant one",
            experiment,
            predicted_in_sigma: None,
        });
    }
    if let Some(v) = fixed(data, |c| c.viscosity_pa_s) {
        out.push(DesignLimit {
            field: "viscosity_pa_s",
            value: v,
            cannot_separate:
                "an effect of the oil's viscosity (or of a Reynolds number) from a constant one",
            experiment: "a case in a second oil would separate them".to_string(),
            predicted_in_sigma: None,
        });
    }
    out
}

/// The predicted difference of the module docs, largest over the cases.
fn second_tube(data: &Dataset, found: &Model, base: &Model, tube_mm: f64) -> Option<f64> {
    let median = super::separation::median_rel_se(data);
    let mut best: Option<f64> = None;
    for c in &data.cases {
        let mut k = c.clone();
        Field::Tube.set(&mut k, tube_mm);
        if !feasible(&k) {
            continue;
        }
        let (Ok(f1), Ok(b1), Ok(f2), Ok(b2)) = (
            found.predict(c),
            base.predict(c),
            found.predict(&k),
            base.predict(&k),
        ) else {
            continue;
        };
        for (x1, y1, x2, y2, m) in [
            (f1.u_mm_s, b1.u_mm_s, f2.u_mm_s, b2.u_mm_s, c.u_mm_s),
            (
                f1.omega_body_hz,
                b1.omega_body_hz,
                f2.omega_body_hz,
                b2.omega_body_hz,
                c.omega_body_hz,
            ),
        ] {
            let (c1, c2) = (x1 / y1, x2 / y2);
            let se = m
                .map(|m| (m.standard_error() / m.mean).abs())
                .filter(|s| s.is_finite() && *s > 0.0)
                .unwrap_or(median);
            let sigma = (c2 - c1).abs() / se;
            if sigma.is_finite() && best.is_none_or(|b| sigma > b) {
                best = Some(sigma);
            }
        }
    }
    best
}

/// What the design cannot separate, as clauses to append to a verdict's
/// note (`"; every case has ..."`); `found` is the found model, on top of
/// `base`.
pub fn limits_note(data: &Dataset, base: &Model, found: Option<&Model>) -> String {
    limits(data, found.map(|f| (f, base)))
        .iter()
        .map(|l| format!("; {}", l.sentence()))
        .collect()
}
