//! The section on what remains and what is suspected: `diagnose`'s verdict,
//! the corrections it located (with their fitted laws and CIs), the errors
//! the best of them still leaves, and the audit's flags on the data.

use super::html::{escape, table};
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
fn leftovers(data: &Dataset, d: &Diagnosis) -> Option<String> {
    let l = d.verdict.located.first()?;
    let cmp = compare(&l.model, data, 0).ok()?;
    let errs = super::fails::quantity_errors(&cmp.cases);
    let top: Vec<String> = errs
        .iter()
        .take(3)
        .map(|(id, q, e, s)| {
            format!(
                "{}'s {q} {} ({} standard errors)",
                escape(id),
                signed_pct(Some(*e)),
                s.map_or("-".into(), |s| fmt_sig(s, 3))
            )
        })
        .collect();
    Some(format!(
        "<p>What the best located model still misses most: {}.</p>",
        top.join("; ")
    ))
}

pub fn section(data: &Dataset, d: Option<&Diagnosis>, audit: Option<&Audit>) -> String {
    let mut h = String::new();
    match d {
        None => h.push_str(
            "<p>No diagnosis on this page (<code>swimbot compare</code>); <code>swimbot \
             report</code> or <code>swimbot diagnose</code> give the verdict.</p>",
        ),
        Some(d) => {
            h.push_str(&format!(
                "<p class=\"verdict\"><b>Verdict: {}.</b> {}</p>",
                kind(d.verdict.kind),
                escape(
                    d.verdict
                        .note
                        .strip_prefix(&format!("{}: ", kind(d.verdict.kind)))
                        .unwrap_or(&d.verdict.note)
                )
            ));
            if !d.verdict.located.is_empty() {
                let rows: Vec<Vec<String>> = d
                    .verdict
                    .located
                    .iter()
                    .map(|l| {
                        vec![
                            format!("<code>{} = {}</code>", escape(l.place), escape(&l.formula)),
                            escape(&l.interpretation),
                            escape(&params(l)),
                            pct(l.score.mare),
                            pct(l.score.cv_mare),
                            stat(l.score.chi2_reduced),
                            l.explained_fraction.map_or("-".into(), pct),
                        ]
                    })
                    .collect();
                h.push_str("<h3>Located corrections</h3>");
                h.push_str(&table(
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
            if let Some(g) = d.verdict.suggestion.as_ref().filter(|g| g.same_model) {
                h.push_str(&format!(
                    "<p>No measurement of U or Omega_b separates the leading explanations: they are the same model (their predictions agree to {:.0e} on every design the rig can run).</p>",
                    g.rel_difference
                ));
            } else if let Some(g) = &d.verdict.suggestion {
                h.push_str(&format!(
                    "<p>To tell the leading explanations apart, measure {} with {}: their {} \
                     differ by {} there, about {} standard errors.</p>",
                    escape(&g.base_case),
                    escape(&g.change),
                    escape(g.quantity),
                    pct(g.rel_difference),
                    fmt_sig(g.in_sigma, 2)
                ));
            }
            if let Some(s) = leftovers(data, d) {
                h.push_str(&s);
            }
        }
    }
    match audit {
        None => h.push_str(
            "<p class=\"note\">No audit of the data on this page; <code>swimbot audit</code> \
             runs it.</p>",
        ),
        Some(a) if a.flags.is_empty() => {
            h.push_str("<h3>The data's audit</h3><p>No flag: the recorded geometry is consistent, no measured ratio is out of the model family's range, no single case decides the verdict.</p>")
        }
        Some(a) => {
            h.push_str("<h3>The data's audit: what is suspected</h3><ul>");
            for f in &a.flags {
                h.push_str(&format!(
                    "<li><b>{}</b> ({}, {}): {}</li>",
                    escape(&f.case),
                    escape(&f.kind),
                    match f.severity {
                        Severity::Warning => "warning",
                        Severity::Error => "error",
                    },
                    escape(&f.detail)
                ));
            }
            h.push_str("</ul>");
        }
    }
    h
}
