//! The columns of a CSV dataset: the TOML format's keys (docs/data-format.md),
//! with their units in their names, in the order the writer puts them, and
//! how a spreadsheet cell of each is read.
//!
//! Two TOML keys have no column: the raw trials `u_trials_mm_s` and
//! `omega_body_trials_hz` are written as one row per trial, and a case's
//! `uncertainty` table is spread over `uncertainty.KEY` columns.

/// How a cell is read into the raw TOML value the parser validates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Kept as written (ids, `right`/`left`, `vertical`/`horizontal`, ...).
    Text,
    /// `true` or `false` (any case: spreadsheets write `TRUE`).
    Flag,
    /// A whole number >= 0.
    Count,
    /// A decimal number.
    Number,
    /// A TOML inline value (`body_profile = [[length_mm, diameter_mm], ...]`).
    Inline,
    /// A standard uncertainty: a number, or `N%`.
    Uncertainty,
}

/// The measured quantities whose rows are the trials of one case.
pub const TRIAL_COLUMNS: [(&str, &str); 2] = [
    ("u_mm_s", "u_trials_mm_s"),
    ("omega_body_hz", "omega_body_trials_hz"),
];

/// The columns that only a one-row-per-case layout takes: with one row per
/// trial, the interval and the count follow from the rows.
pub const CASE_ONLY_COLUMNS: [&str; 3] = ["u_ci_mm_s", "omega_body_ci_hz", "trials"];

/// Every column but `uncertainty.KEY`, in the writer's order.
pub const COLUMNS: &[(&str, Kind)] = &[
    ("id", Kind::Text),
    ("wavelength_mm", Kind::Number),
    ("amplitude_mm", Kind::Number),
    ("tail_length_mm", Kind::Number),
    ("wire_diameter_mm", Kind::Number),
    ("handedness", Kind::Text),
    ("frequency_hz", Kind::Number),
    ("channel_diameter_mm", Kind::Number),
    ("channel_length_mm", Kind::Number),
    ("channel_closed", Kind::Flag),
    ("orientation", Kind::Text),
    ("viscosity_pa_s", Kind::Number),
    ("density_kg_m3", Kind::Number),
    ("body_diameter_mm", Kind::Number),
    ("body_length_mm", Kind::Number),
    ("coupler_diameter_mm", Kind::Number),
    ("coupler_length_mm", Kind::Number),
    ("coupler_gap_mm", Kind::Number),
    ("body_profile", Kind::Inline),
    ("body_rounded_mm", Kind::Number),
    ("net_weight_g", Kind::Number),
    ("chord_length_mm", Kind::Number),
    ("chord_fixed", Kind::Flag),
    ("amplitude_convention", Kind::Text),
    ("confidence", Kind::Number),
    ("trials", Kind::Count),
    ("u_mm_s", Kind::Number),
    ("u_ci_mm_s", Kind::Number),
    ("omega_body_hz", Kind::Number),
    ("omega_body_ci_hz", Kind::Number),
];

/// The prefix of the uncertainty columns (`uncertainty.amplitude_mm`).
pub const UNCERTAINTY_PREFIX: &str = "uncertainty.";

/// The kind of a column, `None` for a name that is not one.
pub fn kind_of(name: &str) -> Option<Kind> {
    if name
        .strip_prefix(UNCERTAINTY_PREFIX)
        .is_some_and(|k| !k.is_empty())
    {
        return Some(Kind::Uncertainty);
    }
    COLUMNS.iter().find(|(n, _)| *n == name).map(|(_, k)| *k)
}

/// Where a column (or a TOML key) goes in the writer's order: raw trials
/// where their means go, uncertainties last, in the order of the fields.
pub fn order_of(name: &str) -> usize {
    if let Some((mean, _)) = TRIAL_COLUMNS.iter().find(|(_, raw)| *raw == name) {
        return order_of(mean);
    }
    match name.strip_prefix(UNCERTAINTY_PREFIX) {
        Some(k) => {
            COLUMNS.len() + super::uncertainty::input_order(k).unwrap_or(usize::MAX - COLUMNS.len())
        }
        None => COLUMNS
            .iter()
            .position(|(n, _)| *n == name)
            .unwrap_or(usize::MAX),
    }
}

