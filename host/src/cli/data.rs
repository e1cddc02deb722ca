//! `swimbot data add SHEET` and `swimbot data list`: the study's data and
//! the run sheets joined to it ([`crate::study::sheets`]). Joining a sheet
//! recalibrates every step on the joined data and prints each model's
//! error before -> after, then what `diagnose` says now.

use super::study::open;
use super::CliError;
use crate::provenance::Inputs;
use crate::study::{JoinOptions, Joined, Stats, Study};
use clap::{Args, Subcommand};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct DataArgs {
    #[command(subcommand)]
    pub command: DataCommand,
}

#[derive(Subcommand, Debug)]
pub enum DataCommand {
    /// Join a filled run sheet (the CSV `swimbot plan` wrote, or cases `swimbot log` made) to the study's data: every step is recalibrated, then diagnosed again.
    Add(DataAddArgs),
    /// The study's dataset and the run sheets joined to it, with their hashes.
    List(DataListArgs),
}

#[derive(Args, Debug)]
pub struct DataAddArgs {
    /// The filled sheet (CSV or TOML, docs/data-format.md); rows with no measurement are runs not made and are left out.
    #[arg(value_name = "SHEET")]
    pub sheet: PathBuf,
    /// Do not diagnose the recalibrated model [default: diagnose, as `add` does].
    #[arg(long)]
    pub no_diagnose: bool,
    /// The diagnosis's whole note after its headline.
    #[arg(long)]
    pub verbose: bool,
}

#[derive(Args, Debug)]
pub struct DataListArgs {}

pub fn run(a: DataArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    match a.command {
        DataCommand::Add(a) => run_add(a, study, inputs),
        DataCommand::List(_) => run_list(study, inputs),
    }
}

fn run_add(a: DataAddArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let mut s = open(study, inputs)?;
    let spinner = crate::progress::spinner(&format!(
        "joining {} and recalibrating every step",
        a.sheet.display()
    ));
    let joined = s.join_sheet(
        &a.sheet,
        &JoinOptions {
            diagnose: !a.no_diagnose,
        },
    );
    spinner.finish_and_clear();
    let joined = joined?;
    inputs.record_all(s.inputs());
    let width = super::screen::width();
    for line in joined_lines(&s, &joined) {
        println!("{}", super::screen::study::line(&line, width));
    }
    if let Some(d) = s.last_diagnosis() {
        println!(
            "{}",
            super::screen::study::diagnosis("diagnose now", d, a.verbose, width)
        );
    }
    Ok(())
}

fn pct(v: f64) -> String {
    format!("{:.2} %", 100.0 * v)
}

fn chi2_dof(s: &Stats) -> String {
    s.chi2_reduced
        .map_or_else(|| "-".into(), |v| crate::format::fmt_sig(v, 3))
}

/// What joining did, one line a model (the start, then each step).
fn joined_lines(s: &Study, j: &Joined) -> Vec<String> {
    let n = s.dataset().cases.len();
    let mut out = vec![format!(
        "joined {} to {}: {} run{} ({}), {} -> {n} cases",
        j.sheet.path.display(),
        s.path().display(),
        j.sheet.cases.len(),
        if j.sheet.cases.len() == 1 { "" } else { "s" },
        j.sheet.cases.join(", "),
        j.cases_before
    )];
    if !j.sheet.skipped.is_empty() {
        out.push(format!(
            "left out {} row{} with no measurement (runs not made): {}",
            j.sheet.skipped.len(),
            if j.sheet.skipped.len() == 1 { "" } else { "s" },
            j.sheet.skipped.join(", ")
        ));
    }
    out.push(format!(
        "every model recalibrated: MARE and reduced chi-square on the {} cases before -> on the {n} now",
        j.cases_before
    ));
    for (k, m) in j.models.iter().enumerate() {
        let label = match k {
            0 => format!("start ({})", s.file().model.preset),
            _ => format!("step {k} {}", m.what),
        };
        out.push(format!(
            "  {label}: MARE {} -> {}, chi2/dof {} -> {}{}",
            pct(m.before.mare),
            pct(m.after.mare),
            chi2_dof(&m.before),
            chi2_dof(&m.after),
            if m.rises {
                "; on the joined data this step raises the error (`swimbot undo` removes it)"
            } else {
                ""
            }
        ));
    }
    if let Some(k) = j.models.iter().skip(1).position(contradicted) {
        let steps = j.models.len() - 1;
        out.push(format!(
            "step {} ({}) was at the noise floor and is far above it now: the new runs contradict it. `swimbot undo`{} back to the model before it, then `swimbot diagnose`",
            k + 1,
            j.models[k + 1].what,
            match steps - k {
                1 => String::new(),
                n => format!(" {n} times"),
            }
        ));
    }
    out
}

/// A step the joined runs refute: at its noise floor on the data before,
/// ten times its floor's chi-square now.
fn contradicted(m: &crate::study::Recalibrated) -> bool {
    let floor = m.after.noise_floor_chi2.unwrap_or(f64::INFINITY);
    m.before.at_noise_floor && m.after.chi2 > 10.0 * floor
}

fn run_list(study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let s = open(study, inputs)?;
    let d = &s.file().dataset;
    let base = s.dataset().cases.len() - d.sheets.iter().map(|x| x.cases.len()).sum::<usize>();
    println!("{}: {base} cases, SHA-256 {}", d.path.display(), d.sha256);
    for sh in &d.sheets {
        println!(
            "  + {}: {} run{} ({}), SHA-256 {}, joined {}",
            sh.path.display(),
            sh.cases.len(),
            if sh.cases.len() == 1 { "" } else { "s" },
            sh.cases.join(", "),
            sh.sha256,
            sh.joined_utc
        );
    }
    println!("{} cases in all", s.dataset().cases.len());
    Ok(())
}
