//! `swimbot sim --plan SHEET --truth MODEL`: the simulated lab
//! ([`crate::sim::lab`]): every row of a run sheet run through the whole
//! robot in a world the truth model describes, written back as the sheet
//! filled in (`SHEET-filled.csv`, what `swimbot data add` joins to the
//! study) and one run log per row (`ID.swlog`, what `swimbot log` reads).

use super::sim::SimArgs;
use super::CliError;
use crate::format::fmt_sig;
use crate::provenance::Inputs;
use crate::sim::lab::{run_sheet, LabSettings};
use crate::sim::Robot;
use crate::workbench::plan::sheet::{fill, Filled};
use crate::workbench::synth::SynthSettings;
use std::path::Path;

/// A trial's relative noise above this is no measurement (a 50 % scatter).
const MAX_NOISE: f64 = 0.5;
const MAX_TRIALS: u32 = 1000;

fn settings(args: &SimArgs) -> Result<LabSettings, CliError> {
    let noise = args.noise.unwrap_or(0.02);
    if !(noise.is_finite() && (0.0..=MAX_NOISE).contains(&noise)) {
        return Err(CliError::input(format!(
            "--noise: a relative standard deviation from 0 to {MAX_NOISE}, got {noise}"
        )));
    }
    let trials = args.trials.unwrap_or(5);
    if !(2..=MAX_TRIALS).contains(&trials) {
        return Err(CliError::input(format!(
            "--trials: from 2 (a mean needs an interval) to {MAX_TRIALS}, got {trials}"
        )));
    }
    Ok(LabSettings {
        measurement: SynthSettings {
            noise_rel: noise,
            trials,
            seed: args.seed.unwrap_or(1),
            ..SynthSettings::default()
        },
        max_run_s: args.max_time_s.min(LabSettings::default().max_run_s),
    })
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map_or_else(|| "sheet".into(), |s| s.to_string_lossy().into_owned())
}

pub fn run(args: &SimArgs, robot: &Robot, inputs: &Inputs) -> Result<(), CliError> {
    let sheet_path = args.plan.as_ref().expect("--plan given");
    let catalogue = args.model.effect_files.load(inputs)?;
    let truth_text = args.truth.as_deref().unwrap_or_default();
    let truth = super::synth::parse_truth(truth_text, &catalogue)?;
    let s = settings(args)?;
    let text =
        crate::input_file::read_text(sheet_path, crate::input_file::cap::DATASET, "a run sheet")
            .map_err(|e| CliError::input(format!("{}: {e}", sheet_path.display())))?;
    let sheet = crate::data::load_recorded(sheet_path, inputs)?;
    super::output::check_output_dir(&args.output, "sim", inputs)?;
    let spinner = crate::progress::spinner(&format!(
        "running the {} rows of {} through the robot",
        sheet.cases.len(),
        sheet_path.display()
    ));
    let runs = run_sheet(robot, &truth, &sheet, &s);
    spinner.finish_and_clear();
    let runs = runs.map_err(|e| CliError::input(format!("{}: {e}", sheet_path.display())))?;
    let filled: Vec<(String, Filled)> = runs
        .iter()
        .map(|r| {
            let c = &r.case;
            let pair = Filled {
                frequency_hz: c.frequency_hz,
                u: c.u_mm_s.expect("a lab run measures U"),
                omega: c.omega_body_hz.expect("a lab run measures Omega_b"),
            };
            (c.id.clone(), pair)
        })
        .collect();
    let m = &s.measurement;
    let note = format!(
        "measured by swimbot sim --plan in a world of `{}`: {} trials a run, noise {} % each, seed {}",
        truth.describe(),
        m.trials,
        fmt_sig(100.0 * m.noise_rel, 3),
        m.seed
    );
    let out_text = fill(&text, &filled, &note)
        .map_err(|e| CliError::input(format!("{}: {e}", sheet_path.display())))?;
    let sheet_out = args.output.join(format!("{}-filled.csv", stem(sheet_path)));
    let mut files = vec![(sheet_out.clone(), out_text.into_bytes())];
    for r in &runs {
        files.push((
            args.output.join(format!("{}.swlog", r.case.id)),
            r.log_image.clone(),
        ));
    }
    for (p, _) in &files {
        super::output::check_output_file(p, inputs)?;
    }
    super::output::write_all_atomically(&files, inputs)?;
    println!(
        "ran {} row{} of {} in a world of {}:",
        runs.len(),
        if runs.len() == 1 { "" } else { "s" },
        sheet_path.display(),
        truth.describe()
    );
    for r in &runs {
        let c = &r.case;
        println!(
            "  {}: motor held at {} Hz for {} s; tail {} Hz in the lab, U {} mm/s, Omega_b {} Hz",
            c.id,
            fmt_sig(r.set_point_hz, 3),
            fmt_sig(r.steady_s, 3),
            fmt_sig(c.frequency_hz, 4),
            fmt_sig(c.u_mm_s.map_or(f64::NAN, |m| m.mean), 4),
            fmt_sig(c.omega_body_hz.map_or(f64::NAN, |m| m.mean), 4),
        );
    }
    println!(
        "wrote {} and {} run log{} in {}; join the sheet with `swimbot data add {}`",
        sheet_out.display(),
        runs.len(),
        if runs.len() == 1 { "" } else { "s" },
        args.output.display(),
        sheet_out.display()
    );
    Ok(())
}