impl Kind {
    /// The raw value of a non-empty cell, or what is wrong with it (the
    /// cell echoed at most [`super::limits::MAX_ECHO_CHARS`] characters).
    /// Under a decimal comma, `0,586` is a number.
    pub fn read(self, cell: &str, decimal_comma: bool) -> Result<toml::Value, CellError> {
        use toml::Value as V;
        let bad = |problem| CellError {
            shown: super::limits::echo(cell),
            problem,
        };
        let number = |cell: &str| {
            if decimal_comma && super::csv_dialect::is_decimal_point(cell) {
                return Err(bad(CellProblem::DecimalPointAmongCommas));
            }
            number(
                &super::csv_dialect::number_text(cell, decimal_comma),
                decimal_comma,
            )
        };
        match self {
            Kind::Text => Ok(V::String(cell.to_string())),
            Kind::Flag => match cell.to_ascii_lowercase().as_str() {
                "true" => Ok(V::Boolean(true)),
                "false" => Ok(V::Boolean(false)),
                _ => Err(bad(CellProblem::NotAFlag)),
            },
            Kind::Count => cell
                .parse::<u32>()
                .map(|n| V::Integer(i64::from(n)))
                .map_err(|_| bad(CellProblem::NotACount)),
            Kind::Number => number(cell),
            Kind::Uncertainty if cell.ends_with('%') => Ok(V::String(cell.to_string())),
            Kind::Uncertainty => number(cell),
            Kind::Inline => toml::from_str::<toml::Table>(&format!("v = {cell}"))
                .ok()
                .and_then(|mut t| t.remove("v"))
                .ok_or_else(|| bad(CellProblem::NotAnInlineValue)),
        }
    }
}

fn number(cell: &str, decimal_comma: bool) -> Result<toml::Value, CellError> {
    // Rust's parser also takes `nan` and `inf`: the validator then names
    // them ("must be a finite number"), rather than "not a number".
    cell.parse::<f64>().map(toml::Value::Float).map_err(|_| {
        let problem = if !decimal_comma && super::csv_dialect::is_decimal_comma(cell) {
            CellProblem::DecimalCommaUndeclared
        } else if decimal_comma && super::csv_dialect::is_decimal_point(cell) {
            CellProblem::DecimalPointAmongCommas
        } else {
            CellProblem::NotANumber
        };
        CellError {
            shown: super::limits::echo(cell),
            problem,
        }
    })
}

/// A cell that is not a value of its column's kind: the cell as shown
/// (cut to [`super::limits::MAX_ECHO_CHARS`]) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{shown}` {problem}")]
pub struct CellError {
    pub shown: String,
    pub problem: CellProblem,
}

/// What is wrong with a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CellProblem {
    #[error("has a decimal point, but the file writes decimal commas")]
    DecimalPointAmongCommas,
    #[error("is not a number with a decimal point; if the file writes decimal commas, pass --decimal-comma")]
    DecimalCommaUndeclared,
    #[error("is not a number")]
    NotANumber,
    #[error("is not true or false")]
    NotAFlag,
    #[error("is not a whole number >= 0")]
    NotACount,
    #[error("is not a TOML value like [[20.0, 12.0], [30.0, 20.0]]")]
    NotAnInlineValue,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_read_by_their_kind() {
        assert_eq!(
            Kind::Flag.read("TRUE", false),
            Ok(toml::Value::Boolean(true))
        );
        assert!(Kind::Flag
            .read("yes", false)
            .unwrap_err()
            .to_string()
            .contains("true or false"));
        assert_eq!(Kind::Count.read("5", false), Ok(toml::Value::Integer(5)));
        assert!(Kind::Count.read("-1", false).is_err() && Kind::Count.read("2.5", false).is_err());
        assert_eq!(Kind::Number.read("35", false), Ok(toml::Value::Float(35.0)));
        assert!(Kind::Number
            .read("0,586", false)
            .unwrap_err()
            .to_string()
            .contains("--decimal-comma"));
        assert_eq!(
            Kind::Number.read("0,586", true),
            Ok(toml::Value::Float(0.586))
        );
        assert!(Kind::Number.read("0.586", true).is_err());
        assert_eq!(
            Kind::Uncertainty.read("0,5", true),
            Ok(toml::Value::Float(0.5))
        );
        assert_eq!(
            Kind::Uncertainty.read("2%", false),
            Ok(toml::Value::String("2%".into()))
        );
        let profile = Kind::Inline
            .read("[[20.0, 12.0], [30, 20]]", false)
            .unwrap();
        assert_eq!(profile.as_array().map(Vec::len), Some(2));
        assert!(Kind::Inline.read("[[20.0, 12.0]", false).is_err());
        let long = format!("[[{}", "1.0, ".repeat(200));
        let e = Kind::Inline.read(&long, false).unwrap_err().to_string();
        assert!(e.len() < 300 && e.contains("characters in all"), "{e}");
        assert_eq!(kind_of("uncertainty.amplitude_mm"), Some(Kind::Uncertainty));
        assert_eq!(kind_of("uncertainty."), None);
        assert_eq!(kind_of("u_trials_mm_s"), None);
    }
}
