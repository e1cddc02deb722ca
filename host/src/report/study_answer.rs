//! The study page's opening, the answer first: each step's law with its
//! fitted values (value ± u, JCGM 100 sec. 7.2.6), the error falling
//! (MARE and χ²/ν, before -> after, against the noise floor), what the
//! last diagnosis says is still missing and how sure it is (the Akaike
//! weights of the rival sets and the terms' stability under resampling),
//! what the data cannot tell apart, and the next command. Every number is
//! the study file's: the steps' statistics and parameters, and the last
//! diagnosis's [`Headline`], the value `diagnose --format json` prints
//! under `headline`; nothing is recomputed here.

use super::html::{classed_table, html, rich, Cell, Markup};
use super::page::Part;
use super::steps_table::{fitted, param};
use crate::chart::notation;
use crate::format::fmt_sig;
use crate::study::{DiagnosisRecord, Stats, Study};
use crate::workbench::headline::Headline;

/// A MARE (a fraction) as the page and the terminal print it.
pub fn mare(v: f64) -> String {
    format!("{:.2}\u{a0}%", 100.0 * v)
}

/// A reduced chi-square as the terminal prints it (3 significant digits).
pub fn chi2(v: Option<f64>) -> String {
    v.map_or("-".into(), |c| fmt_sig(c, 3))
}

/// The opening section.
pub fn section(s: &Study) -> Part {
    let last = s.last_diagnosis();
    let headline = last.and_then(|d| d.headline.as_ref());
    let mut inner = Part::heading("answer", html! { h2 id="answer" { "What was found" } });
    inner.push(steps_table(s));
    inner.push(html! {
        (error_line(s, headline))
        @if let Some(d) = last {
            (missing(d, headline))
        }
    });
    if let Some(h) = headline {
        inner.push(how_sure(h));
        inner.push(rivals(h));
    }
    inner.push(next(last, headline));
    inner.wrap(|m| html! { section.answer { (m) } })
}

fn law_cell(s: &Study, i: usize) -> Markup {
    let st = &s.steps()[i];
    let d = &st.effect;
    html! {
        b { "+ " (d.name) } ": "
        @if d.formula.is_empty() {
            (rich(&d.statement))
        } @else {
            @for (k, f) in d.formula.iter().enumerate() {
                @if k > 0 { "; " }
                code { (notation(f).replace(" * ", " · ")) }
            }
        }
    }
}

fn steps_table(s: &Study) -> Part {
    let f = s.file();
    let stats = |st: &Stats| (mare(st.mare), chi2(st.chi2_reduced));
    let (m0, c0) = stats(&f.start.stats);
    let mut rows: Vec<Vec<Cell>> = vec![
        vec![
            (None, html! { "step" }),
            (Some("l"), html! { "law" }),
            (Some("l"), html! { "fitted values (value ± u)" }),
            (None, html! { "MARE" }),
            (None, html! { "χ²/ν" }),
        ],
        vec![
            (None, html! { "0" }),
            (Some("l"), html! { "base (" (f.model.preset) ")" }),
            (Some("l"), html! {}),
            (Some("mare"), html! { (m0) }),
            (Some("chi"), html! { (c0) }),
        ],
    ];
    for (i, st) in s.steps().iter().enumerate() {
        let (m, c) = stats(&st.after.stats);
        rows.push(vec![
            (None, html! { (i + 1) }),
            (Some("l"), law_cell(s, i)),
            (
                Some("l params"),
                html! {
                    @for (k, p) in fitted(&st.params).enumerate() {
                        @if k > 0 { br; }
                        (notation(&param(&p)))
                    }
                },
            ),
            (Some("mare"), html! { (m) }),
            (Some("chi"), html! { (c) }),
        ]);
    }
    classed_table("answer-steps", &rows)
}

/// MARE and χ²/ν from the base model through every step, and the floor.
fn error_line(s: &Study, h: Option<&Headline>) -> Markup {
    let f = s.file();
    let all: Vec<&Stats> = std::iter::once(&f.start.stats)
        .chain(s.steps().iter().map(|st| &st.after.stats))
        .collect();
    let m: Vec<String> = all.iter().map(|st| mare(st.mare)).collect();
    let c: Vec<String> = all.iter().map(|st| chi2(st.chi2_reduced)).collect();
    let at_floor = all.last().is_some_and(|st| st.at_noise_floor);
    let floor = match h.and_then(|h| h.noise_floor_chi2_reduced) {
        Some(x) => html! { "the noise floor χ²/ν " span.floor { (chi2(Some(x))) } },
        None => html! {
            "the noise floor χ² " (chi2(all.last().and_then(|st| st.noise_floor_chi2)))
        },
    };
    html! {
        p.error {
            b { "Error: " } "MARE " span.chain { (m.join(" → ")) } "; χ²/ν "
            span.chain { (c.join(" → ")) } ", against " (floor)
            @if at_floor { " (reached)." } @else { " (not reached)." }
        }
    }
}

