//! A filled run sheet joined to the study's data: every row must be a run
//! of the study's robot (the same body, coupler, wire and density: a sheet
//! from another robot is refused) carrying a tail it names truthfully (a
//! row whose `labels.tail` names a data case must have that case's tail
//! geometry: a tail changed since is refused), with at least one
//! measurement and an id of its own. A refusal names the sheet, the row
//! (the case's id and its place among the sheet's cases) and the field,
//! and changes nothing.

use crate::data::{Case, Dataset};

/// Why a sheet's row cannot join the study's data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{sheet}: row {row} (case `{case}`): field `{field}`: {message}")]
pub struct SheetError {
    pub sheet: String,
    /// 1-based, among the sheet's cases.
    pub row: usize,
    pub case: String,
    pub field: &'static str,
    pub message: String,
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The setup fields a run of the study's robot shares with its data.
fn body_fields(c: &Case) -> [(&'static str, f64); 6] {
    [
        ("body_diameter_mm", c.body_diameter_mm),
        ("body_length_mm", c.body_length_mm),
        ("coupler_diameter_mm", c.coupler_diameter_mm),
        ("coupler_length_mm", c.coupler_length_mm),
        ("wire_diameter_mm", c.wire_diameter_mm),
        ("density_kg_m3", c.density_kg_m3),
    ]
}

fn tail_fields(c: &Case) -> [(&'static str, f64); 3] {
    [
        ("wavelength_mm", c.wavelength_mm),
        ("amplitude_mm", c.amplitude_mm),
        ("tail_length_mm", c.tail_length_mm),
    ]
}

fn label<'a>(c: &'a Case, key: &str) -> Option<&'a str> {
    c.recorded
        .labels
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

/// Check one row against the study's data (module docs).
fn check_row(data: &Dataset, c: &Case) -> Result<(), (&'static str, String)> {
    let Some(first) = data.cases.first() else {
        return Ok(());
    };
    for ((field, want), (_, got)) in body_fields(first).into_iter().zip(body_fields(c)) {
        if !same(want, got) {
            return Err((
                field,
                format!("{got} here, {want} in the study's data: another robot's run"),
            ));
        }
    }
    if let Some(tail) = label(c, "tail").and_then(|t| data.cases.iter().find(|d| d.id == t)) {
        for ((field, want), (_, got)) in tail_fields(tail).into_iter().zip(tail_fields(c)) {
            if !same(want, got) {
                return Err((
                    field,
                    format!(
                        "{got} here, {want} for the tail of case `{}` it names: the tail changed",
                        tail.id
                    ),
                ));
            }
        }
    }
    if c.u_mm_s.is_none() && c.omega_body_hz.is_none() {
        return Err((
            "u_mm_s",
            "no measurement: fill in u_mm_s or omega_body_hz (with their intervals or trials)"
                .into(),
        ));
    }
    if data.cases.iter().any(|d| d.id == c.id) {
        return Err((
            "id",
            "the study's data already have a case of this id".into(),
        ));
    }
    Ok(())
}

/// The study's data with the sheet's rows after them, or the first row
/// that cannot join (module docs); `sheet_name` names the sheet in errors.
pub fn merge(data: &Dataset, sheet: &Dataset, sheet_name: &str) -> Result<Dataset, SheetError> {
    let mut out = data.clone();
    for (i, c) in sheet.cases.iter().enumerate() {
        check_row(&out, c).map_err(|(field, message)| SheetError {
            sheet: sheet_name.to_string(),
            row: i + 1,
            case: c.id.clone(),
            field,
            message,
        })?;
        out.cases.push(c.clone());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filled(data: &Dataset) -> Dataset {
        let mut s = data.clone();
        s.cases.truncate(1);
        s.cases[0].id = "plan-1".into();
        s.cases[0].channel_diameter_mm = 45.0;
        s.cases[0]
            .recorded
            .labels
            .push(("tail".into(), data.cases[0].id.clone()));
        s
    }

    #[test]
    fn a_filled_run_of_the_same_robot_joins_after_the_data() {
        let data = crate::data::paper();
        let merged = merge(&data, &filled(&data), "plan.csv").unwrap();
        assert_eq!(merged.cases.len(), data.cases.len() + 1);
        assert_eq!(merged.cases.last().unwrap().id, "plan-1");
    }

    #[test]
    fn another_body_a_changed_tail_an_empty_row_or_a_taken_id_is_refused_by_row_and_field() {
        let data = crate::data::paper();
        let mut body = filled(&data);
        body.cases[0].body_diameter_mm += 1.0;
        let e = merge(&data, &body, "plan.csv").unwrap_err();
        assert_eq!((e.row, e.field), (1, "body_diameter_mm"), "{e}");
        assert!(
            e.to_string().contains("plan.csv: row 1 (case `plan-1`)"),
            "{e}"
        );

        let mut tail = filled(&data);
        tail.cases[0].tail_length_mm *= 1.1;
        assert_eq!(
            merge(&data, &tail, "s").unwrap_err().field,
            "tail_length_mm"
        );

        let mut empty = filled(&data);
        empty.cases[0].u_mm_s = None;
        empty.cases[0].omega_body_hz = None;
        assert_eq!(merge(&data, &empty, "s").unwrap_err().field, "u_mm_s");

        let mut taken = filled(&data);
        taken.cases[0].id = data.cases[2].id.clone();
        assert_eq!(merge(&data, &taken, "s").unwrap_err().field, "id");
    }
}
