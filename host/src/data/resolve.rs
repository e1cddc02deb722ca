//! One case of a dataset as the model reads it: its raw table merged with
//! the `[setup]` defaults and checked field by field (ranges, measured
//! means with their confidence or raw trials, input uncertainties, the
//! geometry's relations), each error naming the file, the case and the
//! field ([`super::parse`] reads the tables).

use super::parse::{err, RawCase};
use super::recorded::Recorded;
use super::uncertainty::{merge_tables, AmplitudeConvention, CaseInputs};
use super::{Case, DataError, Measured, Orientation};
use crate::physics::geometry::Handedness;

/// Merges one case with the setup defaults and checks each value.
struct Resolver<'a> {
    file: &'a str,
    id: String,
    /// The message for a value given neither in the case nor as a default.
    missing: &'static str,
}

impl Resolver<'_> {
    fn fail(&self, field: &str, message: impl Into<String>) -> DataError {
        err(self.file, Some(&self.id), Some(field), message)
    }

    fn positive(
        &self,
        field: &str,
        case: Option<f64>,
        setup: Option<f64>,
    ) -> Result<f64, DataError> {
        let v = case
            .or(setup)
            .ok_or_else(|| self.fail(field, self.missing))?;
        self.check_positive(field, v)
    }

    fn check_positive(&self, field: &str, v: f64) -> Result<f64, DataError> {
        if !v.is_finite() {
            return Err(self.fail(field, format!("must be a finite number, got {v}")));
        }
        if v <= 0.0 {
            return Err(self.fail(field, format!("must be positive, got {v}")));
        }
        Ok(v)
    }

    /// A signed value, 0 when absent.
    fn finite(&self, field: &str, v: Option<f64>) -> Result<f64, DataError> {
        match v {
            Some(v) if !v.is_finite() => {
                Err(self.fail(field, format!("must be a finite number, got {v}")))
            }
            v => Ok(v.unwrap_or(0.0)),
        }
    }

    fn non_negative(
        &self,
        field: &str,
        case: Option<f64>,
        setup: Option<f64>,
        default: f64,
    ) -> Result<f64, DataError> {
        let v = case.or(setup).unwrap_or(default);
        if !v.is_finite() || v < 0.0 {
            return Err(self.fail(field, format!("must be a finite number >= 0, got {v}")));
        }
        Ok(v)
    }

    /// A measured quantity: mean + CI half-width, or raw trials.
    fn measured(
        &self,
        names: [&str; 3],
        mean: Option<f64>,
        ci: Option<f64>,
        trials_raw: Option<&Vec<f64>>,
        trials: Option<u32>,
        confidence: f64,
    ) -> Result<Option<Measured>, DataError> {
        let [mean_name, ci_name, trials_name] = names;
        if let Some(values) = trials_raw {
            if mean.is_some() || ci.is_some() {
                return Err(self.fail(
                    trials_name,
                    format!("give either raw trials or `{mean_name}` + `{ci_name}`, not both"),
                ));
            }
            if values.len() < 2 {
                return Err(self.fail(
                    trials_name,
                    "needs at least 2 trials for a confidence interval",
                ));
            }
            if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                return Err(self.fail(trials_name, format!("contains a non-finite value {bad}")));
            }
            let (m, half) = crate::stats::mean_and_ci(values, confidence);
            if half <= super::limits::MIN_RELATIVE_CI * m.abs() {
                let why = "the trials are (nearly) identical: a zero-width interval gives the measurement an infinite weight";
                return Err(self.fail(trials_name, why));
            }
            return Ok(Some(Measured {
                mean: m,
                ci_half_width: half,
                confidence,
                trials: values.len() as u32,
            }));
        }
        match (mean, ci) {
            (None, None) => Ok(None),
            (Some(_), None) => Err(self.fail(
                ci_name,
                format!("missing: `{mean_name}` needs its confidence half-width"),
            )),
            (None, Some(_)) => Err(self.fail(
                mean_name,
                format!("missing: `{ci_name}` is given without a mean"),
            )),
            (Some(m), Some(c)) => {
                if !m.is_finite() {
                    return Err(self.fail(mean_name, format!("must be finite, got {m}")));
                }
                let c = self.check_positive(ci_name, c)?;
                let n = trials.ok_or_else(|| {
                    self.fail(
                        "trials",
                        "missing: needed to turn the confidence interval into a standard error",
                    )
                })?;
                if n < 2 {
                    return Err(self.fail("trials", format!("must be at least 2, got {n}")));
                }
                Ok(Some(Measured {
                    mean: m,
                    ci_half_width: c,
                    confidence,
                    trials: n,
                }))
            }
        }
    }
}

