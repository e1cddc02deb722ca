//! The runs the rig can make: each tail on hand (the data's distinct tail
//! geometries) in each tube and oil on hand, at every rate the remote's
//! keys reach inside the motor's range; with `new_tails`, also tails not
//! yet built, on a grid inside the data's geometry ranges (amplitude,
//! wavelength, tail length), bent from the data's wire. A run must fit its
//! tube and pass the data limits ([`crate::workbench::experiments::rig::feasible`]).

use crate::data::Case;
use crate::workbench::experiments::rig::{feasible, Rig};

/// What the lab can run a new experiment with.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRig {
    /// Inner diameters of the tubes on hand.
    pub tubes_mm: Vec<f64>,
    /// Viscosities of the oils on hand.
    pub oils_pa_s: Vec<f64>,
    /// The motor's set-point range (the rate controller's).
    pub rate_lo_hz: f64,
    pub rate_hi_hz: f64,
    /// Set-points are reached in these steps (the remote's rate step).
    pub rate_step_hz: f64,
    /// Tails not yet built may be planned.
    pub new_tails: bool,
}

/// Points per geometry field for new tails.
const NEW_TAIL_GRID: usize = 3;

/// A rig that cannot run anything: which field, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct RigError {
    pub field: &'static str,
    pub message: String,
}

/// One run the rig can make.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The case (its id: the data case whose tail it carries, or `new`).
    pub case: Case,
    /// The tail: the id of the first data case with it, or `new tail`.
    pub tail: String,
    /// The controller's set-point, the motor's rate (tail relative to
    /// body, Hz). The case's `frequency_hz` is the tail's rate in the lab,
    /// lower by the body's counter-rotation: [`super::select`] sets it from
    /// the model's prediction at this set-point.
    pub set_point_hz: f64,
}

fn check_list(field: &'static str, v: &[f64], unit: &str) -> Result<(), RigError> {
    if v.is_empty() {
        return Err(RigError {
            field,
            message: format!("no value given: the rig needs at least one (in {unit})"),
        });
    }
    match v.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        Some(x) => Err(RigError {
            field,
            message: format!("{x} is not a positive number of {unit}"),
        }),
        None => Ok(()),
    }
}

