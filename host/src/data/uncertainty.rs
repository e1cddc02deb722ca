//! Input uncertainties of a dataset: standard uncertainties of the numeric
//! inputs of a case (the tail's geometry and rate, the tube, the oil, the
//! body), and the recording conventions the audit needs (what the recorded
//! amplitude `B_o` measures; the wire's chord length when it was kept fixed).
//!
//! In the TOML file (see `docs/data-format.md`) an uncertainty is a number
//! (absolute standard uncertainty in the field's own unit) or a string
//! `"N%"` (relative standard uncertainty); `[setup.uncertainty]` gives
//! defaults and `[case.uncertainty]` overrides them key by key. Every key
//! must be one of [`input_names`]: the numeric fields of a case, the trim
//! `net_weight_g`, and the lengths of the body profile's end sections.
//!
//! Correlation convention (GUM 5.2): the tail's own inputs
//! ([`Scope::PerCase`]: wavelength, amplitude, tail length, wire diameter,
//! tail rate) are measured tail by tail, so their errors are independent
//! between cases; the others ([`Scope::Shared`]: tube, oil, body and its
//! sections, trim, coupler)
//! are one physical object shared by every case, so their errors are fully
//! correlated between cases and cancel, to first order, in ratios between
//! cases. A shared input is one object among the cases that record the
//! same value of it (one oil, one tube); the chi-square with the inputs'
//! covariance (`workbench::input_covariance`) takes it so.
//!
//! References: JCGM 100:2008 (GUM), *Evaluation of measurement data: Guide
//! to the expression of uncertainty in measurement*, sections 4.3 (type B
//! evaluation), 5.1-5.2 (combination, correlated inputs).

use super::quantities::FIELDS;
use super::Case;

/// One standard uncertainty as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Uncertainty {
    /// In the field's own unit.
    Absolute(f64),
    /// Per cent of the value (`"2%"` is stored as 2.0, so that it writes back exactly).
    RelativePercent(f64),
}

impl Uncertainty {
    /// The standard uncertainty of `value`, in the field's unit.
    pub fn standard(&self, value: f64) -> f64 {
        match *self {
            Uncertainty::Absolute(u) => u,
            Uncertainty::RelativePercent(p) => 0.01 * p * value.abs(),
        }
    }

    /// Parse a TOML value: a number >= 0, or a string `"N%"` with N >= 0.
    pub fn from_toml(v: &toml::Value) -> Result<Self, UncertaintyError> {
        let check = |x: f64, relative: bool| -> Result<f64, UncertaintyError> {
            if !x.is_finite() {
                return Err(UncertaintyError::NotFinite { value: x, relative });
            }
            if x < 0.0 {
                return Err(UncertaintyError::Negative { value: x, relative });
            }
            Ok(x)
        };
        match v {
            toml::Value::Float(x) => Ok(Uncertainty::Absolute(check(*x, false)?)),
            toml::Value::Integer(i) => Ok(Uncertainty::Absolute(check(*i as f64, false)?)),
            toml::Value::String(s) => {
                let num = s
                    .trim()
                    .strip_suffix('%')
                    .ok_or_else(|| UncertaintyError::NotAPercentage { text: s.clone() })?;
                let p: f64 =
                    num.trim()
                        .parse()
                        .map_err(|_| UncertaintyError::PercentageNotANumber {
                            text: s.clone(),
                            number: num.to_string(),
                        })?;
                Ok(Uncertainty::RelativePercent(check(p, true)?))
            }
            other => Err(UncertaintyError::NotAValue {
                given: other.to_string(),
            }),
        }
    }

    /// The form the file takes (round trip of the writer).
    pub fn to_toml(&self) -> String {
        match *self {
            Uncertainty::Absolute(u) => format!("{u:?}"),
            Uncertainty::RelativePercent(p) => format!("\"{p:?}%\""),
        }
    }
}

