//! The headline as the terminal prints it ([`super::headline`]): each
//! item a short wrapped paragraph, the numbers rounded as JCGM 100 sec.
//! 7.2.6 asks ([`super::rounding`]).

use super::headline::{Headline, HeadlineStep};
use super::symbols::symbols;
use super::wrap;
use crate::format::fmt_sig;
pub use crate::report::steps_table::param;

/// One item of the screen: its text and the indents of its first and
/// further lines.
pub struct Item {
    pub first: String,
    pub rest: String,
    pub text: String,
}

fn item(first: &str, rest: &str, text: String) -> Item {
    Item {
        first: first.into(),
        rest: rest.into(),
        text,
    }
}

/// The screen, lines at most `width` columns.
pub fn render(h: &Headline, width: usize) -> String {
    items(h)
        .iter()
        .map(|i| wrap(&i.text, width, &i.first, &i.rest))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The screen's items, in order, before wrapping.
pub fn items(h: &Headline) -> Vec<Item> {
    let mut out = vec![item(
        "",
        "  ",
        format!("verdict: {} ({})", h.kind, summary(h)),
    )];
    for (i, s) in h.steps.iter().enumerate() {
        out.extend(step(i, s));
    }
    out.extend(error_lines(h));
    out.extend(how_sure(h));
    out.extend(rivals(h));
    if let Some(e) = &h.next_experiment {
        out.push(item("", "  ", format!("next experiment: {}", symbols(e))));
    }
    out.push(item("", "  ", format!("next: {}", h.next_command)));
    out.push(item(
        "",
        "",
        "(the full tables: --verbose; every number: --format json)".into(),
    ));
    out
}

fn summary(h: &Headline) -> String {
    let n = h.steps.len();
    match h.kind.as_ref() {
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

fn step(i: usize, s: &HeadlineStep) -> Vec<Item> {
    let explains = s
        .explains
        .map(|f| format!(", removes {:.0}\u{a0}% of the excess χ² left", 100.0 * f))
        .unwrap_or_default();
    let head = format!("{}. {} [{}{explains}]", i + 1, symbols(&s.law), s.kind);
    let mut items = vec![item("  ", "     ", head)];
    if let Some(v) = &s.variable {
        items.push(item("     ", "       ", symbols(v)));
    }
    if !s.reading.is_empty() {
        items.push(item("     ", "       ", symbols(&s.reading)));
    }
    if !s.params.is_empty() {
        let ps: Vec<String> = s.params.iter().map(param).collect();
        items.push(item("     ", "       ", ps.join("; ")));
    }
    if !s.correlations.is_empty() {
        let pairs: Vec<String> = s
            .correlations
            .iter()
            .map(|c| format!("{} and {} (r = {:+.2})", c.a, c.b, c.r))
            .collect();
        items.push(item(
            "     ",
            "       ",
            format!("correlated: {}", pairs.join("; ")),
        ));
    }
    items
}

fn error_lines(h: &Headline) -> Vec<Item> {
    let mare: Vec<String> = h
        .mare
        .iter()
        .map(|m| format!("{:.2}\u{a0}%", 100.0 * m))
        .collect();
    let chi: Vec<String> = h
        .chi2_reduced
        .iter()
        .map(|c| c.map_or("-".into(), |c| fmt_sig(c, 3)))
        .collect();
    let floor = h
        .noise_floor_chi2_reduced
        .map_or("-".into(), |f| fmt_sig(f, 3));
    vec![
        item("", "  ", format!("error: MARE {}", mare.join(" -> "))),
        item(
            "       ",
            "         ",
            format!("reduced χ² {} (noise floor {floor})", chi.join(" -> ")),
        ),
    ]
}

fn how_sure(h: &Headline) -> Vec<Item> {
    let sets = match h.rivals.len() {
        0 => "no rival set within the margin".to_string(),
        n => format!(
            "the found set has Akaike weight {:.2} among {n} sets",
            h.rivals[0].akaike_weight
        ),
    };
    if h.stability.is_empty() {
        return vec![item(
            "",
            "  ",
            format!("how sure: {sets}; stability under resampling was not measured"),
        )];
    }
    let mut items = vec![item("", "  ", format!("how sure: {sets}"))];
    items.extend(h.stability.iter().map(|t| {
        item(
            "  ",
            "    ",
            format!(
                "{} chosen in {} of {} {} resamples ({:.0}\u{a0}%)",
                symbols(&t.term),
                t.selected,
                t.resamples,
                t.method,
                100.0 * t.fraction
            ),
        )
    }));
    items
}

fn rivals(h: &Headline) -> Vec<Item> {
    if h.rivals.len() < 2 {
        return Vec::new();
    }
    let mut items = vec![item(
        "",
        "",
        format!(
            "  {:>3} {:>8} {:>7} {:>5}  set",
            "", "Δkey", "weight", "floor"
        ),
    )];
    for (i, r) in h.rivals.iter().enumerate() {
        let first = format!(
            "  {:>3} {:>8} {:>7.3} {:>5}  ",
            format!("{}.", i + 1),
            format!("{:+.1}", r.key_difference),
            r.akaike_weight,
            if r.at_noise_floor { "yes" } else { "no" }
        );
        let pad = " ".repeat(first.chars().count());
        items.push(Item {
            first,
            rest: pad,
            text: symbols(&r.members.join(" + ")),
        });
    }
    items
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workbench::diagnose::{diagnose, DiagnoseSettings};

    /// Every item of the paper's screen is one sentence of at most 60
    /// words, and every line of it fits the width.
    #[test]
    fn the_paper_s_screen_has_short_items_and_lines() {
        let d = diagnose(
            &crate::model::Model::base(),
            &crate::data::paper(),
            &DiagnoseSettings::default(),
        )
        .unwrap();
        let h = super::super::headline::headline(&d, None);
        let items = items(&h);
        assert!(items.len() >= 6);
        for i in &items {
            let words = i.text.split_whitespace().count();
            assert!(words <= 60, "{words} words: {}", i.text);
        }
        for width in [40, 72, 100] {
            for line in render(&h, width).lines() {
                assert!(textwrap::core::display_width(line) <= width, "{line:?}");
            }
        }
    }
}
