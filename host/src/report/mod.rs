//! The static HTML report: one self-contained page that tells the story of
//! the model against the measurements ([`story`]), its figures as inline
//! SVG, and beside it every figure and table as its own file: the page
//! is built with its artefacts as data (`page`), which the bundle writes
//! (`bundle`). The report renders what the workbench decided (the
//! user's path, [`crate::workbench::path`], and the diagnosis): it fits
//! nothing and searches nothing. It does evaluate models the workbench has
//! already fitted: their comparisons with the data (`remains`, `physics`
//! with the input bands, `physics_misses`) and their curves through the
//! Fig. 4 analogue (`curve`, drawn by `figure4` on both pages).

mod bundle;
pub use bundle::Guard;
mod correlated;
mod curve;
mod fails;
mod figure4;
#[cfg(test)]
mod figure_checks;
mod html;
mod intro;
mod page;
mod paper;
mod parity;
mod path;
mod path_chart;
mod physics;
mod physics_misses;
mod remains;
mod residuals;
pub mod steps_table;
pub mod story;
mod study_answer;
mod study_charts;
mod study_page;
mod study_params;
mod tex_math;
mod wording;
mod yours;

pub use crate::format::fmt_sig;
pub use story::{StoryInput, ZeroParam};
// The page's figures of one comparison, for the Python package's HTML.
pub use page::Artefact;
pub use parity::parity;

use crate::provenance::Inputs;
pub use bundle::BundleError;
pub use residuals::residual_plots;

/// Refuse `dir` before any work when another command's page is in it.
pub fn check_bundle_dir(dir: &std::path::Path, command: &str) -> Result<(), BundleError> {
    bundle::check_dir(dir, command)
}

/// Write the story page from `input` into `dir`, with its bundle (every
/// figure as SVG, every table as CSV and JSON, `manifest.json`), each
/// naming the files in `inputs` as its own.
pub fn write_story(
    dir: &std::path::Path,
    input: &StoryInput,
    guard: bundle::Guard,
    inputs: &Inputs,
) -> Result<std::path::PathBuf, BundleError> {
    let page = story::page(input)?;
    bundle::write(dir, input.command, &page, guard, inputs)
}

/// Write the story page for the model at the end of `path` on `data`
/// (with the path section when a diagnosis is given), without the
/// zero-parameter model's section (its first run takes tens of seconds) or
/// the audit: what `compare` writes.
pub fn write_report(
    dir: &std::path::Path,
    path: &crate::workbench::path::Path,
    data: &crate::data::Dataset,
    diagnosis: Option<&crate::workbench::diagnose::Diagnosis>,
    guard: bundle::Guard,
    inputs: &Inputs,
) -> Result<std::path::PathBuf, BundleError> {
    write_story(
        dir,
        &StoryInput {
            data,
            start: &path.last().model,
            path,
            command: "compare",
            diagnosis,
            zero_param: ZeroParam::Skipped(
                "the best model without a fitted parameter (`swimbot report` adds it)".into(),
            ),
            audit: None,
        },
        guard,
        inputs,
    )
}

/// Write the page of a study into `dir` with its bundle: a renderer of
/// the study file, computing nothing (`study_page`).
pub fn write_study(
    dir: &std::path::Path,
    study: &crate::study::Study,
    guard: bundle::Guard,
    inputs: &Inputs,
) -> Result<std::path::PathBuf, BundleError> {
    let mut page = study_page::page(study);
    page.artefacts.extend(steps_table::bundle_files(study));
    bundle::write(dir, "report", &page, guard, inputs)
}
