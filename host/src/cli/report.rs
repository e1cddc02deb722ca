//! `swimbot report`: the story page (the paper's model and Fig. 4, where it
//! fails, the path `diagnose` takes, the best zero-parameter model, what
//! remains), with progress on the console while it computes.

use super::model_args::{in_data, DataArgs, ModelArgs};
use super::CliError;
use crate::model::preset;
use crate::provenance::Inputs;
use crate::report::{write_story, StoryInput, ZeroParam};
use crate::workbench::audit::{audit, AuditSettings};
use crate::workbench::diagnose::{diagnose, DiagnoseSettings};
use crate::workbench::path::user_path;
use clap::Args;
use indicatif::ProgressBar;
use rayon::prelude::*;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ReportArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// The model options choose where `diagnose`'s path starts (default: plain RFT); the paper's
    /// two models and the zero-parameter model are always drawn.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Output directory: index.html, every figure as SVG, every table as CSV and JSON, and
    /// manifest.json; a directory another command wrote is refused.
    #[arg(short, long, default_value = super::output::DEFAULT_REPORT_DIR)]
    pub output: PathBuf,
    /// Skip the section on the best model without a fitted parameter (`--preset physics`): its first
    /// run solves every tail inside the tube (tens of seconds on 2 cores, then cached in
    /// $SWIMBOT_CACHE_DIR or the temporary directory); skip it for a report in about a second.
    #[arg(long)]
    pub no_physics: bool,
    /// Refuse the report when its estimated run time (the diagnosis timed on growing subsets of
    /// the cases and grown to all, the audit's estimate, the zero-parameter model's first solves
    /// at every geometry of its input bands) is longer [default: no limit; from 200 cases the estimate is made, and one over 10 s is
    /// announced on stderr].
    #[arg(long, value_name = "SECONDS")]
    pub max_seconds: Option<f64>,
}

fn spinner(message: &str) -> ProgressBar {
    crate::progress::spinner(message)
}

pub fn run(a: ReportArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    if let Some(s) = super::study::active_study(study, &a.data, &a.model, inputs)? {
        return run_study(&a, &s, inputs);
    }
    let data = a.data.load(inputs)?;
    let (model, catalogue) = a.model.model_and_catalogue(inputs)?;
    super::output::check_output_dir(&a.output, "report", inputs)?;
    crate::report::check_bundle_dir(&a.output, "report").map_err(CliError::input)?;
    let to_input = in_data(&a.data.data);
    // Every model on the page must predict every case: a bad case is the
    // input's fault (exit 2), found before the slow parts.
    for m in [&model, &preset("paper").expect("preset")] {
        for c in &data.cases {
            m.predict(c).map_err(&to_input)?;
        }
    }
    let budget = super::budget::parse_budget(a.max_seconds)?;
    if budget.is_some() || data.cases.len() >= super::budget::ESTIMATE_FROM_CASES {
        let est = estimate_seconds(&model, &data, &catalogue, !a.no_physics);
        let what = format!("the report of {} cases", data.cases.len());
        match est {
            Some(s) => super::budget::check(&what, s, budget)?,
            None => super::budget::unestimated(&what, budget),
        }
    }
    let s = spinner("diagnosing");
    let settings = DiagnoseSettings {
        progress: Some(crate::progress::to_message(&s)),
        catalogue,
        ..Default::default()
    };
    let d = diagnose(&model, &data, &settings).map_err(CliError::input)?;
    s.set_message("auditing the data");
    let audited = audit(&model, &data, &AuditSettings::default()).map_err(&to_input)?;
    s.finish_and_clear();
    let steps =
        user_path(&model, super::compare::preset_effects(&a.model), &data).map_err(&to_input)?;
    let physics = preset("physics").expect("preset");
    let zero_param = if a.no_physics {
        ZeroParam::Skipped(
            "the best model without a fitted parameter (--no-physics; run without it to add \
             --preset physics)"
                .into(),
        )
    } else {
        solve_physics(&physics, &data).map_err(&to_input)?;
        ZeroParam::Model {
            name: "zero-parameter model (physics preset)".into(),
            model: &physics,
        }
    };
    let path = write_story(
        &a.output,
        &StoryInput {
            data: &data,
            start: &model,
            path: &steps,
            command: "report",
            diagnosis: Some(&d),
            zero_param,
            audit: Some(&audited),
        },
        &|p| super::output::not_an_input(p, inputs),
        inputs,
    )
    .map_err(|e| CliError::input(format!("writing the report to {}: {e}", a.output.display())))?;
    println!("{}", path.display());
    eprintln!(
        "report: wrote {} (with every figure as SVG, every table as CSV and JSON, manifest.json)",
        path.display()
    );
    Ok(())
}

