//! How the verdict of `diagnose` is worded: numbers as every command and
//! the page print them, and the sentences of each kind. What is decided is
//! in [`super::verdict`] and [`super::stagewise`].

use super::design::Suggestion;
use super::diagnosis::Baseline;
use super::stagewise::{Level, Path};

/// A reduced chi-square in a note: 3 significant figures (`crate::format`).
pub fn fmt(x: Option<f64>) -> String {
    x.map(|v| crate::format::fmt_sig(v, 3))
        .unwrap_or_else(|| "n/a".into())
}

/// A share of the excess chi-square: two decimals just below 100 %.
pub fn frac(x: Option<f64>) -> String {
    x.map(|v| {
        if v > 0.99 && v < 1.0 {
            format!("{:.2} %", 100.0 * v)
        } else {
            format!("{:.0} %", 100.0 * v)
        }
    })
    .unwrap_or_else(|| "n/a".into())
}

/// "; to tell them apart, measure ..." for a discriminating case.
pub fn hint(g: &Suggestion) -> String {
    format!(
        "; to tell them apart, measure {} with {} ({} differs by {:.0} %, about {:.0} standard errors)",
        g.base_case, g.change, g.quantity, 100.0 * g.rel_difference, g.in_sigma
    )
}

/// The note of a stagewise verdict: every step in order with what it
/// removes, then the errors before and after.
pub fn stagewise_note(base: &Baseline, path: &Path, last: &Level) -> String {
    let steps: Vec<String> = path
        .steps
        .iter()
        .enumerate()
        .map(|(i, (step, _, located))| {
            let what = match located {
                Some(l) => format!("located {} ({})", step.name, l.interpretation),
                None => format!("catalogue effect {}", step.name),
            };
            let of = if i == 0 {
                "of the excess chi-square".to_string()
            } else {
                format!("of what step {i} leaves")
            };
            format!(
                "{}. {}{what}: removes {} {of}",
                i + 1,
                if i == 0 { "" } else { "on top of it, " },
                frac(step.explained_fraction)
            )
        })
        .collect();
    let head = if last.at_floor {
        format!("{} steps reach the noise floor", path.steps.len())
    } else {
        format!(
            "stagewise, {} steps lower the error but do not reach the noise floor",
            path.steps.len()
        )
    };
    format!(
        "{head}: {}. MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
        steps.join("; "),
        100.0 * base.mare,
        100.0 * last.mare,
        100.0 * last.cv_mare,
        fmt(base.chi2_reduced),
        fmt(last.chi2_reduced),
        fmt(base.noise_floor_chi2_reduced)
    )
}
