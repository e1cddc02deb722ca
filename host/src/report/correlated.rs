//! The chi-square with the inputs' covariance and the shared inputs' pulls
//! on the page, in the words `compare` prints
//! ([`crate::workbench::input_covariance`]).

use super::html::{escape, table};
use crate::format::fmt_sig;
use crate::workbench::compare::Comparison;

/// The statistic in `compare`'s words, the independent one labelled, or
/// why there is none.
pub fn statistic(cmp: &Comparison) -> String {
    match &cmp.chi2_correlated {
        Some(x) => format!(
            "{}; the same residuals: chi-square {}",
            escape(&x.describe()),
            escape(&x.describe_independent()).replace("Omega_b", "Ω<sub>b</sub>")
        ),
        None => "the chi-square with the inputs' covariance is not computed (a quantity with \
                 neither a measured nor an input uncertainty)"
            .into(),
    }
}

/// What the data would want of the inputs that cases share: a sentence on
/// the largest pull and a table of those the data pin (nothing when none).
pub fn pulls(cmp: &Comparison) -> String {
    let Some(x) = &cmp.chi2_correlated else {
        return String::new();
    };
    let shown: Vec<_> = x.pulls.iter().filter(|p| p.informative()).collect();
    let Some(first) = shown.first() else {
        return String::new();
    };
    let rows: Vec<Vec<String>> = shown
        .iter()
        .map(|p| {
            vec![
                format!("<code>{}</code>", escape(&p.input)),
                fmt_sig(p.standard, 2),
                fmt_sig(p.shift, 2),
                format!(
                    "{} ± {}",
                    fmt_sig(p.pull_sigmas, 2),
                    fmt_sig(p.pull_sd_sigmas, 2)
                ),
                p.cases.to_string(),
            ]
        })
        .collect();
    format!(
        "<p id=\"physics-pulls\">What the data would want of the inputs the cases share, each \
         alone with the others at their declared uncertainty (a generalised-least-squares \
         estimate; reported, never applied to the prediction): most of all {}. The table lists \
         every shared input the data pin to within {} declared standard uncertainties. None of \
         these shifts is a measurement of the robot: each says in which direction of the data \
         the model misses.</p>{}",
        escape(&first.describe()),
        crate::workbench::input_covariance::SHOWN_PULL_SD,
        table(
            &[
                "<input",
                "declared u",
                "wanted shift",
                "in declared u",
                "cases sharing it"
            ],
            &rows
        )
    )
}
