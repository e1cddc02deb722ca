//! The headline as the terminal prints it ([`super::headline`]): each
//! item a short wrapped paragraph, the numbers rounded as JCGM 100 sec.
//! 7.2.6 asks ([`super::rounding`]).

use super::headline::{Headline, HeadlineStep};
use super::rounding::{percent, value_pm};
use super::symbols::symbols;
use super::wrap;
use crate::format::fmt_sig;
use crate::workbench::fit::report::ParamReport;

/// The screen, lines at most `width` columns.
pub fn render(h: &Headline, width: usize) -> String {
    let mut out = Vec::new();
    out.push(wrap(&format!("verdict: {} ({})", h.kind, summary(h)), width, "", "  "));
    for (i, s) in h.steps.iter().enumerate() {
        out.extend(step(i, s, width));
    }
    out.push(error_lines(h, width));
    out.push(wrap(&format!("how sure: {}", how_sure(h)), width, "", "  "));
    out.extend(rivals(h, width));
    if let Some(e) = &h.next_experiment {
        out.push(wrap(
            &format!("next experiment: {}", symbols(e)),
            width,
            "",
            "  ",
        ));
    }
    out.push(wrap(&format!("next: {}", h.next_command), width, "", "  "));
    out.push(wrap(
        "(the full tables: --verbose; every number: --format json)",
        width,
        "",
        "",
    ));
    out.join("\n")
}

fn summary(h: &Headline) -> String {
    let n = h.steps.len();
    match h.kind {
        "none-needed" => "the model is at the noise floor: nothing is missing".into(),
        "identified" => "a catalogue effect explains what the model misses".into(),
        "located" => "a law beyond the catalogue explains what the model misses".into(),
        "indistinguishable" => "the data cannot tell the findings below apart".into(),
        _ if n == 0 => "nothing found lowers the error enough".into(),
        _ if h.at_noise_floor => format!("{n} steps reach the noise floor"),
        _ => format!(
            "{n} step{} lower the error but do not reach the noise floor",
            if n == 1 { "" } else { "s" }
        ),
    }
}

fn step(i: usize, s: &HeadlineStep, width: usize) -> Vec<String> {
    let explains = s
        .explains
        .map(|f| format!(", removes {:.0} % of the excess χ² left", 100.0 * f))
        .unwrap_or_default();
    let head = format!("{}. {} [{}{explains}]", i + 1, symbols(&s.law), s.kind);
    let mut lines = vec![wrap(&head, width, "  ", "     ")];
    if let Some(v) = &s.variable {
        lines.push(wrap(&symbols(v), width, "     ", "     "));
    }
    if !s.reading.is_empty() {
        lines.push(wrap(&symbols(&s.reading), width, "     ", "     "));
    }
    if !s.params.is_empty() {
        let ps: Vec<String> = s.params.iter().map(param).collect();
        lines.push(wrap(&ps.join("; "), width, "     ", "       "));
    }
    lines
}

/// `name = value ± u unit (rel %, 95 % lo .. hi)`, or the value alone.
pub fn param(p: &ParamReport) -> String {
    let unit = match p.unit.as_str() {
        "" | "1" => String::new(),
        u => format!(" {u}"),
    };
    let bound = if p.at_bound { ", at its bound" } else { "" };
    let Some(u) = p.standard_uncertainty else {
        return format!(
            "{} = {}{unit} (no interval of its own{bound})",
            p.name,
            value_pm(p.value, None)
        );
    };
    let rel = p
        .relative_uncertainty_percent
        .map(|r| format!("{}, ", percent(r)))
        .unwrap_or_default();
    let ci = match (p.ci95_low, p.ci95_high) {
        (Some(lo), Some(hi)) => format!(
            "95 % {} .. {}",
            value_pm(lo, Some(u)).split(" ±").next().unwrap_or(""),
            value_pm(hi, Some(u)).split(" ±").next().unwrap_or("")
        ),
        _ => String::new(),
    };
    format!(
        "{} = {}{unit} ({rel}{ci}{bound})",
        p.name,
        value_pm(p.value, Some(u))
    )
}

fn error_lines(h: &Headline, width: usize) -> String {
    let mare: Vec<String> = h.mare.iter().map(|m| format!("{:.2} %", 100.0 * m)).collect();
    let chi: Vec<String> = h
        .chi2_reduced
        .iter()
        .map(|c| c.map_or("-".into(), |c| fmt_sig(c, 3)))
        .collect();
    let floor = h
        .noise_floor_chi2_reduced
        .map_or("-".into(), |f| fmt_sig(f, 3));
    [
        wrap(&format!("error: MARE {}", mare.join(" -> ")), width, "", "  "),
        wrap(
            &format!(
                "       reduced χ² {} (noise floor {floor})",
                chi.join(" -> ")
            ),
            width,
            "",
            "         ",
        ),
    ]
    .join("\n")
}

fn how_sure(h: &Headline) -> String {
    let sets = match h.rivals.len() {
        0 => "no rival set within the margin".to_string(),
        n => format!(
            "the found set has Akaike weight {:.2} among {n} sets",
            h.rivals[0].akaike_weight
        ),
    };
    if h.stability.is_empty() {
        return format!("{sets}; stability under resampling was not measured");
    }
    let terms: Vec<String> = h
        .stability
        .iter()
        .map(|t| {
            format!(
                "{} chosen in {} of {} {} resamples ({:.0} %)",
                symbols(&t.term),
                t.selected,
                t.resamples,
                t.method,
                100.0 * t.fraction
            )
        })
        .collect();
    format!("{sets}; {}", terms.join("; "))
}

fn rivals(h: &Headline, width: usize) -> Vec<String> {
    if h.rivals.len() < 2 {
        return Vec::new();
    }
    let mut lines = vec![format!("  {:>3} {:>8} {:>7} {:>5}  set", "", "Δkey", "weight", "floor")];
    for (i, r) in h.rivals.iter().enumerate() {
        let first = format!(
            "  {:>3} {:>8} {:>7.3} {:>5}  ",
            format!("{}.", i + 1),
            format!("{:+.1}", r.key_difference),
            r.akaike_weight,
            if r.at_noise_floor { "yes" } else { "no" }
        );
        let pad = " ".repeat(first.chars().count());
        lines.push(wrap(&symbols(&r.members.join(" + ")), width, &first, &pad));
    }
    lines
}
