//! TOML -> [`Dataset`]: serde reads the raw tables (rejecting unknown keys),
//! then every case is merged with `[setup]` and validated field by field so
//! that an error names the file, the case and the field. A `.csv` file is
//! first turned into the same raw tables by [`super::csv_read`], so both
//! formats share every check.

use super::recorded::Recorded;
use super::uncertainty::{merge_tables, AmplitudeConvention, CaseInputs};
use super::{Case, DataError, Dataset, Measured, Orientation};
use crate::physics::geometry::Handedness;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDataset {
    name: Option<String>,
    source: Option<String>,
    #[serde(default)]
    setup: RawCase,
    #[serde(default, rename = "case")]
    cases: Vec<RawCase>,
    rig: Option<toml::Table>,
}

/// Every key a case may carry; `[setup]` takes the same keys as defaults.
#[derive(Deserialize, Default, Clone)]
#[serde(deny_unknown_fields)]
struct RawCase {
    id: Option<String>,
    wavelength_mm: Option<f64>,
    amplitude_mm: Option<f64>,
    tail_length_mm: Option<f64>,
    wire_diameter_mm: Option<f64>,
    handedness: Option<Handedness>,
    frequency_hz: Option<f64>,
    channel_diameter_mm: Option<f64>,
    channel_length_mm: Option<f64>,
    channel_closed: Option<bool>,
    orientation: Option<Orientation>,
    viscosity_pa_s: Option<f64>,
    density_kg_m3: Option<f64>,
    body_diameter_mm: Option<f64>,
    body_length_mm: Option<f64>,
    coupler_diameter_mm: Option<f64>,
    coupler_length_mm: Option<f64>,
    coupler_gap_mm: Option<f64>,
    /// `[[length_mm, diameter_mm], ...]`, nose first.
    body_profile: Option<Vec<[f64; 2]>>,
    body_rounded_mm: Option<f64>,
    net_weight_g: Option<f64>,
    confidence: Option<f64>,
    trials: Option<u32>,
    u_mm_s: Option<f64>,
    u_ci_mm_s: Option<f64>,
    u_trials_mm_s: Option<Vec<f64>>,
    omega_body_hz: Option<f64>,
    omega_body_ci_hz: Option<f64>,
    omega_body_trials_hz: Option<Vec<f64>>,
    // Input uncertainties and recording conventions (data/uncertainty.rs).
    uncertainty: Option<toml::Table>,
    chord_length_mm: Option<f64>,
    chord_fixed: Option<bool>,
    amplitude_convention: Option<AmplitudeConvention>,
    // What the lab recorded beside the case (data/recorded.rs).
    recorded: Option<toml::Table>,
    labels: Option<toml::Table>,
}

/// Where a dataset is written: what names the place of case `i` (the
/// file, or the file and its rows for a CSV), and where a value missing
/// from a case may be given instead, in the format's own words.
pub(super) struct Written<'a> {
    pub locate: &'a dyn Fn(usize) -> String,
    pub missing: &'static str,
}

/// A value missing from a case of a TOML dataset.
const TOML_MISSING: &str = "missing (set it in the case or in [setup])";
/// A value missing from a case of a CSV dataset.
pub(super) const CSV_MISSING: &str =
    "missing (give it a column, or a `# key = value` line above the column names)";

/// Parse and validate dataset text; `file` names it in error messages.
pub fn parse_str(text: &str, file: &str) -> Result<Dataset, DataError> {
    // Straight from the text, so that an unknown key's error keeps its line.
    let raw: RawDataset = toml::from_str(text).map_err(|e| not_a_dataset(file, &e))?;
    let written = Written {
        locate: &|_| file.to_string(),
        missing: TOML_MISSING,
    };
    validate(raw, file, &written)
}

fn not_a_dataset(file: &str, e: &toml::de::Error) -> DataError {
    err(
        file,
        None,
        None,
        format!("not a valid dataset: {}", e.to_string().trim_end()),
    )
}

/// Validate the raw tables of a dataset written as `written` says.
/// is written (the file, or the file and its rows for a CSV). Each case is
/// read on its own, so that a bad value (`handedness = "lefty"`) names its
/// case, its rows and its field.
pub(super) fn parse_table(
    mut table: toml::Table,
    file: &str,
    written: &Written<'_>,
) -> Result<Dataset, DataError> {
    let cases = match table.remove("case") {
        Some(toml::Value::Array(cases)) => cases,
        Some(_) => return Err(err(file, None, Some("case"), "must be a list of cases")),
        None => Vec::new(),
    };
    let mut raw: RawDataset =
        toml::Value::Table(table.clone())
            .try_into()
            .map_err(|e: toml::de::Error| {
                let setup = table.get("setup").and_then(toml::Value::as_table);
                let field = setup.and_then(failing_key).map(|k| format!("setup.{k}"));
                err(
                    file,
                    None,
                    field.as_deref(),
                    e.message().trim_end().to_string(),
                )
            })?;
    raw.cases = cases
        .into_iter()
        .enumerate()
        .map(|(i, case)| raw_case(case, i, written.locate))
        .collect::<Result<_, _>>()?;
    validate(raw, file, written)
}

