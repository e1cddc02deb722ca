//! TOML -> [`Dataset`]: serde reads the raw tables (rejecting unknown keys),
//! then every case is merged with `[setup]` and validated field by field
//! ([`super::resolve`]) so that an error names the file, the case and the
//! field; here the dataset as a whole is checked (cases, ids). A `.csv` file is
//! first turned into the same raw tables by [`super::csv_read`], so both
//! formats share every check.

use super::uncertainty::AmplitudeConvention;
use super::{DataError, Dataset, Orientation};
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
pub(super) struct RawCase {
    pub(super) id: Option<String>,
    pub(super) wavelength_mm: Option<f64>,
    pub(super) amplitude_mm: Option<f64>,
    pub(super) tail_length_mm: Option<f64>,
    pub(super) wire_diameter_mm: Option<f64>,
    pub(super) handedness: Option<Handedness>,
    pub(super) frequency_hz: Option<f64>,
    pub(super) channel_diameter_mm: Option<f64>,
    pub(super) channel_length_mm: Option<f64>,
    pub(super) channel_closed: Option<bool>,
    pub(super) orientation: Option<Orientation>,
    pub(super) viscosity_pa_s: Option<f64>,
    pub(super) density_kg_m3: Option<f64>,
    pub(super) body_diameter_mm: Option<f64>,
    pub(super) body_length_mm: Option<f64>,
    pub(super) coupler_diameter_mm: Option<f64>,
    pub(super) coupler_length_mm: Option<f64>,
    pub(super) coupler_gap_mm: Option<f64>,
    /// `[[length_mm, diameter_mm], ...]`, nose first.
    pub(super) body_profile: Option<Vec<[f64; 2]>>,
    pub(super) body_rounded_mm: Option<f64>,
    pub(super) net_weight_g: Option<f64>,
    pub(super) confidence: Option<f64>,
    pub(super) trials: Option<u32>,
    pub(super) u_mm_s: Option<f64>,
    pub(super) u_ci_mm_s: Option<f64>,
    pub(super) u_trials_mm_s: Option<Vec<f64>>,
    pub(super) omega_body_hz: Option<f64>,
    pub(super) omega_body_ci_hz: Option<f64>,
    pub(super) omega_body_trials_hz: Option<Vec<f64>>,
    // Input uncertainties and recording conventions (data/uncertainty.rs).
    pub(super) uncertainty: Option<toml::Table>,
    pub(super) chord_length_mm: Option<f64>,
    pub(super) chord_fixed: Option<bool>,
    pub(super) amplitude_convention: Option<AmplitudeConvention>,
    // What the lab recorded beside the case (data/recorded.rs).
    pub(super) recorded: Option<toml::Table>,
    pub(super) labels: Option<toml::Table>,
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
        let case = super::resolve::resolve(&at, written.missing, i, &raw.setup, rc)?;
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
