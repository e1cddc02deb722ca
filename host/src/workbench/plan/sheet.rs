//! The run sheet: the plan as a dataset CSV (docs/data-format.md) with the
//! measurement columns (`u_mm_s`, `u_ci_mm_s`, `omega_body_hz`,
//! `omega_body_ci_hz`, `trials`) left empty for the lab to fill in, one row
//! per run in the order to run them (by tail, then tube and oil, then
//! rate). `frequency_hz` is the tail's expected rate in the lab at the
//! run's set-point; the lab writes over it the rate it measured. What the
//! plan says of each run rides in `labels.` columns, text the dataset
//! keeps but never offers `diagnose` as a feature: the tail, the
//! set-point (the motor's rate, which the controller holds), the expected
//! separation in standard deviations, the rivals it separates, the
//! remote's keys and the expected duration.

use super::keys::{duration_s, run_keys};
use super::rivals::Rivals;
use super::select::{Plan, PlannedRun};
use crate::data::Case;

/// The case columns a sheet writes, in order.
const CASE_COLUMNS: [&str; 17] = [
    "id",
    "wavelength_mm",
    "amplitude_mm",
    "tail_length_mm",
    "wire_diameter_mm",
    "handedness",
    "frequency_hz",
    "channel_diameter_mm",
    "channel_length_mm",
    "channel_closed",
    "orientation",
    "viscosity_pa_s",
    "density_kg_m3",
    "body_diameter_mm",
    "body_length_mm",
    "coupler_diameter_mm",
    "coupler_length_mm",
];
/// The measurement columns, empty.
pub const MEASURED_COLUMNS: [&str; 5] = [
    "u_mm_s",
    "u_ci_mm_s",
    "omega_body_hz",
    "omega_body_ci_hz",
    "trials",
];
/// The plan's columns.
pub const PLAN_COLUMNS: [&str; 6] = [
    "labels.tail",
    "labels.set_point_hz",
    "labels.expected_sigma",
    "labels.separates",
    "labels.keys",
    "labels.duration_s",
];

fn case_cells(c: &Case) -> Vec<String> {
    let n = |x: f64| format!("{x:?}");
    vec![
        c.id.clone(),
        n(c.wavelength_mm),
        n(c.amplitude_mm),
        n(c.tail_length_mm),
        n(c.wire_diameter_mm),
        format!("{:?}", c.handedness).to_lowercase(),
        n(c.frequency_hz),
        n(c.channel_diameter_mm),
        n(c.channel_length_mm),
        c.channel_closed.to_string(),
        format!("{:?}", c.orientation).to_lowercase(),
        n(c.viscosity_pa_s),
        n(c.density_kg_m3),
        n(c.body_diameter_mm),
        n(c.body_length_mm),
        n(c.coupler_diameter_mm),
        n(c.coupler_length_mm),
    ]
}

/// A candidate run as a sheet row's case: its labels say the tail and
/// the set-point the controller holds, as the sheet's columns do (what
/// [`crate::sim::lab`] reads to run it).
pub fn labelled(c: &super::Candidate, id: &str) -> Case {
    let mut case = c.case.clone();
    case.id = id.to_string();
    case.recorded.labels.push(("tail".into(), c.tail.clone()));
    case.recorded
        .labels
        .push(("set_point_hz".into(), format!("{:?}", c.set_point_hz)));
    case
}

/// The runs in the order to run them, each with its sheet id `plan-N`.
pub fn ordered(plan: &Plan) -> Vec<PlannedRun> {
    let mut runs = plan.runs.clone();
    runs.sort_by(|a, b| {
        let (x, y) = (&a.candidate, &b.candidate);
        x.tail
            .cmp(&y.tail)
            .then(x.case.tail_length_mm.total_cmp(&y.case.tail_length_mm))
            .then(x.case.amplitude_mm.total_cmp(&y.case.amplitude_mm))
            .then(x.case.wavelength_mm.total_cmp(&y.case.wavelength_mm))
            .then(
                x.case
                    .channel_diameter_mm
                    .total_cmp(&y.case.channel_diameter_mm),
            )
            .then(x.case.viscosity_pa_s.total_cmp(&y.case.viscosity_pa_s))
            .then(x.case.frequency_hz.total_cmp(&y.case.frequency_hz))
    });
    for (i, r) in runs.iter_mut().enumerate() {
        r.candidate.case.id = format!("plan-{}", i + 1);
    }
    runs
}