impl PlanRig {
    /// The rig of `data` with the firmware's rate range: the data's tubes
    /// and oils unless given.
    pub fn of(
        data: &crate::data::Dataset,
        tubes_mm: Option<Vec<f64>>,
        oils_pa_s: Option<Vec<f64>>,
        new_tails: bool,
    ) -> PlanRig {
        let distinct = |get: fn(&Case) -> f64| {
            let mut v: Vec<f64> = data.cases.iter().map(get).collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        let rate = swimbot_shared::board::RATE;
        let keys = swimbot_shared::board::SET_POINT_KEYS;
        PlanRig {
            tubes_mm: tubes_mm.unwrap_or_else(|| Rig::of(data).tubes_mm),
            oils_pa_s: oils_pa_s.unwrap_or_else(|| distinct(|c| c.viscosity_pa_s)),
            rate_lo_hz: f64::from(rate.min_rate_mhz) / 1e3,
            rate_hi_hz: f64::from(rate.max_rate_mhz) / 1e3,
            rate_step_hz: f64::from(keys.step_mhz) / 1e3,
            new_tails,
        }
    }

    /// The set-points: every rate step inside the motor's range.
    pub fn rates_hz(&self) -> Vec<f64> {
        let first = (self.rate_lo_hz / self.rate_step_hz - 1e-9).ceil() as i64;
        let last = (self.rate_hi_hz / self.rate_step_hz + 1e-9).floor() as i64;
        (first..=last)
            .map(|k| (k as f64 * self.rate_step_hz * 1e6).round() / 1e6)
            .collect()
    }

    /// Refuse a rig that cannot run anything, naming the field.
    pub fn check(&self) -> Result<(), RigError> {
        check_list("--tubes-mm", &self.tubes_mm, "mm")?;
        check_list("--oils-pa-s", &self.oils_pa_s, "Pa s")?;
        let ok = self.rate_lo_hz.is_finite()
            && self.rate_step_hz > 0.0
            && self.rate_hi_hz >= self.rate_lo_hz;
        if !ok || self.rates_hz().is_empty() {
            return Err(RigError {
                field: "rate",
                message: format!(
                    "the motor's range {}-{} Hz holds no set-point in steps of {} Hz",
                    self.rate_lo_hz, self.rate_hi_hz, self.rate_step_hz
                ),
            });
        }
        Ok(())
    }
}

fn same_tail(a: &Case, b: &Case) -> bool {
    a.wavelength_mm == b.wavelength_mm
        && a.amplitude_mm == b.amplitude_mm
        && a.tail_length_mm == b.tail_length_mm
        && a.wire_diameter_mm == b.wire_diameter_mm
        && a.handedness == b.handedness
}

/// The data's tails: one template case per distinct tail geometry.
pub fn tails_on_hand(data: &crate::data::Dataset) -> Vec<&Case> {
    let mut out: Vec<&Case> = Vec::new();
    for c in &data.cases {
        if !out.iter().any(|t| same_tail(t, c)) {
            out.push(c);
        }
    }
    out
}

/// The tails to plan with: those on hand, and with `new_tails` a grid in
/// the data's geometry ranges (each on the first case's body and wire).
fn tails(data: &crate::data::Dataset, rig: &PlanRig) -> Vec<(String, Case)> {
    let mut out: Vec<(String, Case)> = tails_on_hand(data)
        .into_iter()
        .map(|c| (c.id.clone(), c.clone()))
        .collect();
    let Some(first) = data.cases.first() else {
        return out;
    };
    if rig.new_tails {
        let r = Rig::of(data);
        for a in r.amplitude_mm.grid(NEW_TAIL_GRID) {
            for w in r.wavelength_mm.grid(NEW_TAIL_GRID) {
                for l in r.tail_length_mm.grid(NEW_TAIL_GRID) {
                    let mut k = first.clone();
                    (k.amplitude_mm, k.wavelength_mm, k.tail_length_mm) = (a, w, l);
                    if !out.iter().any(|(_, t)| same_tail(t, &k)) {
                        out.push(("new tail".into(), k));
                    }
                }
            }
        }
    }
    out
}

/// Every run the rig can make (module docs), or why it can make none.
pub fn candidates(data: &crate::data::Dataset, rig: &PlanRig) -> Result<Vec<Candidate>, RigError> {
    rig.check()?;
    let rates = rig.rates_hz();
    let mut out = Vec::new();
    for (tail, template) in tails(data, rig) {
        for &d in &rig.tubes_mm {
            for &mu in &rig.oils_pa_s {
                for &f in &rates {
                    let mut c = template.clone();
                    c.channel_diameter_mm = d;
                    c.viscosity_pa_s = mu;
                    c.frequency_hz = f;
                    c.u_mm_s = None;
                    c.omega_body_hz = None;
                    if feasible(&c) {
                        out.push(Candidate {
                            case: c,
                            tail: tail.clone(),
                            set_point_hz: f,
                        });
                    }
                }
            }
        }
    }
    if out.is_empty() {
        return Err(no_run(data, rig));
    }
    Ok(out)
}

/// Which field leaves the rig with nothing to run: a tube no body fits,
/// an oil outside the data limits, else the rates.
fn no_run(data: &crate::data::Dataset, rig: &PlanRig) -> RigError {
    let Some(c) = data.cases.first() else {
        return RigError {
            field: "data",
            message: "the study has no case to plan from".into(),
        };
    };
    let fits =
        |d: f64| c.body_diameter_mm < d && c.amplitude_mm + 0.5 * c.wire_diameter_mm < 0.5 * d;
    let in_limits = |d: f64| {
        crate::data::limits::check_case(&Case {
            channel_diameter_mm: d,
            ..c.clone()
        })
        .is_ok()
    };
    if !rig.tubes_mm.iter().any(|d| fits(*d) && in_limits(*d)) {
        return RigError {
            field: "--tubes-mm",
            message: format!(
                "no tube given fits the robot (body {} mm, the tails' helix) inside the data limits (docs/limits.md): nothing can run",
                c.body_diameter_mm
            ),
        };
    }
    let oil_ok = |mu: f64| {
        let mut k = c.clone();
        k.viscosity_pa_s = mu;
        crate::data::limits::check_case(&k).is_ok()
    };
    if !rig.oils_pa_s.iter().any(|m| oil_ok(*m)) {
        return RigError {
            field: "--oils-pa-s",
            message: "no oil given lies inside the data limits (docs/limits.md): an unknown oil"
                .into(),
        };
    }
    RigError {
        field: "rate",
        message: format!(
            "no run at {}-{} Hz in these tubes and oils passes the data limits",
            rig.rate_lo_hz, rig.rate_hi_hz
        ),
    }
}