/// What the last diagnosis proposes to add, with what each removes.
fn missing(d: &DiagnosisRecord, h: Option<&Headline>) -> Markup {
    html! {
        p.missing {
            b { "Still missing" } " (diagnose of this model: " (d.verdict) ")"
            @if d.proposals.is_empty() { ": nothing the data can show." } @else { ":" }
        }
        @if !d.proposals.is_empty() {
            ul.missing {
                @for (i, p) in d.proposals.iter().enumerate() {
                    @let step = h.and_then(|h| h.steps.get(i));
                    li {
                        code { (notation(step.map_or(p.law.as_deref().unwrap_or(&p.name), |s| &s.law))) }
                        @if let Some(v) = step.and_then(|s| s.variable.as_ref()) {
                            ", " (notation(v))
                        }
                        @if let Some(x) = p.explains {
                            "; removes " span.explains { (format!("{:.0}", 100.0 * x)) }
                            "\u{a0}% of the excess χ² left"
                        }
                        @if let Some(s) = step.filter(|s| !s.params.is_empty()) {
                            " ("
                            @for (k, q) in s.params.iter().enumerate() {
                                @if k > 0 { "; " }
                                (notation(&param(q)))
                            }
                            ")"
                        }
                    }
                }
            }
        }
    }
}

fn how_sure(h: &Headline) -> Markup {
    html! {
        p.sure {
            b { "How sure: " }
            @match h.rivals.first() {
                None => "no rival set within the margin",
                Some(r) => {
                    "the found set has Akaike weight " span.weight { (format!("{:.2}", r.akaike_weight)) }
                    " among " (h.rivals.len()) " sets"
                }
            }
            @if h.stability.is_empty() {
                "; stability under resampling was not measured."
            } @else {
                "; "
                @for (i, t) in h.stability.iter().enumerate() {
                    @if i > 0 { ", " }
                    (notation(&t.term)) " chosen in " (t.selected) " of " (t.resamples) " "
                    (t.method) " resamples (" span.stability { (format!("{:.0}", 100.0 * t.fraction)) }
                    "\u{a0}%)"
                }
                "."
            }
        }
    }
}

/// The sets the data cannot tell apart, when there are several.
fn rivals(h: &Headline) -> Part {
    if h.rivals.len() < 2 {
        return Part::new();
    }
    let mut rows: Vec<Vec<Cell>> = vec![vec![
        (None, html! { "#" }),
        (Some("l"), html! { "set" }),
        (None, html! { "Δ key" }),
        (None, html! { "Akaike weight" }),
        (None, html! { "at the floor" }),
    ]];
    for (i, r) in h.rivals.iter().enumerate() {
        rows.push(vec![
            (None, html! { (i + 1) }),
            (Some("l"), html! { (notation(&r.members.join(" + "))) }),
            (None, html! { (format!("{:+.1}", r.key_difference)) }),
            (
                Some("weight"),
                html! { (format!("{:.3}", r.akaike_weight)) },
            ),
            (
                None,
                html! { @if r.at_noise_floor { "yes" } @else { "no" } },
            ),
        ]);
    }
    Part::from(html! { p { b { "Cannot be told apart:" } } }).with(classed_table("rivals", &rows))
}

/// The one command to run next: plan the runs that separate rivals,
/// else add what is proposed, else the diagnosis's own next step.
pub fn next_command(d: Option<&DiagnosisRecord>, h: Option<&Headline>) -> String {
    if h.is_some_and(|h| h.rivals.len() >= 2) {
        return "swimbot plan".into();
    }
    match d {
        Some(d) if d.verdict == "none-needed" => "swimbot data add MORE.csv".into(),
        Some(d) if !d.proposals.is_empty() => d.proposals[0].add_commands().join(", then "),
        _ => h.map_or("swimbot diagnose".into(), |h| h.next_command.clone()),
    }
}

fn next(d: Option<&DiagnosisRecord>, h: Option<&Headline>) -> Markup {
    let why = match (d, h) {
        (_, Some(h)) if h.rivals.len() >= 2 => h
            .next_experiment
            .clone()
            .unwrap_or_else(|| "the runs that tell the rivals apart".into()),
        (Some(d), _) if d.verdict == "none-needed" => {
            "nothing is missing at this data's precision; new measurements test it further".into()
        }
        _ => String::new(),
    };
    html! {
        p.next {
            b { "Next: " }
            @for (i, c) in next_command(d, h).split(", then ").enumerate() {
                @if i > 0 { ", then " }
                code.next { (c) }
            }
            @if !why.is_empty() { " (" (notation(&why)) ")" }
        }
    }
}
