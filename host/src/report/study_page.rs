//! The page of a study: a renderer of [`crate::study::Study`] that computes
//! nothing of its own. Every number on it is a number stored in the study
//! file (the same values `swimbot steps --format json` prints), shown in
//! the order the user built the model: what `diagnose` said of the base
//! model, then each step (its law in physics notation, its physical
//! statement, its fitted values with 95 % intervals, before -> after per
//! case as a table and figures), then what `diagnose` says of the final
//! model. The figures are drawn from the stored predictions
//! ([`super::study_charts`], or the paper's Fig. 4 layout for data of its
//! design, [`super::figure4::study`]).

use super::html::{document, figure, html, omega_b, rich, table, Markup};
use super::page::{Page, Part};
use super::study_charts::{
    feature_of, parity, residuals, LABELLED_WORST, LABEL_ALL_UP_TO, SPLIT_RATIO,
};
use crate::chart::{notation, steps};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::study::{CaseRow, DiagnosisRecord, Snapshot, Stats, StepRecord, Study};

/// Section ids and titles, named by what they hold.
pub const SECTIONS: [(&str, &str); 4] = [
    ("first-diagnosis", "What diagnose said of the base model"),
    ("steps", "The model, step by step"),
    ("final-diagnosis", "What diagnose says of the final model"),
    ("data", "The data and the study file"),
];

fn heading(i: usize) -> Part {
    let (id, t) = SECTIONS[i];
    Part::heading(id, html! { h2 id=(id) { (t) } })
}

/// A number as the page prints it: 4 significant digits, in its own cell.
fn num(v: f64) -> String {
    fmt_sig(v, 4)
}

fn opt_num(v: Option<f64>) -> String {
    v.map_or_else(String::new, num)
}

/// A fraction as a percentage number (the column's header says `%`).
fn pc(v: f64) -> String {
    format!("{:.2}", 100.0 * v)
}

fn opt_pc(v: Option<f64>) -> String {
    v.map_or_else(String::new, pc)
}

/// The whole page, with its artefacts.
pub fn page(s: &Study) -> Page {
    let f = s.file();
    let title = format!("swimbot study: {}", f.dataset.name);
    let mut before = &f.start;
    let mut steps = Vec::new();
    for (i, st) in s.steps().iter().enumerate() {
        steps.push(step(s.dataset(), i + 1, st, &before.cases));
        before = &st.after;
    }
    let mut body = Part::from(html! { h1 { (title) } });
    body.push(super::study_answer::section(s));
    body.push(html! {
        p.note {
            "data: " code { (f.dataset.path.display()) } " (SHA-256 " code { (f.dataset.sha256) }
            "); base model: " code { (f.model.preset) } "; likelihood: " (f.model.likelihood)
            "; started " (f.created_utc) " with swimbot " (f.swimbot_version) "; study file "
            code { (s.path().display()) } ". Every number on this page is the study file's ("
            code { "swimbot steps --format json" } ")."
        }
        ol.toc {
            @for (id, t) in SECTIONS {
                li { a href={ "#" (id) } { (t) } }
            }
        }
    });
    body.push(heading(0));
    body.push(stats_table(&[("base", &f.start.stats)]));
    body.push(diagnosis(f.first_diagnosis.as_ref()));
    body.push(heading(1));
    body.push(overview(s));
    for st in steps {
        body.push(st);
    }
    body.push(heading(2));
    body.push(stats_table(&[("final", &s.current().stats)]));
    body.push(diagnosis(s.last_diagnosis()));
    body.push(heading(3));
    body.push(cases_table(&f.start));
    document(&title, body)
}

fn stats_table(rows: &[(&str, &Stats)]) -> Part {
    table(
        &[
            "<model",
            "MARE (%)",
            "CV MARE (%)",
            "chi-square",
            "reduced chi-square",
            "noise floor chi-square",
            "at the noise floor",
            "quantities",
            "fitted parameters",
        ],
        &rows
            .iter()
            .map(|(l, st)| {
                vec![
                    l.to_string(),
                    pc(st.mare),
                    pc(st.cv_mare),
                    num(st.chi2),
                    opt_num(st.chi2_reduced),
                    opt_num(st.noise_floor_chi2),
                    if st.at_noise_floor { "yes" } else { "no" }.into(),
                    st.n.to_string(),
                    st.free_params.to_string(),
                ]
            })
            .collect::<Vec<_>>(),
    )
}

