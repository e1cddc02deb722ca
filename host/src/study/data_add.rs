//! A filled run sheet joined to the study's data: every row must be a run
//! of the study's robot (the same body, coupler, wire and density: a sheet
//! from another robot is refused) carrying a tail it names truthfully (a
//! row whose `labels.tail` names a data case must have that case's tail
//! geometry: a tail changed since is refused) and an id of its own. A row
//! with no measurement is a run not made: it is left out and listed. A
//! refusal names the sheet, the row (the case's id and its place among the
//! sheet's cases) and the field, and changes nothing.

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
    if data.cases.iter().any(|d| d.id == c.id) {
        return Err((
            "id",
            "the study's data already have a case of this id".into(),
        ));
    }
    Ok(())
}

/// A sheet joined: the data with its measured rows after them.
#[derive(Debug, Clone)]
pub struct Merged {
    pub data: Dataset,
    /// The ids of the rows that joined, in the sheet's order.
    pub joined: Vec<String>,
    /// Rows with no measurement at all (runs not made), left out.
    pub skipped: Vec<String>,
}

fn measured(c: &Case) -> bool {
    c.u_mm_s.is_some() || c.omega_body_hz.is_some()
}

/// The study's data with the sheet's measured rows after them, or the
/// first row that cannot join (module docs); `sheet_name` names the sheet
/// in errors. A row with no measurement is a run not made: left out and
/// listed, unless no row has one.
pub fn merge(data: &Dataset, sheet: &Dataset, sheet_name: &str) -> Result<Merged, SheetError> {
    let mut out = Merged {
        data: data.clone(),
        joined: Vec::new(),
        skipped: Vec::new(),
    };
    let refuse = |i: usize, c: &Case, field, message| SheetError {
        sheet: sheet_name.to_string(),
        row: i + 1,
        case: c.id.clone(),
        field,
        message,
    };
    for (i, c) in sheet.cases.iter().enumerate() {
        if !measured(c) {
            out.skipped.push(c.id.clone());
            continue;
        }
        check_row(&out.data, c).map_err(|(field, message)| refuse(i, c, field, message))?;
        out.joined.push(c.id.clone());
        out.data.cases.push(c.clone());
    }
    if out.joined.is_empty() {
        let first = sheet.cases.first().ok_or_else(|| SheetError {
            sheet: sheet_name.to_string(),
            row: 0,
            case: String::new(),
            field: "id",
            message: "the sheet has no rows".into(),
        })?;
        return Err(refuse(
            0,
            first,
            "u_mm_s",
            "no row of the sheet has a measurement: fill in u_mm_s or omega_body_hz (with u_ci_mm_s / omega_body_ci_hz, or trials) for the runs made".into(),
        ));
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
        assert_eq!(merged.data.cases.len(), data.cases.len() + 1);
        assert_eq!(merged.data.cases.last().unwrap().id, "plan-1");
        assert_eq!(merged.joined, ["plan-1"]);
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
        let mut one_run_made = filled(&data);
        one_run_made.cases.push(empty.cases[0].clone());
        one_run_made.cases[1].id = "plan-2".into();
        let m = merge(&data, &one_run_made, "s").unwrap();
        assert_eq!(
            (m.joined, m.skipped),
            (vec!["plan-1".to_string()], vec!["plan-2".to_string()])
        );

        let mut taken = filled(&data);
        taken.cases[0].id = data.cases[2].id.clone();
        assert_eq!(merge(&data, &taken, "s").unwrap_err().field, "id");
    }
}
