//! The section on what remains and what is suspected: `diagnose`'s verdict,
//! the corrections it located (with their fitted laws and CIs), the errors
//! the best of them still leaves, and the audit's flags on the data.

use super::html::{html, rich, table, Markup};
use super::page::Part;
use super::wording::{pct, signed_pct, stat};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::audit::{Audit, Severity};
use crate::workbench::compare::compare;
use crate::workbench::diagnose::{Diagnosis, VerdictKind};

fn kind(k: VerdictKind) -> &'static str {
    match k {
        VerdictKind::NoneNeeded => "none needed",
        VerdictKind::Identified => "identified",
        VerdictKind::Located => "located",
        VerdictKind::Indistinguishable => "indistinguishable",
        VerdictKind::Unexplained => "unexplained",
    }
}

fn params(l: &crate::workbench::discovery::Located) -> String {
    l.params
        .iter()
        .map(|p| match p.ci95 {
            Some(ci) => format!("{} = {}", p.name, super::wording::value_unc(p.value, ci)),
            None => format!("{} = {} (not identifiable)", p.name, fmt_sig(p.value, 3)),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The largest errors the best located model still leaves.
fn leftovers(data: &Dataset, d: &Diagnosis) -> Option<Markup> {
    let l = d.verdict.located.first()?;
    let cmp = compare(&l.model, data, 0).ok()?;
    let errs = super::fails::quantity_errors(&cmp.cases);
    Some(html! {
        p {
            "What the best located model still misses most: "
            @for (i, (id, q, e, s)) in errs.iter().take(3).enumerate() {
                @if i > 0 { "; " }
                (id) "'s " (rich(q)) " " (signed_pct(Some(*e))) " ("
                (s.map_or("-".into(), |s| fmt_sig(s, 3))) " standard errors)"
            }
            "."
        }
    })
}

fn diagnosis(data: &Dataset, d: Option<&Diagnosis>) -> Part {
    let Some(d) = d else {
        return Part::from(html! {
            p {
                "No diagnosis on this page (" code { "swimbot compare" } "); "
                code { "swimbot report" } " or " code { "swimbot diagnose" }
                " give the verdict."
            }
        });
    };
    let word = kind(d.verdict.kind);
    let note = d
        .verdict
        .note
        .strip_prefix(&format!("{word}: "))
        .unwrap_or(&d.verdict.note);
    let rows: Vec<Vec<Markup>> = d
        .verdict
        .located
        .iter()
        .map(|l| {
            vec![
                html! { code { (l.place) " = " (l.formula) } },
                html! { (l.interpretation) },
                html! { (params(l)) },
                html! { (pct(l.score.mare)) },
                html! { (pct(l.score.cv_mare)) },
                html! { (stat(l.score.chi2_reduced)) },
                html! { (l.explained_fraction.map_or("-".into(), pct)) },
            ]
        })
        .collect();
    let mut out = Part::from(html! {
        p.verdict { b { "Verdict: " (word) "." } " " (note) }
    });
    if !rows.is_empty() {
        out.push(html! { h3 { "Located corrections" } });
        out.push(table(
            &[
                "<correction",
                "<what it means",
                "<fitted (95 % CI of the fit)",
                "MARE",
                "cross-validated MARE",
                "reduced χ²",
                "share of the excess χ² removed",
            ],
            &rows,
        ));
    }
    out.with(html! {
        @if let Some(g) = d.verdict.suggestion.as_ref().filter(|g| g.same_model) {
            p {
                "No measurement of U or Omega_b separates the leading explanations: they are \
                the same model (their predictions agree to "
                (format!("{:.0e}", g.rel_difference)) " on every design the rig can run)."
            }
        } @else if let Some(g) = &d.verdict.suggestion {
            p {
                "To tell the leading explanations apart, measure " (g.base_case) " with "
                (g.change) ": their " (g.quantity) " differ by " (pct(g.rel_difference))
                " there, about " (fmt_sig(g.in_sigma, 2)) " standard errors."
            }
        }
        @if let Some(s) = leftovers(data, d) {
            (s)
        }
    })
}

fn audit_flags(audit: Option<&Audit>) -> Markup {
    match audit {
        None => html! {
            p.note {
                "No audit of the data on this page; " code { "swimbot audit" } " runs it."
            }
        },
        Some(a) if a.flags.is_empty() => html! {
            h3 { "The data's audit" }
            p {
                "No flag: the recorded geometry is consistent, no measured ratio is out of the \
                model family's range, no single case decides the verdict."
            }
        },
        Some(a) => html! {
            h3 { "The data's audit: what is suspected" }
            ul {
                @for f in &a.flags {
                    li {
                        b { (f.case) } " (" (f.kind) ", "
                        (match f.severity {
                            Severity::Warning => "warning",
                            Severity::Error => "error",
                        })
                        "): " (f.detail)
                    }
                }
            }
        },
    }
}

pub fn section(data: &Dataset, d: Option<&Diagnosis>, audit: Option<&Audit>) -> Part {
    diagnosis(data, d).with(audit_flags(audit))
}
