//! The run sheet: the plan as a dataset CSV (docs/data-format.md) with the
//! measurement columns (`u_mm_s`, `u_ci_mm_s`, `omega_body_hz`,
//! `omega_body_ci_hz`, `trials`) left empty for the lab to fill in, one row
//! per run in the order to run them (by tail, then tube and oil, then
//! rate). What the plan says of each run rides in `labels.` columns, text
//! the dataset keeps but never offers `diagnose` as a feature: the tail,
//! the expected separation in standard deviations, the rivals it
//! separates, the remote's keys and the expected duration.

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
pub const PLAN_COLUMNS: [&str; 5] = [
    "labels.tail",
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
        row.push(format!("{:.2}", r.separation_sigma));
        row.push(format!(
            "{} vs {}",
            rivals.models[i].name, rivals.models[j].name
        ));
        row.push(run_keys(c.frequency_hz).unwrap_or_default());
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
