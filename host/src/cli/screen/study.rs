//! The study commands' screens (`init`, `add`, `steps`): a diagnosis as
//! its verdict and proposals, one short wrapped item each; the verdict's
//! whole note only with `--verbose` (it is kept in the study file).

use super::symbols::symbols;
use super::wrap;
use crate::study::DiagnosisRecord;

/// `label: KIND`, then each proposal with what it removes and the command
/// that adds it; with `verbose`, the note after.
pub fn diagnosis(label: &str, d: &DiagnosisRecord, verbose: bool, width: usize) -> String {
    let mut out = vec![wrap(&format!("{label}: {}", d.verdict), width, "", "  ")];
    for p in &d.proposals {
        let explains = p
            .explains
            .map(|f| format!(", removes {:.0}\u{a0}% of the excess χ²", 100.0 * f))
            .unwrap_or_default();
        let what = p.law.as_deref().unwrap_or(&p.name);
        let how: Vec<String> = p.add_commands().iter().map(|c| format!("`{c}`")).collect();
        out.push(wrap(
            &format!(
                "proposes {}{explains}: {}",
                symbols(what),
                how.join(", then ")
            ),
            width,
            "  ",
            "    ",
        ));
    }
    if verbose {
        out.push(wrap(&symbols(&d.note), width, "  ", "  "));
    } else if !d.note.is_empty() {
        out.push(wrap("(the verdict in full: --verbose)", width, "  ", "  "));
    }
    out.join("\n")
}

/// Any line of the study's tables, wrapped with a hanging indent under its
/// first word.
pub fn line(text: &str, width: usize) -> String {
    let indent: String = text.chars().take_while(|c| *c == ' ').collect();
    let rest = format!("{indent}    ");
    wrap(&symbols(text.trim_start()), width, &indent, &rest)
}

/// [`line`] without the paper's symbols, for lines that name files and
/// datasets: they must print as spelled (`lambda pi.csv` is no `λ π.csv`).
pub fn plain_line(text: &str, width: usize) -> String {
    let indent: String = text.chars().take_while(|c| *c == ' ').collect();
    let rest = format!("{indent}    ");
    wrap(text.trim_start(), width, &indent, &rest)
}
