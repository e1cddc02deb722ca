//! Text formatting of results and the static HTML report.

mod html;
pub mod plots;

/// `v` to `sig` significant digits, without exponent for everyday magnitudes.
pub fn fmt_sig(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{:.*e}", sig.saturating_sub(1), v);
    }
    let decimals = (sig as i32 - 1 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

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
