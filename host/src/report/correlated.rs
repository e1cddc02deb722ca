//! The chi-square with the inputs' covariance and the shared inputs' pulls
//! on the page, in the words `compare` prints
//! ([`crate::workbench::input_covariance`]).

use super::html::{html, omega_b, table, Markup};
use super::page::Part;
use crate::format::fmt_sig;
use crate::workbench::compare::Comparison;

/// `text` with each `Omega_b` written as Ω<sub>b</sub>.
fn with_omega_b(text: &str) -> Markup {
    html! {
        @for (i, part) in text.split("Omega_b").enumerate() {
            @if i > 0 { (omega_b()) }
            (part)
        }
    }
}

/// The statistic in `compare`'s words, the independent one labelled, or
/// why there is none.
pub fn statistic(cmp: &Comparison) -> Markup {
    match &cmp.chi2_correlated {
        Some(x) => html! {
            (x.describe()) "; the same residuals: chi-square "
            (with_omega_b(&x.describe_independent()))
        },
        None => html! {
            "the chi-square with the inputs' covariance is not computed (a quantity with \
            neither a measured nor an input uncertainty)"
        },
    }
}

/// What the data would want of the inputs that cases share: a sentence on
/// the largest pull and a table of those the data pin (nothing when none).
pub fn pulls(cmp: &Comparison) -> Part {
    let Some(x) = &cmp.chi2_correlated else {
        return Part::new();
    };
    let shown: Vec<_> = x.pulls.iter().filter(|p| p.informative()).collect();
    let Some(first) = shown.first() else {
        return Part::new();
    };
    let rows: Vec<Vec<Markup>> = shown
        .iter()
        .map(|p| {
            vec![
                html! { code { (p.input) } },
                html! { (fmt_sig(p.standard, 2)) },
                html! { (fmt_sig(p.shift, 2)) },
                html! { (fmt_sig(p.pull_sigmas, 2)) " ± " (fmt_sig(p.pull_sd_sigmas, 2)) },
                html! { (p.cases) },
            ]
        })
        .collect();
    Part::from(html! {
        p id="physics-pulls" {
            "What the data would want of the inputs the cases share, each alone with the \
            others at their declared uncertainty (a generalised-least-squares estimate; \
            reported, never applied to the prediction): most of all " (first.describe())
            ". The table lists every shared input the data pin to within "
            (crate::workbench::input_covariance::SHOWN_PULL_SD) " declared standard \
            uncertainties. None of these shifts is a measurement of the robot: each says in \
            which direction of the data the model misses."
        }
    })
    .with(table(
        &[
            "<input",
            "declared u",
            "wanted shift",
            "in declared u",
            "cases sharing it",
        ],
        &rows,
    ))
}
