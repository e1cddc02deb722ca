//! The setup a `sweep` varies the tail in: the paper's first case, or a
//! dataset's (`--data`, `--case`). The tail's own fields and the rate come
//! from the grid; everything else (body, coupler, oil, wire, channel) from
//! here, so a dataset whose cases differ in any of those must say which
//! case to take rather than have one picked silently. Inside a study the
//! dataset is the study's, with its joined run sheets.

use super::CliError;
use crate::data::quantities::FIELDS;
use crate::data::Case;
use crate::provenance::Inputs;
use std::path::PathBuf;

/// The fields the grid sets; every other numeric field is the setup's.
const GRID_FIELDS: [&str; 4] = [
    "wavelength_mm",
    "amplitude_mm",
    "tail_length_mm",
    "frequency_hz",
];

/// The case whose setup the sweep uses.
/// The files read are recorded in `inputs`.
/// `joined` is a study's dataset with its run sheets (then `data` names
/// its file).
pub fn template(
    data: Option<&PathBuf>,
    joined: Option<&crate::data::Dataset>,
    case: Option<&str>,
    inputs: &Inputs,
) -> Result<Case, CliError> {
    let Some(path) = data else {
        if let Some(id) = case {
            return Err(CliError::input(format!(
                "--case `{id}`: a case of which data? give --data FILE (or run inside a study)"
            )));
        }
        let paper = crate::data::PAPER_TOML.as_bytes();
        inputs.record_named("<built-in paper data>", paper);
        return Ok(crate::data::paper().cases[0].clone());
    };
    let d = match joined {
        Some(d) => d.clone(),
        None => crate::data::load_recorded(path, inputs)?,
    };
    let file = path.display();
    if let Some(id) = case {
        return d.cases.iter().find(|c| c.id == id).cloned().ok_or_else(|| {
            let ids: Vec<&str> = d.cases.iter().map(|c| c.id.as_str()).collect();
            CliError::input(format!(
                "--case `{id}`: {file} has no such case; its cases are {}",
                ids.join(", ")
            ))
        });
    }
    let first = &d.cases[0];
    for other in &d.cases[1..] {
        if let Some(field) = differing_setup(first, other) {
            return Err(CliError::input(format!(
                "--data {file}: its cases `{}` and `{}` differ in {field}; the sweep takes one setup: choose it with --case ID",
                first.id, other.id
            )));
        }
    }
    Ok(first.clone())
}

/// The first setup field (not set by the grid) in which two cases differ.
fn differing_setup(a: &Case, b: &Case) -> Option<String> {
    let numeric = FIELDS
        .iter()
        .filter(|q| !GRID_FIELDS.contains(&q.id))
        .find(|q| q.of(a) != q.of(b))
        .map(|q| format!("{} ({} against {})", q.id, q.of(a), q.of(b)));
    numeric.or_else(|| {
        [
            ("channel_closed", a.channel_closed != b.channel_closed),
            ("orientation", a.orientation != b.orientation),
            ("body_profile", a.body_profile != b.body_profile),
        ]
        .into_iter()
        .find(|(_, differs)| *differs)
        .map(|(name, _)| name.to_string())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_of_one_setup_agree_and_a_changed_oil_is_named() {
        let paper = crate::data::paper();
        let (a, b) = (&paper.cases[0], &paper.cases[4]);
        assert_eq!(
            differing_setup(a, b),
            None,
            "the paper's tails share a setup"
        );
        let mut thinner = b.clone();
        thinner.viscosity_pa_s = 1.0;
        assert!(differing_setup(a, &thinner)
            .unwrap()
            .starts_with("viscosity_pa_s"));
        let mut open = b.clone();
        open.channel_closed = false;
        assert_eq!(differing_setup(a, &open).as_deref(), Some("channel_closed"));
    }
}
