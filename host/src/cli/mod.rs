//! The `swimbot` command line: argument definitions and dispatch. Every
//! subcommand validates its flags into a model, a dataset and settings
//! before any work starts; input problems are [`CliError::Input`] (exit 2).

mod audit;
mod body;
mod budget;
mod cleanup;
mod compare;
mod convert;
mod count;
mod data;
mod diagnose;
mod effects;
mod error;
mod finite;
mod fit;
mod helix;
mod help_lint;
mod likelihood;
mod log;
mod model_args;
mod output;
mod output_guard;
mod plan;
mod report;
pub mod screen;
mod sim;
mod sim_plan;
mod stdout;
mod study;
mod sweep;
mod sweep_setup;
mod synth;

pub use error::CliError;
pub use stdout::note_stdout_closed_at_start;

/// The commands' work without their printing, for the Python package
/// (python/): the same flags (parsed by [`Cli`]), the same numbers.
pub mod api {
    pub use super::audit::audited;
    pub use super::cleanup::settle_output_dir;
    pub use super::compare::{compared, Compared};
    pub use super::diagnose::diagnosed;
    pub use super::fit::{fitted, Fitted};
    pub use super::likelihood::diagnosis_json;
    pub use super::output::{check_output_dir, not_an_input};
    pub use super::output_guard::mark_claimed_dirs;
    pub use super::study::definition;
}

use crate::provenance::Inputs;
use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "swimbot",
    version,
    about = "Model, compare and diagnose a helical-tail swimming robot in a channel",
    long_about = "Resistive-force-theory model of a two-link helical swimmer in a closed, oil-filled channel, \
                  a workbench that compares it with measurements and finds the missing physical effect, \
                  and a whole-robot simulation. Without --data, the paper's built-in measurements are used."
)]
pub struct Cli {
    /// No progress lines or bars on stderr (errors and notes still print).
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// The study file to read and write [default: swimbot-study.toml in the working directory,
    /// when there is one]. Inside a study, compare, diagnose, fit, audit, sweep and report work
    /// on the study's data and current model without --data or model flags.
    #[arg(long, global = true, value_name = "FILE")]
    pub study: Option<std::path::PathBuf>,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Model against measurement for every case, with summary errors and the HTML report.
    Compare(compare::CompareArgs),
    /// Checks of the data themselves: geometry consistency, ratio tests, influence, outliers.
    Audit(audit::AuditArgs),
    /// The tail's 6x6 resistance matrix for one helix.
    Helix(helix::HelixArgs),
    /// Predictions over a grid of geometries (CSV, parallel).
    Sweep(sweep::SweepArgs),
    /// List the catalogue of physical effects.
    Effects(effects::EffectsArgs),
    /// Where the model fails, and which catalogue effect is missing.
    Diagnose(diagnose::DiagnoseArgs),
    /// Calibrate effect parameters on chosen cases; report the error on all.
    Fit(fit::FitArgs),
    /// Synthetic measurements from a chosen truth model.
    Synth(synth::SynthArgs),
    /// The HTML report (comparison, Fig. 4 analogue, parity, residuals, diagnosis).
    Report(report::ReportArgs),
    /// Whole-robot simulation: remote script -> controller -> motor and cell -> swimmer model -> climb.
    Sim(sim::SimArgs),
    /// The body's exact axial drag and rotational drag in free space or in the tube.
    Body(body::BodyArgs),
    /// A dataset from CSV to TOML or back, losslessly (docs/data-format.md).
    Convert(convert::ConvertArgs),
    /// The robot's run log (file or USB port): steady windows, a dataset's trials, the trace figure.
    Log(log::LogArgs),
    /// Start a study: the model you build step by step on one dataset, in swimbot-study.toml.
    Init(study::InitArgs),
    /// Add an effect to the study: calibrate it on top of the current model, print before -> after.
    Add(study::AddArgs),
    /// The study on one screen: data, each step with before -> after, what diagnose says now.
    Steps(study::StepsArgs),
    /// Remove the study's last step.
    Undo(study::UndoArgs),
    /// The next runs: those that best separate the study's rival explanations, as a run sheet.
    Plan(plan::PlanArgs),
    /// The study's data: join a filled run sheet (`data add SHEET`, every step recalibrated), list what joined.
    Data(data::DataArgs),
}

/// Run a parsed command line. A run that fails (or is interrupted by
/// SIGINT or SIGTERM) leaves no temporary file and no folder it created
/// (`cleanup`); a failure to write stdout is an error (exit 2).
/// `command` is the command line `cli` was parsed from, one argument per
/// entry: the outputs' provenance records it, and the output guard reads
/// the files it names.
pub fn run(cli: Cli, command: Vec<String>) -> Result<(), CliError> {
    crate::progress::set_quiet(cli.quiet);
    stdout::check_stdout_open()?;
    cleanup::install_signal_cleanup();
    crate::atomic_file::set_transactional(true);
    stdout::install_stdout_failure_exit();
    let inputs = &Inputs::for_command(command);
    let done = dispatch(cli, inputs).and_then(|()| {
        use std::io::Write;
        stdout::stdout_written(std::io::stdout().flush(), "the output")
    });
    match &done {
        Ok(()) => {
            output_guard::mark_claimed_dirs(inputs);
            cleanup::keep_new_dirs();
            crate::atomic_file::keep_committed();
        }
        Err(_) => cleanup::clean_up(),
    }
    done
}

/// Runs the command. What it reads is recorded in `inputs`, made by
/// [`run`] for this command alone: its outputs name those files, and
/// refuse to overwrite them.
fn dispatch(cli: Cli, inputs: &Inputs) -> Result<(), CliError> {
    let st = &cli.study;
    match cli.command {
        Command::Compare(mut a) => {
            study::fill_from_study(st, &mut a.data, &mut a.model, inputs)?;
            compare::run(a, inputs)
        }
        Command::Audit(mut a) => {
            study::fill_from_study(st, &mut a.data, &mut a.model, inputs)?;
            audit::run(a, inputs)
        }
        Command::Helix(a) => helix::run(a),
        Command::Sweep(mut a) => {
            sweep::in_study(&mut a, st, inputs)?;
            sweep::run(a, inputs)
        }
        Command::Effects(a) => effects::run(a, inputs),
        Command::Diagnose(mut a) => {
            study::fill_from_study(st, &mut a.data, &mut a.model, inputs)?;
            diagnose::run(a, inputs)
        }
        Command::Fit(mut a) => {
            study::fill_from_study(st, &mut a.data, &mut a.model, inputs)?;
            fit::run(a, inputs)
        }
        Command::Synth(a) => synth::run(a, inputs),
        Command::Report(a) => report::run(a, st, inputs),
        Command::Sim(a) => sim::run(a, inputs),
        Command::Body(a) => body::run(a, inputs),
        Command::Convert(a) => convert::run(a, inputs),
        Command::Log(a) => log::run(a, inputs),
        Command::Init(a) => study::run_init(a, st, inputs),
        Command::Add(a) => study::run_add(a, st, inputs),
        Command::Steps(a) => study::run_steps(a, st, inputs),
        Command::Undo(a) => study::run_undo(a, st, inputs),
        Command::Plan(a) => plan::run(a, st, inputs),
        Command::Data(a) => data::run(a, st, inputs),
    }
}