/// Predict every case with the zero-parameter model, in parallel, with a
/// progress bar: the first run solves each tail in the tube; the results
/// are cached, so the page's later predictions are immediate.
fn solve_physics(
    model: &crate::model::Model,
    data: &crate::data::Dataset,
) -> Result<(), crate::model::ModelError> {
    let bar = crate::progress::bar(
        data.cases.len() as u64,
        "cases",
        "zero-parameter model (tails in the tube; cached after the first run)",
    );
    let r = data.cases.par_iter().try_for_each(|c| {
        let p = model.predict(c).map(|_| ());
        bar.inc(1);
        p
    });
    bar.finish_and_clear();
    r
}

/// The report's run time: the diagnosis ([`super::diagnose::estimate_seconds`]),
/// the audit ([`super::audit::estimate_seconds`], its default family) and,
/// with the zero-parameter model, its solves in the tube: the page shows
/// that model with its input bands, so each case is solved at its own
/// geometry and at two more per uncertain input that moves the tail or the
/// body ([`super::audit::geometries_of`]: 13 for a paper case), each timed
/// as a first solve on two cases and spread over the cores (solves the
/// disk cache already holds are fast and so estimated fast). Counting one
/// solve per case announced 23 s for 300 cases that took 5 min 55 s.
/// `None` when the diagnosis cannot be timed.
fn estimate_seconds(
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    catalogue: &crate::effects::Catalogue,
    physics: bool,
) -> Option<f64> {
    let settings = DiagnoseSettings {
        catalogue: catalogue.clone(),
        ..Default::default()
    };
    let diagnosis = super::diagnose::estimate_seconds(model, data, &settings)?;
    let audit =
        super::audit::estimate_seconds(model, data, AuditSettings::default().family_samples);
    let zero = if physics {
        let m = preset("physics").expect("preset");
        let sample = data.cases.len().min(2);
        let (_, s) = super::budget::timed(|| {
            for c in &data.cases[..sample] {
                let _ = m.predict(c);
            }
        });
        let geometries: usize = data.cases.iter().map(super::audit::geometries_of).sum();
        s / sample.max(1) as f64 * geometries as f64 / rayon::current_num_threads() as f64
    } else {
        0.0
    };
    Some(diagnosis + audit + zero)
}

/// Inside a study: the study's page, rendered from the study file alone.
fn run_study(a: &ReportArgs, s: &crate::study::Study, inputs: &Inputs) -> Result<(), CliError> {
    super::output::check_output_dir(&a.output, "report", inputs)?;
    crate::report::check_bundle_dir(&a.output, "report").map_err(CliError::input)?;
    let guard = |p: &std::path::Path| super::output::not_an_input(p, inputs);
    let path = crate::report::write_study(&a.output, s, &guard, inputs).map_err(|e| {
        CliError::input(format!("writing the report to {}: {e}", a.output.display()))
    })?;
    println!("{}", path.display());
    eprintln!(
        "report: wrote {} from the study {} ({} step(s))",
        path.display(),
        s.path().display(),
        s.steps().len()
    );
    Ok(())
}