/// An uncertainty the data cannot hold: the value or text as given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UncertaintyError {
    /// `relative`: a percentage's number, else an absolute uncertainty.
    #[error("{} must be a finite number, got {value}", what(*.relative))]
    NotFinite { value: f64, relative: bool },
    #[error("{} must be >= 0, got {value}", what(*.relative))]
    Negative { value: f64, relative: bool },
    #[error("`{text}` is neither a number (absolute) nor a percentage like \"2%\"")]
    NotAPercentage { text: String },
    #[error("`{text}` is not a percentage: `{number}` is not a number")]
    PercentageNotANumber { text: String, number: String },
    /// Neither a number nor a string (`given`: the TOML value as written).
    #[error("must be a number (absolute) or a string like \"2%\" (relative), got {given}")]
    NotAValue { given: String },
}

fn what(relative: bool) -> &'static str {
    if relative {
        "a relative uncertainty"
    } else {
        "an uncertainty"
    }
}

/// Which cases share an input's error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scope {
    /// Recorded tail by tail: independent between cases.
    PerCase,
    /// One tube, one oil, one body: the same error in every case.
    Shared,
}

/// The scope of a field (see the module docs), every input named:
/// - per case: the tail's geometry (each case its own hand-made helix on
///   the paper's robot) and its rate (counted on each run's video; a
///   camera clock error common to all runs would be shared, but at 30 fps
///   from a crystal it is far below the 2 % counting error);
/// - shared: the tube, the oil, the body and its sections, the trim, the
///   coupler: one object for every case that records the same value
///   (`workbench::input_covariance` groups by value, so a second oil or
///   another tube is another object with its own error).
///
/// A name that is not an input ([`input_names`]) is taken as shared: it
/// can carry no uncertainty (the parser refuses it), so it never counts.
pub fn scope_of(field: &str) -> Scope {
    match field {
        "wavelength_mm" | "amplitude_mm" | "tail_length_mm" | "wire_diameter_mm"
        | "frequency_hz" => Scope::PerCase,
        "channel_diameter_mm"
        | "channel_length_mm"
        | "viscosity_pa_s"
        | "density_kg_m3"
        | "body_diameter_mm"
        | "body_length_mm"
        | "coupler_diameter_mm"
        | "coupler_length_mm"
        | "coupler_gap_mm"
        | "net_weight_g"
        | super::body_inputs::NOSE
        | super::body_inputs::REAR => Scope::Shared,
        _ => Scope::Shared,
    }
}

/// What the recorded `amplitude_mm` measures. The model's `B_o` is the
/// radius of the wire's centre line; the parser converts to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum AmplitudeConvention {
    /// The wire's centre-line radius (the model's `B_o`; the default).
    #[default]
    CentreLine,
    /// The mandrel's radius the wire was coiled on: `B_o = recorded + D_t/2`.
    Mandrel,
    /// The helix's outer radius: `B_o = recorded - D_t/2`.
    Outer,
}

/// A case's input uncertainties and recording conventions, `[setup]` merged.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CaseInputs {
    /// `(field id, uncertainty)`, in the order of [`FIELDS`].
    pub uncertainties: Vec<(&'static str, Uncertainty)>,
    /// The wire's chord length as the experimenters stated it (mm).
    pub chord_length_mm: Option<f64>,
    /// The chord length was kept the same for every case (value unknown
    /// unless `chord_length_mm` is given).
    pub chord_fixed: bool,
    /// What the recorded amplitude measured (already converted).
    pub amplitude_convention: AmplitudeConvention,
}

impl CaseInputs {
    /// The standard uncertainty of `field` in `case`, zero when none is given.
    pub fn standard(&self, case: &Case, field: &str) -> f64 {
        self.uncertainties
            .iter()
            .find(|(f, _)| *f == field)
            .map(|(f, u)| u.standard(field_value(case, f).unwrap_or(0.0)))
            .unwrap_or(0.0)
    }

