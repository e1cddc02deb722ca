//! `swimbot init`, `add`, `steps` and `undo`: the study's commands, thin
//! over [`crate::study::Study`]; and the translation that lets `compare`,
//! `diagnose`, `fit` and `audit` work on the study's current model when
//! run inside a study without `--data` or model flags.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, print_csv, print_json, TableJsonCsv};
use super::CliError;
use crate::format::fmt_sig;
use crate::provenance::Inputs;
use crate::study::{
    AddOptions, Application, Definition, InitOptions, Snapshot, StepRecord, Study, StudyError,
    DEFAULT_FILE,
};
use clap::Args;
use std::path::{Path, PathBuf};

/// `println!` wrapped at the terminal's width (`cli/screen/study.rs`).
macro_rules! say {
    ($($t:tt)*) => {
        println!("{}", super::screen::study::line(&format!($($t)*), super::screen::width()))
    };
}

/// [`say!`] for lines that name files: no symbols in place of their words.
macro_rules! say_plain {
    ($($t:tt)*) => {
        println!("{}", super::screen::study::plain_line(&format!($($t)*), super::screen::width()))
    };
}

impl From<StudyError> for CliError {
    fn from(e: StudyError) -> Self {
        if e.is_input() {
            CliError::input(e)
        } else {
            CliError::failure(e)
        }
    }
}

#[derive(Args, Debug)]
pub struct InitArgs {
    /// The measurements the study is calibrated on, TOML or CSV (docs/data-format.md).
    #[arg(long, value_name = "FILE")]
    pub data: PathBuf,
    /// The base model the steps start from: base, paper, paper-lighthill, physics [default: base].
    #[arg(long, default_value = "base")]
    pub preset: String,
    /// Start again over a study already there (its steps are lost); also
    /// how a study is re-pinned to a dataset that changed.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub likelihood: super::likelihood::LikelihoodArgs,
    /// Also print the first diagnosis's verdict in full.
    #[arg(long)]
    pub verbose: bool,
}

#[derive(Args, Debug)]
pub struct AddArgs {
    /// A catalogue effect (`swimbot effects`), or an effects file FILE.toml[#NAME]
    /// (e.g. the law `diagnose --write-effect found.toml` wrote).
    #[arg(value_name = "EFFECT | FILE[#NAME]")]
    pub effect: String,
    /// Refit every step's parameters jointly [default: earlier steps held at their values].
    #[arg(long)]
    pub refit_all: bool,
    /// Record the step even if the error (MARE) rises.
    #[arg(long)]
    pub force: bool,
    /// Also print the diagnosis after the step in full.
    #[arg(long)]
    pub verbose: bool,
}

#[derive(Args, Debug)]
pub struct StepsArgs {
    /// Output format on stdout (json: the whole study, the numbers the page
    /// prints; csv: one row per step, its statistics before and after;
    /// latex: the steps as a booktabs table; markdown: the same for a lab
    /// notebook).
    #[arg(long, value_enum, default_value = "table")]
    pub format: StepsFormat,
    /// Apply the study to other data, every parameter held at the study's
    /// values (calibrated on the study's data, predicting these) [default: none, the study's own
    /// data as recorded].
    #[arg(long, value_name = "NEW.csv")]
    pub data: Option<PathBuf>,
    /// Also print the diagnoses' verdicts in full.
    #[arg(long)]
    pub verbose: bool,
}

/// `steps --format`: the console table, JSON, CSV, or a paper's table.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepsFormat {
    Table,
    Json,
    Csv,
    Latex,
    Markdown,
}

#[derive(Args, Debug)]
pub struct UndoArgs {}

/// The study file to use: `--study FILE`, else [`DEFAULT_FILE`] in the
/// working directory when there is one.
pub fn locate(explicit: &Option<PathBuf>) -> Option<PathBuf> {
    Study::locate(explicit.as_deref(), Path::new("."))
}

/// The study, its files recorded in `inputs`.
pub(super) fn open(explicit: &Option<PathBuf>, inputs: &Inputs) -> Result<Study, CliError> {
    let path = locate(explicit).ok_or_else(|| {
        CliError::input(format!(
            "no study in this folder ({DEFAULT_FILE}); start one with `swimbot init --data FILE`, or give --study FILE"
        ))
    })?;
    let s = Study::open(&path)?;
    inputs.record_all(s.inputs());
    Ok(s)
}

pub fn run_init(a: InitArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let path = study.clone().unwrap_or_else(|| PathBuf::from(DEFAULT_FILE));
    let spinner = crate::progress::spinner("diagnosing the base model");
    let s = Study::init(
        &path,
        &a.data,
        &InitOptions {
            preset: a.preset,
            likelihood: a.likelihood.get(),
            force: a.force,
            diagnose: true,
        },
    );
    spinner.finish_and_clear();
    let s = s?;
    inputs.record_all(s.inputs());
    say_plain!(
        "started the study {} on {}",
        path.display(),
        s.dataset_path().display()
    );
    print_table(&s, a.verbose);
    Ok(())
}

