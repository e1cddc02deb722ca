//! Text formatting of results and the static HTML report.

mod figure4;
mod html;
mod parity;
mod path;
pub mod plots;
mod residuals;

pub use crate::format::fmt_sig;

/// Write the HTML report for `model` on `data` into `dir` (with the
/// diagnosis section when given); returns the page's path.
pub fn write_report(
    dir: &std::path::Path,
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    diagnosis: Option<&crate::workbench::diagnose::Diagnosis>,
) -> Result<std::path::PathBuf, String> {
    let page = html::page(model, data, diagnosis).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let path = dir.join("index.html");
    // Temporary file, then rename: a failed write never leaves half a page.
    let tmp = dir.join(format!(".index.html.tmp-{}", std::process::id()));
    std::fs::write(&tmp, page)
        .and_then(|()| std::fs::rename(&tmp, &path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            e.to_string()
        })?;
    Ok(path)
}