    /// Fields with a non-zero uncertainty, with their standard uncertainties.
    pub fn nonzero(&self, case: &Case) -> Vec<(&'static str, f64)> {
        self.uncertainties
            .iter()
            .map(|(f, u)| (*f, u.standard(field_value(case, f).unwrap_or(0.0))))
            .filter(|(_, s)| *s > 0.0)
            .collect()
    }

    pub fn is_empty(&self) -> bool {
        self.uncertainties.is_empty()
    }
}

/// The inputs [`set_field`] can vary that are fields of a case.
const SETTABLE: &[&str] = &[
    "wavelength_mm",
    "amplitude_mm",
    "tail_length_mm",
    "wire_diameter_mm",
    "frequency_hz",
    "channel_diameter_mm",
    "channel_length_mm",
    "viscosity_pa_s",
    "density_kg_m3",
    "body_diameter_mm",
    "body_length_mm",
    "coupler_diameter_mm",
    "coupler_length_mm",
    "coupler_gap_mm",
];

/// Inputs that are not among the case quantities (`FIELDS`, which
/// `diagnose` searches as features): the trim, 0 in most datasets, and the
/// lengths of the body profile's end sections ([`super::body_inputs`]).
pub const OTHER_INPUTS: &[&str] = &[
    "net_weight_g",
    super::body_inputs::NOSE,
    super::body_inputs::REAR,
];

/// An input whose value may be negative (its draws are not redrawn at 0).
pub fn is_signed(field: &str) -> bool {
    field == "net_weight_g"
}

/// The canonical `'static` name of a numeric input that can carry an
/// uncertainty (an input [`set_field`] can vary).
pub fn field_id(name: &str) -> Option<&'static str> {
    FIELDS
        .iter()
        .map(|q| q.id)
        .find(|id| *id == name && SETTABLE.contains(&name))
        .or_else(|| OTHER_INPUTS.iter().copied().find(|id| *id == name))
}

/// Every input that can carry an uncertainty, in the documented order.
pub fn input_names() -> impl Iterator<Item = &'static str> {
    FIELDS
        .iter()
        .map(|q| q.id)
        .filter(|id| SETTABLE.contains(id))
        .chain(OTHER_INPUTS.iter().copied())
}

/// Where an input goes in the writer's order (the case quantities first).
pub fn input_order(name: &str) -> Option<usize> {
    FIELDS.iter().position(|q| q.id == name).or_else(|| {
        OTHER_INPUTS
            .iter()
            .position(|id| *id == name)
            .map(|i| FIELDS.len() + i)
    })
}

/// The value of a numeric input.
pub fn field_value(case: &Case, field: &str) -> Option<f64> {
    match field {
        "net_weight_g" => Some(case.net_weight_g),
        _ => super::body_inputs::value(case, field)
            .or_else(|| FIELDS.iter().find(|q| q.id == field).map(|q| q.of(case))),
    }
}

/// Set a numeric input; `false` for a name that is not one. The body's
/// length, diameter and end sections move its profile with them (see
/// [`super::body_inputs`]), so that every body model sees the same body.
pub fn set_field(case: &mut Case, field: &str, v: f64) -> bool {
    if super::body_inputs::set(case, field, v) {
        return true;
    }
    let slot = match field {
        "wavelength_mm" => &mut case.wavelength_mm,
        "amplitude_mm" => &mut case.amplitude_mm,
        "tail_length_mm" => &mut case.tail_length_mm,
        "wire_diameter_mm" => &mut case.wire_diameter_mm,
        "frequency_hz" => &mut case.frequency_hz,
        "channel_diameter_mm" => &mut case.channel_diameter_mm,
        "channel_length_mm" => &mut case.channel_length_mm,
        "viscosity_pa_s" => &mut case.viscosity_pa_s,
        "density_kg_m3" => &mut case.density_kg_m3,
        "coupler_diameter_mm" => &mut case.coupler_diameter_mm,
        "coupler_length_mm" => &mut case.coupler_length_mm,
        "net_weight_g" => &mut case.net_weight_g,
        "coupler_gap_mm" => &mut case.coupler_gap_mm,
        _ => return false,
    };
    *slot = v;
    true
}