/// `EFFECT` or `FILE[#NAME]`: a file when the text names one.
/// A file read is recorded in `inputs`.
pub fn definition(text: &str, inputs: &Inputs) -> Result<Definition, CliError> {
    let (file, name) = match text.split_once('#') {
        Some((f, n)) => (f, Some(n)),
        None => (text, None),
    };
    if name.is_some() && file.trim().is_empty() {
        return Err(CliError::input(format!(
            "`{}`: no effects file before `#`: give FILE.toml#NAME (the file `diagnose --write-effect` wrote, and a law in it), or a catalogue effect (`swimbot effects`)",
            crate::data::limits::echo(text)
        )));
    }
    let looks_like_file = name.is_some() || file.ends_with(".toml") || Path::new(file).is_file();
    if looks_like_file {
        return Definition::of_file(Path::new(file), name, inputs).map_err(CliError::input);
    }
    let effect = crate::effects::by_name(text).ok_or_else(|| {
        let known: Vec<&str> = crate::effects::CATALOGUE.iter().map(|e| e.name()).collect();
        CliError::input(format!(
            "no effect `{}`{}; `swimbot effects` lists them, or give an effects file FILE.toml[#NAME]",
            crate::data::limits::echo(text),
            crate::effects::expr::suggest(text, known.iter().copied())
        ))
    })?;
    Ok(Definition::of_catalogue(effect))
}

pub fn run_add(a: AddArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let mut s = open(study, inputs)?;
    let def = definition(&a.effect, inputs)?;
    let spinner = crate::progress::spinner(&format!("calibrating {}", def.name));
    let r = s.add(
        def,
        &AddOptions {
            refit_all: a.refit_all,
            force: a.force,
            diagnose: true,
        },
    );
    spinner.finish_and_clear();
    let step = r?.clone();
    let n = s.steps().len();
    say_plain!("added step {n} to {}:", s.path().display());
    print_step(n, &step);
    if let Some(d) = &step.diagnosis_after {
        println!(
            "{}",
            super::screen::study::diagnosis("diagnose now", d, a.verbose, super::screen::width())
        );
    }
    Ok(())
}

pub fn run_undo(_a: UndoArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let mut s = open(study, inputs)?;
    let n = s.steps().len();
    let gone = s.undo()?;
    say_plain!(
        "removed step {n} ({}) from {}; the model is back to MARE {}",
        gone.effect.name,
        s.path().display(),
        pct(s.current().stats.mare)
    );
    Ok(())
}

pub fn run_steps(a: StepsArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    let s = open(study, inputs)?;
    if let Some(other) = &a.data {
        let data = crate::data::load_recorded(other, inputs)?;
        let app = s.apply_to(&data)?;
        let format = match a.format {
            StepsFormat::Json => TableJsonCsv::Json,
            StepsFormat::Csv => TableJsonCsv::Csv,
            StepsFormat::Table => TableJsonCsv::Table,
            StepsFormat::Latex | StepsFormat::Markdown => {
                return Err(CliError::input(
                    "steps --data prints table, json or csv; the paper's table (latex, markdown) is of the study's own data",
                ))
            }
        };
        return print_application(&s, &app, format, inputs);
    }
    match a.format {
        StepsFormat::Json => print_json(s.file(), inputs),
        StepsFormat::Csv => print_csv(&rows(&s), inputs)?,
        StepsFormat::Table => print_table(&s, a.verbose),
        // The bundle's `tables/steps.*` then `tables/laws.*`, one renderer.
        StepsFormat::Latex | StepsFormat::Markdown => {
            let files = crate::report::steps_table::bundle_files(&s);
            let ext = match a.format {
                StepsFormat::Latex => ".tex",
                _ => ".md",
            };
            let texts: Vec<&str> = files
                .iter()
                .filter(|f| f.file.ends_with(ext))
                .map(|f| f.text.as_str())
                .collect();
            print!("{}", texts.join("\n"));
        }
    }
    Ok(())
}

fn pct(v: f64) -> String {
    format!("{:.2} %", 100.0 * v)
}

/// One row of `steps --format csv`: a step's statistics before and after,
/// each number its own column.
#[derive(serde::Serialize)]
struct StepRow {
    step: usize,
    effect: String,
    refit: String,
    mare_before: f64,
    mare_after: f64,
    cv_mare_after: f64,
    chi2_before: f64,
    chi2_after: f64,
    chi2_reduced_after: Option<f64>,
    noise_floor_chi2_after: Option<f64>,
    at_noise_floor: bool,
    free_params: usize,
}