/// The sheet's text (module docs); `header` lines are written first as
/// `#` comments (the study, the criterion).
pub fn to_csv(plan: &Plan, rivals: &Rivals, header: &[String]) -> Result<String, csv::Error> {
    let mut out = String::new();
    for h in header {
        out.push_str(&format!("# {h}\n"));
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    let columns: Vec<&str> = CASE_COLUMNS
        .iter()
        .chain(&MEASURED_COLUMNS)
        .chain(&PLAN_COLUMNS)
        .copied()
        .collect();
    w.write_record(&columns)?;
    for r in ordered(plan) {
        let c = &r.candidate.case;
        let mut row = case_cells(c);
        row.extend(MEASURED_COLUMNS.iter().map(|_| String::new()));
        let (i, j) = r.separates;
        row.push(r.candidate.tail.clone());
        row.push(format!("{:?}", r.candidate.set_point_hz));
        row.push(format!("{:.2}", r.separation_sigma));
        row.push(format!(
            "{} vs {}",
            rivals.models[i].name, rivals.models[j].name
        ));
        row.push(run_keys(r.candidate.set_point_hz).unwrap_or_default());
        row.push(
            duration_s(c, r.expected.u_mm_s)
                .map(|t| format!("{t:.0}"))
                .unwrap_or_default(),
        );
        w.write_record(&row)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    out.push_str(&String::from_utf8_lossy(&bytes));
    Ok(out)
}

/// A measured run to write into its sheet row.
#[derive(Debug, Clone, Copy)]
pub struct Filled {
    pub frequency_hz: f64,
    pub u: crate::data::Measured,
    pub omega: crate::data::Measured,
}

/// The sheet's text (`text`, as [`to_csv`] wrote it) with each row named
/// in `runs` filled in: the measured rate, means, intervals and trials.
/// Comment lines and every other cell are kept; `note` is added as a
/// comment. A missing column, or a run naming no row, is an error.
pub fn fill(text: &str, runs: &[(String, Filled)], note: &str) -> Result<String, String> {
    let body_at = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| l.len() + 1)
        .sum::<usize>()
        .min(text.len());
    let (comments, body) = text.split_at(body_at);
    let mut r = csv::ReaderBuilder::new().from_reader(body.as_bytes());
    let header = r.headers().map_err(|e| e.to_string())?.clone();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.trim() == name)
            .ok_or_else(|| format!("the sheet has no `{name}` column"))
    };
    let [id, f, u, u_ci, om, om_ci, trials] = [
        "id",
        "frequency_hz",
        "u_mm_s",
        "u_ci_mm_s",
        "omega_body_hz",
        "omega_body_ci_hz",
        "trials",
    ]
    .map(col);
    let (id, f, u, u_ci, om, om_ci, trials) = (id?, f?, u?, u_ci?, om?, om_ci?, trials?);
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&header).map_err(|e| e.to_string())?;
    let mut used = vec![false; runs.len()];
    for rec in r.records() {
        let mut row: Vec<String> = rec
            .map_err(|e| e.to_string())?
            .iter()
            .map(str::to_string)
            .collect();
        if let Some(k) = runs.iter().position(|(i, _)| row.get(id) == Some(i)) {
            let m = &runs[k].1;
            used[k] = true;
            row[f] = format!("{:?}", m.frequency_hz);
            row[u] = format!("{:?}", m.u.mean);
            row[u_ci] = format!("{:?}", m.u.ci_half_width);
            row[om] = format!("{:?}", m.omega.mean);
            row[om_ci] = format!("{:?}", m.omega.ci_half_width);
            row[trials] = m.u.trials.to_string();
        }
        w.write_record(&row).map_err(|e| e.to_string())?;
    }
    if let Some(k) = used.iter().position(|u| !u) {
        return Err(format!("no row of the sheet has the id `{}`", runs[k].0));
    }
    let bytes = w.into_inner().map_err(|e| e.into_error().to_string())?;
    Ok(format!(
        "{comments}# {note}\n{}",
        String::from_utf8_lossy(&bytes)
    ))
}