/// Merge `[setup.uncertainty]` with a case's table; the error is
/// `(field, message)` with the field written `uncertainty.KEY`.
pub fn merge_tables(
    setup: Option<&toml::Table>,
    case: Option<&toml::Table>,
) -> Result<Vec<(&'static str, Uncertainty)>, (String, String)> {
    let mut out: Vec<(&'static str, Uncertainty)> = Vec::new();
    for table in [setup, case].into_iter().flatten() {
        for (k, v) in table {
            let field = format!("uncertainty.{k}");
            let id = field_id(k).ok_or_else(|| {
                let known: Vec<&str> = input_names().collect();
                (
                    field.clone(),
                    format!(
                        "`{k}` is not a numeric input; uncertainties may be given for: {}",
                        known.join(", ")
                    ),
                )
            })?;
            let u = Uncertainty::from_toml(v).map_err(|m| (field.clone(), m.to_string()))?;
            match out.iter_mut().find(|(f, _)| *f == id) {
                Some(slot) => slot.1 = u,
                None => out.push((id, u)),
            }
        }
    }
    out.sort_by_key(|(f, _)| input_order(f));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_absolute_and_relative_and_rejects_the_rest() {
        let v = |s: &str| -> toml::Value {
            toml::from_str::<toml::Table>(&format!("x = {s}")).unwrap()["x"].clone()
        };
        assert_eq!(
            Uncertainty::from_toml(&v("0.5")),
            Ok(Uncertainty::Absolute(0.5))
        );
        assert_eq!(
            Uncertainty::from_toml(&v("1")),
            Ok(Uncertainty::Absolute(1.0))
        );
        assert_eq!(
            Uncertainty::from_toml(&v("\"2.5%\"")),
            Ok(Uncertainty::RelativePercent(2.5))
        );
        assert!(Uncertainty::from_toml(&v("-0.1"))
            .unwrap_err()
            .to_string()
            .contains(">= 0"));
        assert!(Uncertainty::from_toml(&v("nan"))
            .unwrap_err()
            .to_string()
            .contains("finite"));
        assert!(Uncertainty::from_toml(&v("\"2\"")).is_err());
        assert!(Uncertainty::from_toml(&v("\"-2%\"")).is_err());
        assert!(Uncertainty::from_toml(&v("true")).is_err());
        assert_eq!(Uncertainty::RelativePercent(2.0).standard(-50.0), 1.0);
    }

    #[test]
    fn every_field_can_be_set_and_scopes_are_stated() {
        let mut c = crate::data::paper().cases[0].clone();
        assert!(c.body_profile.is_some(), "the paper's body is its parts");
        for q in FIELDS {
            assert_eq!(field_id(q.id).is_some(), SETTABLE.contains(&q.id));
        }
        for id in input_names() {
            let mut c = c.clone();
            assert!(set_field(&mut c, id, 7.25), "{id}");
            assert_eq!(field_value(&c, id), Some(7.25), "{id}");
        }
        assert!(!set_field(&mut c, "u_mm_s", 1.0));
        assert_eq!(scope_of("amplitude_mm"), Scope::PerCase);
        assert_eq!(scope_of("viscosity_pa_s"), Scope::Shared);
        assert_eq!(scope_of("net_weight_g"), Scope::Shared);
        assert_eq!(scope_of(crate::data::body_inputs::NOSE), Scope::Shared);
        // every input's scope is stated, and the tail's own are per case
        let per_case: Vec<&str> = input_names()
            .filter(|f| scope_of(f) == Scope::PerCase)
            .collect();
        assert_eq!(
            per_case,
            [
                "wavelength_mm",
                "amplitude_mm",
                "tail_length_mm",
                "wire_diameter_mm",
                "frequency_hz"
            ]
        );
    }
}