fn rows(s: &Study) -> Vec<StepRow> {
    let start = &s.file().start.stats;
    let mut out = vec![StepRow {
        step: 0,
        effect: format!("(base: {})", s.file().model.preset),
        refit: String::new(),
        mare_before: start.mare,
        mare_after: start.mare,
        cv_mare_after: start.cv_mare,
        chi2_before: start.chi2,
        chi2_after: start.chi2,
        chi2_reduced_after: start.chi2_reduced,
        noise_floor_chi2_after: start.noise_floor_chi2,
        at_noise_floor: start.at_noise_floor,
        free_params: start.free_params,
    }];
    out.extend(s.steps().iter().enumerate().map(|(i, st)| StepRow {
        step: i + 1,
        effect: st.effect.name.clone(),
        refit: st.refit.clone(),
        mare_before: st.before.mare,
        mare_after: st.after.stats.mare,
        cv_mare_after: st.after.stats.cv_mare,
        chi2_before: st.before.chi2,
        chi2_after: st.after.stats.chi2,
        chi2_reduced_after: st.after.stats.chi2_reduced,
        noise_floor_chi2_after: st.after.stats.noise_floor_chi2,
        at_noise_floor: st.after.stats.at_noise_floor,
        free_params: st.after.stats.free_params,
    }));
    out
}

fn stats_line(label: &str, s: &Snapshot) -> String {
    let st = &s.stats;
    format!(
        "  {:<24} MARE {:>8}  CV MARE {:>8}  χ² {:>9}  χ²/ν {:>7}  floor {:>6}{}",
        label,
        pct(st.mare),
        pct(st.cv_mare),
        fmt_sig(st.chi2, 4),
        opt(st.chi2_reduced, 3),
        opt(st.noise_floor_chi2, 3),
        if st.at_noise_floor {
            "  at the noise floor"
        } else {
            ""
        }
    )
}

fn print_table(s: &Study, verbose: bool) {
    let f = s.file();
    say_plain!(
        "data: {} ({}; SHA-256 {}…, {} cases, {} quantities); base: {}; likelihood: {}",
        f.dataset.path.display(),
        f.dataset.name,
        &f.dataset.sha256[..12],
        s.dataset().cases.len(),
        f.start.stats.n,
        f.model.preset,
        f.model.likelihood
    );
    if let Some(d) = &f.first_diagnosis {
        let mut d = d.clone();
        if !s.steps().is_empty() {
            d.proposals.clear();
        }
        println!(
            "{}",
            super::screen::study::diagnosis("first diagnosis", &d, verbose, super::screen::width())
        );
    }
    say!(
        "{}",
        stats_line(&format!("0. base ({})", f.model.preset), &f.start)
    );
    for (i, st) in s.steps().iter().enumerate() {
        say!(
            "{}   (MARE {} -> {})",
            stats_line(&format!("{}. + {}", i + 1, st.effect.name), &st.after),
            pct(st.before.mare),
            pct(st.after.stats.mare)
        );
        for p in crate::report::steps_table::fitted(&st.params) {
            say!("     {}", crate::report::steps_table::param(&p));
        }
    }
    match s.last_diagnosis() {
        Some(_) if s.steps().is_empty() => {}
        Some(d) => {
            println!(
                "{}",
                super::screen::study::diagnosis("diagnose now", d, verbose, super::screen::width())
            );
        }
        None => say!("diagnose now: not run"),
    }
}

fn print_step(n: usize, st: &StepRecord) {
    say!(
        "  {n}. + {} ({}): {}",
        st.effect.name,
        st.effect.kind,
        st.effect.statement
    );
    for f in &st.effect.formula {
        say!("     {f}");
    }
    if let Some(p) = &st.proposed_by {
        say!("     proposed by {p}");
    }
    for p in st.params.iter().chain(&st.refitted) {
        // A fitted one as `diagnose`, the page and the tables spell it
        // (value ± u, and which 95 % interval); the others by value.
        let said = if p.status == "fitted" && p.standard_uncertainty.is_some() {
            crate::report::steps_table::param(&p.report())
        } else {
            let unit = if p.unit.is_empty() || p.unit == "1" {
                String::new()
            } else {
                format!(" {}", p.unit)
            };
            format!("{} = {}{unit}", p.name, fmt_sig(p.value, 4))
        };
        say!(
            "     {}.{said}  [{}]{}",
            p.effect,
            p.status,
            p.reason
                .as_deref()
                .map(|r| format!(": {r}"))
                .unwrap_or_default()
        );
    }
    for note in &st.notes {
        say!("     {note}");
    }
    say!(
        "     MARE {} -> {}, CV MARE {}, chi-square {} -> {}{}",
        pct(st.before.mare),
        pct(st.after.stats.mare),
        pct(st.after.stats.cv_mare),
        fmt_sig(st.before.chi2, 4),
        fmt_sig(st.after.stats.chi2, 4),
        if st.forced {
            " (recorded with --force although the error rose)"
        } else {
            ""
        }
    );
}

