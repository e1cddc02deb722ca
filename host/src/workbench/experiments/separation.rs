//! Which new measurement would tell two models apart, inside what the rig
//! can run ([`super::rig`]): each case varied in one field at a time over
//! its feasible range (rates, amplitudes, wavelengths, tail lengths on a
//! grid, every tube the lab has), scored by how far the two models'
//! predictions of U or Omega_b differ in the standard errors such a
//! measurement would carry (the base case's own relative standard error of
//! that quantity, else the data's median).
//!
//! **Same model.** When the two predictions agree to round-off
//! ([`SAME_MODEL_REL`]) on every case and every feasible variant, no
//! measurement of U or Omega_b separates them: they are the same model
//! (e.g. a law on the tail's torque and its reciprocal on the body's
//! rotational drag, which the torque balance makes identical), and no
//! measurement is suggested.

use super::rig::{feasible, Field, Rig};
use crate::data::{Case, Dataset, Measured};
use crate::model::Model;
use serde::Serialize;

/// Relative differences below this on every feasible design are round-off:
/// the two models are one.
pub const SAME_MODEL_REL: f64 = 1e-9;

/// Grid points per continuous field.
const GRID: usize = 5;

#[derive(Debug, Clone, Serialize)]
pub struct Suggestion {
    pub base_case: String,
    pub change: String,
    /// Largest relative difference of U or Omega_b between the models.
    pub rel_difference: f64,
    pub quantity: &'static str,
    /// That difference in the standard errors of such a measurement.
    pub in_sigma: f64,
    /// No feasible measurement separates them: they are the same model
    /// (then `base_case` and `change` are empty).
    pub same_model: bool,
    /// The feasible range searched, in words.
    pub rig: String,
}

impl Suggestion {
    /// The clause a verdict appends ("; to tell them apart, ...").
    pub fn hint(&self) -> String {
        self.hint_within(false)
    }

    /// [`Self::hint`]; with `rig_said`, the rig's ranges are left to an
    /// earlier clause of the same verdict (one sentence per pair of sets
    /// would otherwise repeat every tube the lab has).
    pub fn hint_within(&self, rig_said: bool) -> String {
        let rig = match rig_said {
            true => "the same rig as above",
            false => self.rig.as_str(),
        };
        if self.same_model {
            return format!(
                "; no measurement of U or Omega_b separates these, they are the same model (their predictions agree to {:.0e} on every case and every design the rig can run: {rig})",
                self.rel_difference.max(f64::MIN_POSITIVE),
            );
        }
        format!(
            "; to tell them apart, measure {} with {} ({} differs by {}, about {:.0} standard errors; searched within {}{rig})",
            self.base_case,
            self.change,
            self.quantity,
            percent(self.rel_difference),
            self.in_sigma,
            if rig_said { "" } else { "the rig: " },
        )
    }
}

fn percent(x: f64) -> String {
    if x >= 0.01 {
        format!("{:.0} %", 100.0 * x)
    } else {
        format!("{} %", crate::format::fmt_sig(100.0 * x, 2))
    }
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

/// The feasible one-field variants of `c` (the case itself first).
fn variants(c: &Case, rig: &Rig) -> Vec<(String, Case)> {
    let mut v = vec![(String::new(), c.clone())];
    for field in Field::ALL {
        for x in rig.values(field, GRID) {
            if (x - field.get(c)).abs() <= 1e-9 * x.abs() {
                continue;
            }
            let mut k = c.clone();
            field.set(&mut k, x);
            if feasible(&k) {
                let change = format!("{} = {}", field.key(), crate::format::fmt_sig(x, 4));
                v.push((change, k));
            }
        }
    }
    v
}

fn rel_se(m: Option<Measured>, fallback: f64) -> f64 {
    m.map(|m| (m.standard_error() / m.mean).abs())
        .filter(|x| x.is_finite() && *x > 0.0)
        .unwrap_or(fallback)
}

/// The feasible measurement that best separates `a` from `b`, or the word
/// that none does because they are the same model (module docs); `None`
/// when neither model predicts any feasible case.
pub fn best_discriminating_case(data: &Dataset, a: &Model, b: &Model) -> Option<Suggestion> {
    let rig = Rig::of(data);
    let median = median_rel_se(data);
    let mut best: Option<Suggestion> = None;
    let mut largest_rel = 0.0f64;
    for c in &data.cases {
        for (change, v) in variants(c, &rig) {
            let (Ok(pa), Ok(pb)) = (a.predict(&v), b.predict(&v)) else {
                continue;
            };
            for (q, x, y, m) in [
                ("U", pa.u_mm_s, pb.u_mm_s, c.u_mm_s),
                (
                    "Omega_b",
                    pa.omega_body_hz,
                    pb.omega_body_hz,
                    c.omega_body_hz,
                ),
            ] {
                let rel = (x - y).abs() / (0.5 * (x.abs() + y.abs())).max(1e-300);
                if !rel.is_finite() {
                    continue;
                }
                largest_rel = largest_rel.max(rel);
                // A measurement already made is no new experiment.
                if change.is_empty() {
                    continue;
                }
                let in_sigma = rel / rel_se(m, median);
                if best.as_ref().is_none_or(|s| in_sigma > s.in_sigma) {
                    best = Some(Suggestion {
                        base_case: c.id.clone(),
                        change: change.clone(),
                        rel_difference: rel,
                        quantity: q,
                        in_sigma,
                        same_model: false,
                        rig: String::new(),
                    });
                }
            }
        }
    }
    if largest_rel < SAME_MODEL_REL {
        return Some(Suggestion {
            base_case: String::new(),
            change: String::new(),
            rel_difference: largest_rel,
            quantity: "U and Omega_b",
            in_sigma: 0.0,
            same_model: true,
            rig: rig.describe(),
        });
    }
    best.map(|s| Suggestion {
        rig: rig.describe(),
        ..s
    })
}