fn diagnosis(d: Option<&DiagnosisRecord>) -> Markup {
    let Some(d) = d else {
        return html! { p.note { "diagnose was not run." } };
    };
    html! {
        div.verdict {
            p { b { (d.verdict) } ": " (d.note) }
            @if !d.proposals.is_empty() {
                p { "It proposes:" }
                ul {
                    @for p in &d.proposals {
                        li {
                            (notation(&p.text))
                            @if let Some(x) = p.explains {
                                "; removes " (format!("{:.0}", 100.0 * x))
                                " % of the excess chi-square"
                            }
                            " ("
                            @for (i, c) in p.add_commands().iter().enumerate() {
                                @if i > 0 { ", then " }
                                code { (c) }
                            }
                            ")"
                        }
                    }
                }
            }
        }
    }
}

/// The error at every step, as a table and a bar chart.
fn overview(s: &Study) -> Part {
    let f = s.file();
    let mut labels = vec![format!("base ({})", f.model.preset)];
    let mut values = vec![100.0 * f.start.stats.mare];
    let mut rows = vec![vec![
        "0".into(),
        labels[0].clone(),
        String::new(),
        String::new(),
        pc(f.start.stats.mare),
        pc(f.start.stats.cv_mare),
        num(f.start.stats.chi2),
        opt_num(f.start.stats.noise_floor_chi2),
    ]];
    for (i, st) in s.steps().iter().enumerate() {
        labels.push(format!("+ {}", st.effect.name));
        values.push(100.0 * st.after.stats.mare);
        rows.push(vec![
            (i + 1).to_string(),
            format!("+ {}", st.effect.name),
            st.refit.clone(),
            pc(st.before.mare),
            pc(st.after.stats.mare),
            pc(st.after.stats.cv_mare),
            num(st.after.stats.chi2),
            opt_num(st.after.stats.noise_floor_chi2),
        ]);
    }
    let chart = steps("MARE at each step", "MARE (%)", &labels, &values);
    table(
        &[
            "step",
            "<effect",
            "<earlier steps",
            "MARE before (%)",
            "MARE after (%)",
            "CV MARE after (%)",
            "chi-square after",
            "noise floor chi-square",
        ],
        &rows,
    )
    .with(figure(
        "fig-steps",
        &[chart],
        1,
        html! {
            "The mean absolute relative error over every measured quantity after each \
            step, each step calibrated on top of the ones before it."
        },
    ))
    .with(html! {
        @if s.steps().is_empty() {
            p { "No step yet: " code { "swimbot add EFFECT" } " adds one." }
        }
    })
}

/// One step; `before` are the cases as the step before it left them.
fn step(data: &Dataset, n: usize, st: &StepRecord, before: &[CaseRow]) -> Part {
    let d = &st.effect;
    Part::from(html! {
        h3 id={ "step-" (n) } { "Step " (n) ": + " (d.name) }
        p { (notation(&d.statement)) }
        @if !d.formula.is_empty() {
            p {
                "The law: "
                @for (i, f) in d.formula.iter().enumerate() {
                    @if i > 0 { "; " }
                    code { (notation(f)) }
                }
            }
        }
        p.note {
            "reference: " (d.reference) "; " (d.kind) " effect; added " (st.date_utc)
            " with swimbot " (st.swimbot_version)
            @if st.forced { "; recorded with --force although the error rose" }
            "."
        }
        @if let Some(p) = &st.proposed_by {
            p { "Proposed by " (notation(p)) "." }
        }
    })
    .with(super::study_params::params_table(st))
    .with(html! {
        @if !st.notes.is_empty() {
            ul {
                @for note in &st.notes {
                    li { (note) }
                }
            }
        }
        p {
            "MARE " (pc(st.before.mare)) " % → " (pc(st.after.stats.mare))
            " % (cross-validated " (pc(st.after.stats.cv_mare)) " %); chi-square "
            (num(st.before.chi2)) " → " (num(st.after.stats.chi2)) " (noise floor "
            (opt_num(st.after.stats.noise_floor_chi2)) ")."
        }
    })
    .with(before_after_table(before, &st.after))
    .with(step_figure(data, n, st, before))
}