/// `steps --data`: one row per step, the error on the other data.
#[derive(serde::Serialize)]
struct AppliedRow {
    step: usize,
    effect: String,
    mare: f64,
    chi2: f64,
    chi2_reduced: Option<f64>,
    mare_on_study_data: f64,
}

fn print_application(
    s: &Study,
    app: &Application,
    format: TableJsonCsv,
    inputs: &Inputs,
) -> Result<(), CliError> {
    let mut rows = vec![AppliedRow {
        step: 0,
        effect: format!("(base: {})", s.file().model.preset),
        mare: app.start.stats.mare,
        chi2: app.start.stats.chi2,
        chi2_reduced: app.start.stats.chi2_reduced,
        mare_on_study_data: s.file().start.stats.mare,
    }];
    for (i, (a, st)) in app.steps.iter().zip(s.steps()).enumerate() {
        rows.push(AppliedRow {
            step: i + 1,
            effect: a.effect.clone(),
            mare: a.after.stats.mare,
            chi2: a.after.stats.chi2,
            chi2_reduced: a.after.stats.chi2_reduced,
            mare_on_study_data: st.after.stats.mare,
        });
    }
    match format {
        TableJsonCsv::Json => print_json(app, inputs),
        TableJsonCsv::Csv => print_csv(&rows, inputs)?,
        TableJsonCsv::Table => {
            println!(
                "the study {} (calibrated on {}) applied to {}, every parameter held:",
                s.path().display(),
                s.file().dataset.name,
                app.dataset
            );
            println!(
                "  {:<34} {:>12} {:>12} {:>10}",
                "step", "MARE here", "MARE study", "chi2_red"
            );
            for r in &rows {
                println!(
                    "  {:<34} {:>12} {:>12} {:>10}",
                    format!("{}. {}", r.step, r.effect),
                    pct(r.mare),
                    pct(r.mare_on_study_data),
                    opt(r.chi2_reduced, 3)
                );
            }
        }
    }
    Ok(())
}

/// Inside a study, a command given no `--data` and no model flags works on
/// the study's data and current model: the flags are filled in from the
/// study (its preset, then each step as `NAME:k=v` at full precision).
/// Returns whether a study was used. With flags given, the study is left
/// alone and a note says so.
pub fn fill_from_study(
    study: &Option<PathBuf>,
    data: &mut DataArgs,
    model: &mut ModelArgs,
    inputs: &Inputs,
) -> Result<bool, CliError> {
    let Some(s) = active_study(study, data, model, inputs)? else {
        return Ok(false);
    };
    let m = s.model()?;
    model.effect_files.known = s.catalogue()?;
    let first = m.effects.len() - s.steps().len();
    data.data = Some(s.dataset_path());
    if !s.file().dataset.sheets.is_empty() {
        data.joined = Some(s.dataset().clone());
    }
    model.preset = Some(s.file().model.preset.clone());
    model.effects = m.effects[first..]
        .iter()
        .map(crate::workbench::discovery::write::exact_spec)
        .collect();
    let sheets = s.file().dataset.sheets.len();
    eprintln!(
        "note: the study {}: {}{} with {} step(s)",
        s.path().display(),
        s.dataset_path().display(),
        match sheets {
            0 => String::new(),
            n => format!(
                " and {n} joined run sheet(s), {} cases",
                s.dataset().cases.len()
            ),
        },
        s.steps().len()
    );
    Ok(true)
}

/// The study a command works in: one is found (`--study FILE`, or
/// [`DEFAULT_FILE`] here) and the command has no `--data` or model flag.
/// With such flags, `--study` is refused as contradictory and a study
/// found in the folder is left alone, with a note. The study's files are
/// recorded in `inputs`.
pub fn active_study(
    study: &Option<PathBuf>,
    data: &DataArgs,
    model: &ModelArgs,
    inputs: &Inputs,
) -> Result<Option<Study>, CliError> {
    let Some(path) = locate(study) else {
        return Ok(None);
    };
    let flags = data.data.is_some()
        || model.preset.is_some()
        || !model.effects.is_empty()
        || !model.effect_files.files.is_empty();
    if flags {
        if study.is_some() {
            return Err(CliError::input(format!(
                "--study {} and --data/--preset/--effect/--effect-file: give one or the other",
                path.display()
            )));
        }
        eprintln!(
            "note: model or data flags given: the study {} is not used",
            path.display()
        );
        return Ok(None);
    }
    let s = Study::open(&path)?;
    inputs.record_all(s.inputs());
    Ok(Some(s))
}