pub(super) fn resolve(
    file: &str,
    missing: &'static str,
    index: usize,
    s: &RawCase,
    c: &RawCase,
) -> Result<Case, DataError> {
    let id = c.id.clone().unwrap_or_else(|| format!("#{}", index + 1));
    let r = Resolver {
        file,
        id: id.clone(),
        missing,
    };
    let confidence = c.confidence.or(s.confidence).unwrap_or(0.95);
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(r.fail(
            "confidence",
            format!("must be between 0 and 1, got {confidence}"),
        ));
    }
    let trials = c.trials.or(s.trials);
    let case = Case {
        wavelength_mm: r.positive("wavelength_mm", c.wavelength_mm, s.wavelength_mm)?,
        amplitude_mm: r.positive("amplitude_mm", c.amplitude_mm, s.amplitude_mm)?,
        tail_length_mm: r.positive("tail_length_mm", c.tail_length_mm, s.tail_length_mm)?,
        wire_diameter_mm: r.positive("wire_diameter_mm", c.wire_diameter_mm, s.wire_diameter_mm)?,
        handedness: c.handedness.or(s.handedness).unwrap_or(Handedness::Right),
        frequency_hz: r.positive("frequency_hz", c.frequency_hz, s.frequency_hz)?,
        channel_diameter_mm: r.positive(
            "channel_diameter_mm",
            c.channel_diameter_mm,
            s.channel_diameter_mm,
        )?,
        channel_length_mm: r.positive(
            "channel_length_mm",
            c.channel_length_mm,
            s.channel_length_mm,
        )?,
        channel_closed: c.channel_closed.or(s.channel_closed).unwrap_or(true),
        orientation: c
            .orientation
            .or(s.orientation)
            .unwrap_or(Orientation::Vertical),
        viscosity_pa_s: r.positive("viscosity_pa_s", c.viscosity_pa_s, s.viscosity_pa_s)?,
        density_kg_m3: r.positive("density_kg_m3", c.density_kg_m3, s.density_kg_m3)?,
        body_diameter_mm: r.positive("body_diameter_mm", c.body_diameter_mm, s.body_diameter_mm)?,
        body_length_mm: r.positive("body_length_mm", c.body_length_mm, s.body_length_mm)?,
        coupler_diameter_mm: r.non_negative(
            "coupler_diameter_mm",
            c.coupler_diameter_mm,
            s.coupler_diameter_mm,
            0.0,
        )?,
        coupler_length_mm: r.non_negative(
            "coupler_length_mm",
            c.coupler_length_mm,
            s.coupler_length_mm,
            0.0,
        )?,
        coupler_gap_mm: r.non_negative(
            "coupler_gap_mm",
            c.coupler_gap_mm,
            s.coupler_gap_mm,
            super::DEFAULT_COUPLER_GAP_MM,
        )?,
        body_profile: None,
        net_weight_g: r.finite("net_weight_g", c.net_weight_g.or(s.net_weight_g))?,
        u_mm_s: r.measured(
            ["u_mm_s", "u_ci_mm_s", "u_trials_mm_s"],
            c.u_mm_s,
            c.u_ci_mm_s,
            c.u_trials_mm_s.as_ref(),
            trials,
            confidence,
        )?,
        omega_body_hz: r.measured(
            ["omega_body_hz", "omega_body_ci_hz", "omega_body_trials_hz"],
            c.omega_body_hz,
            c.omega_body_ci_hz,
            c.omega_body_trials_hz.as_ref(),
            trials,
            confidence,
        )?,
        inputs: CaseInputs::default(),
        recorded: Recorded::from_tables(
            (s.recorded.as_ref(), s.labels.as_ref()),
            (c.recorded.as_ref(), c.labels.as_ref()),
        )
        .map_err(|(field, message)| r.fail(&field, message))?,
        derived: Default::default(),
        id,
    };
    let case = with_inputs(&r, s, c, case)?;
    check_geometry(&r, &case)?;
    let profile = c.body_profile.as_ref().or(s.body_profile.as_ref());
    let rounded = c.body_rounded_mm.or(s.body_rounded_mm);
    let case = Case {
        body_profile: super::profile::resolve(|f, m| r.fail(f, m), &case, profile, rounded)?,
        ..case
    };
    for (field, _) in &case.inputs.uncertainties {
        super::body_inputs::check(&case, field)
            .map_err(|m| r.fail(&format!("uncertainty.{field}"), m.to_string()))?;
    }
    Ok(case)
}