/// The step's figure: the paper's Fig. 4 layout for data of its design,
/// else the parity plots and the residual against the step's feature.
fn step_figure(data: &Dataset, n: usize, st: &StepRecord, before: &[CaseRow]) -> Part {
    let d = &st.effect;
    if super::figure4::study::applies(data, &st.after.cases) {
        return super::figure4::study::figure(data, n, &d.name, before, &st.after.cases);
    }
    let feature = feature_of(data, &d.formula);
    let mut charts = vec![
        parity(before, &st.after.cases, false),
        parity(before, &st.after.cases, true),
    ];
    let split = {
        let r = residuals(data, feature, before, &st.after.cases);
        let split = r.len() > 1;
        charts.extend(r);
        split
    };
    let some = st.after.cases.len() > LABEL_ALL_UP_TO;
    figure(
        &format!("fig-step-{n}"),
        &charts,
        2,
        html! {
            "Step " (n) ", + " (d.name) ": predicted against measured U and " (omega_b())
            " before (hollow, grey) and after (filled) the step, "
            @if some {
                "the " (LABELLED_WORST) " cases worst after the step labelled (the table above \
                holds every case), "
            } @else {
                "each point labelled by its case, "
            }
            "the measured 95 % intervals as horizontal bars; and the relative error against "
            (rich(feature.name))
            @if split {
                ", before and after the step in panels of their own (the error before is more \
                than " (SPLIT_RATIO) " times the error after: on one axis the after-values \
                would lie on zero)."
            } @else {
                " before and after."
            }
        },
    )
}

fn before_after_table(before: &[CaseRow], after: &Snapshot) -> Part {
    let rows: Vec<Vec<String>> = after
        .cases
        .iter()
        .map(|a| {
            let b = before.iter().find(|b| b.id == a.id);
            vec![
                a.id.clone(),
                opt_num(a.u_obs_mm_s),
                opt_num(a.u_ci_mm_s),
                b.map_or_else(String::new, |b| num(b.u_pred_mm_s)),
                num(a.u_pred_mm_s),
                opt_pc(b.and_then(|b| b.u_rel_err)),
                opt_pc(a.u_rel_err),
                opt_num(a.omega_obs_hz),
                opt_num(a.omega_ci_hz),
                b.map_or_else(String::new, |b| num(b.omega_pred_hz)),
                num(a.omega_pred_hz),
                opt_pc(b.and_then(|b| b.omega_rel_err)),
                opt_pc(a.omega_rel_err),
            ]
        })
        .collect();
    table(
        &[
            "<case",
            "U measured (mm/s)",
            "U 95 % CI (mm/s)",
            "U before (mm/s)",
            "U after (mm/s)",
            "U error before (%)",
            "U error after (%)",
            "Ω_b measured (Hz)",
            "Ω_b 95 % CI (Hz)",
            "Ω_b before (Hz)",
            "Ω_b after (Hz)",
            "Ω_b error before (%)",
            "Ω_b error after (%)",
        ],
        &rows,
    )
}

fn cases_table(start: &Snapshot) -> Part {
    let rows: Vec<Vec<String>> = start
        .cases
        .iter()
        .map(|c| {
            vec![
                c.id.clone(),
                num(c.n_waves),
                num(c.amplitude_ratio),
                num(c.frequency_hz),
                opt_num(c.u_obs_mm_s),
                opt_num(c.u_ci_mm_s),
                opt_num(c.omega_obs_hz),
                opt_num(c.omega_ci_hz),
            ]
        })
        .collect();
    table(
        &[
            "<case",
            "N_λ",
            "B_o/R_body",
            "f (Hz)",
            "U measured (mm/s)",
            "U 95 % CI (mm/s)",
            "Ω_b measured (Hz)",
            "Ω_b 95 % CI (Hz)",
        ],
        &rows,
    )
}