/// One case's raw table, its errors at its rows, with its id and field.
fn raw_case(
    case: toml::Value,
    i: usize,
    locate: &dyn Fn(usize) -> String,
) -> Result<RawCase, DataError> {
    let table = match case {
        toml::Value::Table(t) => t,
        _ => return Err(err(&locate(i), None, None, "a case must be a table")),
    };
    let id = table
        .get("id")
        .and_then(toml::Value::as_str)
        .map_or_else(|| format!("#{}", i + 1), str::to_string);
    toml::Value::Table(table.clone())
        .try_into()
        .map_err(|e: toml::de::Error| {
            let field = failing_key(&table);
            err(
                &locate(i),
                Some(&id),
                field.as_deref(),
                e.message().trim_end().to_string(),
            )
        })
}

/// The first key of a case table that is wrong on its own (serde's error
/// on a whole table does not name the key of a bad value).
fn failing_key(table: &toml::Table) -> Option<String> {
    table
        .iter()
        .find(|(k, v)| {
            let one = toml::Table::from_iter([((*k).clone(), (*v).clone())]);
            toml::Value::Table(one).try_into::<RawCase>().is_err()
        })
        .map(|(k, _)| k.clone())
}

fn validate(raw: RawDataset, file: &str, written: &Written<'_>) -> Result<Dataset, DataError> {
    if raw.cases.is_empty() {
        return Err(err(file, None, None, "the dataset has no [[case]] tables"));
    }
    if raw.cases.len() > super::limits::MAX_CASES {
        let n = format!(
            "{} cases; at most {} are allowed",
            raw.cases.len(),
            super::limits::MAX_CASES
        );
        return Err(err(file, None, Some("case"), n));
    }
    let mut cases = Vec::with_capacity(raw.cases.len());
    // A set, not a scan of the cases so far: 10^4 cases would take 5 10^7
    // comparisons.
    let mut ids = std::collections::HashSet::with_capacity(raw.cases.len());
    for (i, rc) in raw.cases.iter().enumerate() {
        let at = (written.locate)(i);
        let case = resolve(&at, written.missing, i, &raw.setup, rc)?;
        super::limits::check_case(&case).map_err(|(f, m)| err(&at, Some(&case.id), Some(f), m))?;
        if !ids.insert(case.id.clone()) {
            return Err(err(&at, Some(&case.id), Some("id"), "duplicate case id"));
        }
        cases.push(case);
    }
    Ok(Dataset {
        name: raw.name.unwrap_or_else(|| "unnamed".into()),
        source: raw.source.unwrap_or_default(),
        cases,
        rig: super::rig::parse(raw.rig, file)?,
    })
}

pub(super) fn err(
    file: &str,
    case: Option<&str>,
    field: Option<&str>,
    message: impl Into<String>,
) -> DataError {
    DataError {
        file: file.to_string(),
        case: case.map(str::to_string),
        field: field.map(str::to_string),
        message: message.into(),
    }
}

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

fn resolve(
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
            .map_err(|m| r.fail(&format!("uncertainty.{field}"), m))?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_case_key_has_a_csv_column_but_the_raw_trials_and_the_uncertainty_table() {
        // serde lists the keys a case takes: "unknown field `x`, expected
        // one of `id`, `wavelength_mm`, ...".
        let e = toml::from_str::<RawCase>("not_a_key = 1")
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        let keys: Vec<&str> = e.split('`').skip(3).step_by(2).collect();
        assert!(keys.len() > 20, "{e}");
        let without_column = [
            "u_trials_mm_s",
            "omega_body_trials_hz",
            "uncertainty",
            "recorded",
            "labels",
        ];
        let mut want: Vec<&str> = keys
            .into_iter()
            .filter(|k| !without_column.contains(k))
            .collect();
        let mut columns: Vec<&str> = super::super::csv_columns::COLUMNS
            .iter()
            .map(|(name, _)| *name)
            .collect();
        want.sort_unstable();
        columns.sort_unstable();
        assert_eq!(columns, want);
    }
}
