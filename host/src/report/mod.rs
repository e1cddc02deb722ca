//! The static HTML report: one self-contained page that tells the story of
//! the model against the measurements ([`story`]), its figures as inline
//! SVG.

mod curve;
mod fails;
mod figure4;
mod html;
mod intro;
mod paper;
mod parity;
mod path;
mod path_chart;
mod physics;
pub mod plots;
mod remains;
mod residuals;
pub mod story;
mod wording;

pub use crate::format::fmt_sig;
pub use story::{StoryInput, ZeroParam};

/// Write `page` as `dir/index.html` (temporary file, then rename: a failed
/// write never leaves half a page); returns the page's path.
fn write_page(dir: &std::path::Path, page: &str) -> Result<std::path::PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let path = dir.join("index.html");
    let tmp = dir.join(format!(".index.html.tmp-{}", std::process::id()));
    let page = crate::provenance::Provenance::capture().into_html(page);
    std::fs::write(&tmp, page)
        .and_then(|()| std::fs::rename(&tmp, &path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            e.to_string()
        })?;
    Ok(path)
}

/// Write the story page from `input` into `dir`.
pub fn write_story(
    dir: &std::path::Path,
    input: &StoryInput,
) -> Result<std::path::PathBuf, String> {
    let page = story::page(input).map_err(|e| e.to_string())?;
    write_page(dir, &page)
}

/// Write the story page for `model` on `data` (with the path section when
/// a diagnosis is given), without the zero-parameter model's section (its
/// first run takes tens of seconds) or the audit: what `compare` writes.
pub fn write_report(
    dir: &std::path::Path,
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    diagnosis: Option<&crate::workbench::diagnose::Diagnosis>,
) -> Result<std::path::PathBuf, String> {
    write_story(
        dir,
        &StoryInput {
            data,
            start: model,
            diagnosis,
            zero_param: ZeroParam::Skipped(
                "the best model without a fitted parameter (`swimbot report` adds it)".into(),
            ),
            audit: None,
        },
    )
}