/// The input uncertainties and conventions of a case, `[setup]` merged;
/// a recorded amplitude is converted to the wire's centre-line radius.
fn with_inputs(
    r: &Resolver<'_>,
    s: &RawCase,
    c: &RawCase,
    mut case: Case,
) -> Result<Case, DataError> {
    let uncertainties = merge_tables(s.uncertainty.as_ref(), c.uncertainty.as_ref())
        .map_err(|(field, message)| r.fail(&field, message))?;
    let chord_length_mm = match c.chord_length_mm.or(s.chord_length_mm) {
        Some(v) => Some(r.check_positive("chord_length_mm", v)?),
        None => None,
    };
    let convention = c
        .amplitude_convention
        .or(s.amplitude_convention)
        .unwrap_or_default();
    let half_wire = 0.5 * case.wire_diameter_mm;
    match convention {
        AmplitudeConvention::CentreLine => {}
        AmplitudeConvention::Mandrel => case.amplitude_mm += half_wire,
        AmplitudeConvention::Outer => {
            if case.amplitude_mm <= half_wire {
                return Err(r.fail(
                    "amplitude_mm",
                    format!(
                        "an outer radius of {} mm leaves no centre-line radius for a {} mm wire",
                        case.amplitude_mm, case.wire_diameter_mm
                    ),
                ));
            }
            case.amplitude_mm -= half_wire;
        }
    }
    case.inputs = CaseInputs {
        uncertainties,
        chord_length_mm,
        chord_fixed: c.chord_fixed.or(s.chord_fixed).unwrap_or(false) || chord_length_mm.is_some(),
        amplitude_convention: convention,
    };
    Ok(case)
}

/// Relations between fields that the physics needs.
fn check_geometry(r: &Resolver<'_>, c: &Case) -> Result<(), DataError> {
    if c.wavelength_mm <= c.wire_diameter_mm {
        return Err(r.fail(
            "wavelength_mm",
            format!(
                "{} mm is not longer than the wire diameter {} mm: the logarithmic RFT coefficients break down",
                c.wavelength_mm, c.wire_diameter_mm
            ),
        ));
    }
    if c.amplitude_mm + 0.5 * c.wire_diameter_mm >= 0.5 * c.channel_diameter_mm {
        return Err(r.fail(
            "amplitude_mm",
            format!(
                "the tail ({} mm radius + wire) does not fit in the {} mm channel",
                c.amplitude_mm, c.channel_diameter_mm
            ),
        ));
    }
    if c.body_diameter_mm >= c.channel_diameter_mm {
        return Err(r.fail(
            "body_diameter_mm",
            format!(
                "the body ({} mm) does not fit in the {} mm channel",
                c.body_diameter_mm, c.channel_diameter_mm
            ),
        ));
    }
    if c.body_length_mm < c.body_diameter_mm {
        return Err(r.fail(
            "body_length_mm",
            "must be at least the body diameter (prolate body model)",
        ));
    }
    Ok(())
}
