//! The page of a study: a renderer of [`crate::study::Study`] that computes
//! nothing of its own. Every number on it is a number stored in the study
//! file (the same values `swimbot steps --format json` prints), shown in
//! the order the user built the model: what `diagnose` said of the base
//! model, then each step (its law in physics notation, its physical
//! statement, its fitted values with 95 % intervals, before -> after per
//! case as a table and figures), then what `diagnose` says of the final
//! model. The figures are drawn from the stored predictions: a parity plot
//! of each step (before and after on one chart, both labelled by case) and
//! the relative error against the step's feature (the quantity its law
//! names, else the geometry that varies across the cases).

use super::html::{document, escape, figure, table};
use crate::chart::{notation, steps, Axis, Chart, Series, PALETTE};
use crate::data::quantities::{by_id, FEATURES};
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

fn heading(i: usize) -> String {
    let (id, t) = SECTIONS[i];
    format!("<h2 id=\"{id}\">{}</h2>", escape(t))
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

/// The whole page.
pub fn page(s: &Study) -> String {
    let f = s.file();
    let title = format!("swimbot study: {}", f.dataset.name);
    let mut b = format!(
        "<h1>{}</h1><p class=\"note\">data: <code>{}</code> (SHA-256 <code>{}</code>); base model: \
         <code>{}</code>; likelihood: {}; started {} with swimbot {}; study file <code>{}</code>. \
         Every number on this page is the study file's (<code>swimbot steps --format json</code>).</p>",
        escape(&title),
        escape(&f.dataset.path.display().to_string()),
        escape(&f.dataset.sha256),
        escape(&f.model.preset),
        escape(&f.model.likelihood),
        escape(&f.created_utc),
        escape(&f.swimbot_version),
        escape(&s.path().display().to_string()),
    );
    b.push_str("<ol class=\"toc\">");
    for (id, t) in SECTIONS {
        b.push_str(&format!("<li><a href=\"#{id}\">{}</a></li>", escape(t)));
    }
    b.push_str("</ol>");
    b.push_str(&heading(0));
    b.push_str(&stats_table(&[("base", &f.start.stats)]));
    b.push_str(&diagnosis(f.first_diagnosis.as_ref()));
    b.push_str(&heading(1));
    b.push_str(&overview(s));
    let mut before = &f.start;
    for (i, st) in s.steps().iter().enumerate() {
        b.push_str(&step(s.dataset(), i + 1, st, &before.cases));
        before = &st.after;
    }
    b.push_str(&heading(2));
    b.push_str(&stats_table(&[("final", &s.current().stats)]));
    b.push_str(&diagnosis(s.last_diagnosis()));
    b.push_str(&heading(3));
    b.push_str(&cases_table(&f.start));
    document(&title, &b)
}

fn stats_table(rows: &[(&str, &Stats)]) -> String {
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
                    escape(l),
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

fn diagnosis(d: Option<&DiagnosisRecord>) -> String {
    let Some(d) = d else {
        return "<p class=\"note\">diagnose was not run.</p>".into();
    };
    let mut h = format!(
        "<div class=\"verdict\"><p><b>{}</b>: {}</p>",
        escape(&d.verdict),
        escape(&d.note)
    );
    if !d.proposals.is_empty() {
        h.push_str("<p>It proposes:</p><ul>");
        for p in &d.proposals {
            let how = p
                .add_commands()
                .iter()
                .map(|c| format!("<code>{}</code>", escape(c)))
                .collect::<Vec<_>>()
                .join(", then ");
            h.push_str(&format!(
                "<li>{}{} ({how})</li>",
                escape(&notation(&p.text)),
                p.explains
                    .map(|x| format!("; removes {:.0} % of the excess chi-square", 100.0 * x))
                    .unwrap_or_default()
            ));
        }
        h.push_str("</ul>");
    }
    h.push_str("</div>");
    h
}

/// The error at every step, as a table and a bar chart.
fn overview(s: &Study) -> String {
    let f = s.file();
    let mut labels = vec![format!("base ({})", f.model.preset)];
    let mut values = vec![100.0 * f.start.stats.mare];
    let mut rows = vec![vec![
        "0".into(),
        escape(&labels[0]),
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
            escape(&format!("+ {}", st.effect.name)),
            escape(&st.refit),
            pc(st.before.mare),
            pc(st.after.stats.mare),
            pc(st.after.stats.cv_mare),
            num(st.after.stats.chi2),
            opt_num(st.after.stats.noise_floor_chi2),
        ]);
    }
    let chart = steps("MARE at each step", "MARE (%)", &labels, &values);
    let mut h = table(
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
    );
    h.push_str(&figure(
        "fig-steps",
        &[chart],
        1,
        "The mean absolute relative error over every measured quantity after each step, \
         each step calibrated on top of the ones before it.",
    ));
    if s.steps().is_empty() {
        h.push_str("<p>No step yet: <code>swimbot add EFFECT</code> adds one.</p>");
    }
    h
}

/// One step; `before` are the cases as the step before it left them.
fn step(data: &Dataset, n: usize, st: &StepRecord, before: &[CaseRow]) -> String {
    let d = &st.effect;
    let mut h = format!(
        "<h3 id=\"step-{n}\">Step {n}: + {}</h3><p>{}</p>",
        escape(&d.name),
        escape(&notation(&d.statement))
    );
    if !d.formula.is_empty() {
        h.push_str("<p>The law: ");
        let laws: Vec<String> = d
            .formula
            .iter()
            .map(|f| format!("<code>{}</code>", escape(&notation(f))))
            .collect();
        h.push_str(&laws.join("; "));
        h.push_str("</p>");
    }
    h.push_str(&format!(
        "<p class=\"note\">reference: {}; {} effect; added {} with swimbot {}{}.</p>",
        escape(&d.reference),
        escape(&d.kind),
        escape(&st.date_utc),
        escape(&st.swimbot_version),
        if st.forced {
            "; recorded with --force although the error rose"
        } else {
            ""
        }
    ));
    if let Some(p) = &st.proposed_by {
        h.push_str(&format!("<p>Proposed by {}.</p>", escape(&notation(p))));
    }
    h.push_str(&params_table(st));
    if !st.notes.is_empty() {
        h.push_str("<ul>");
        for note in &st.notes {
            h.push_str(&format!("<li>{}</li>", escape(note)));
        }
        h.push_str("</ul>");
    }
    h.push_str(&format!(
        "<p>MARE {} % → {} % (cross-validated {} %); chi-square {} → {} (noise floor {}).</p>",
        pc(st.before.mare),
        pc(st.after.stats.mare),
        pc(st.after.stats.cv_mare),
        num(st.before.chi2),
        num(st.after.stats.chi2),
        opt_num(st.after.stats.noise_floor_chi2)
    ));
    h.push_str(&before_after_table(before, &st.after));
    if super::study_fig4::applies(data, &st.after.cases) {
        h.push_str(&super::study_fig4::figure(
            data,
            n,
            &d.name,
            before,
            &st.after.cases,
        ));
        return h;
    }
    let feature = feature_of(data, &st.effect.formula);
    let charts = [
        parity(before, &st.after.cases, false),
        parity(before, &st.after.cases, true),
        residuals(data, feature, before, &st.after.cases),
    ];
    h.push_str(&figure(
        &format!("fig-step-{n}"),
        &charts,
        3,
        &format!(
            "Step {n}, + {}: predicted against measured U and Ω<sub>b</sub> before (hollow, grey) \
             and after (filled) the step, each point labelled by its case, the measured 95 % \
             intervals as horizontal bars; and the relative error against {} before and after.",
            escape(&d.name),
            super::html::rich(feature.name)
        ),
    ));
    h
}

fn params_table(st: &StepRecord) -> String {
    let rows: Vec<Vec<String>> = st
        .params
        .iter()
        .chain(&st.refitted)
        .map(|p| {
            vec![
                escape(&p.effect),
                escape(&notation(&p.name)),
                escape(&p.unit),
                num(p.value),
                opt_num(p.lo),
                opt_num(p.hi),
                escape(&p.status),
                escape(
                    p.reason
                        .as_deref()
                        .unwrap_or(if p.at_bound { "at its bound" } else { "" }),
                ),
            ]
        })
        .collect();
    table(
        &[
            "<effect",
            "<parameter",
            "<unit",
            "value",
            "95 % low",
            "95 % high",
            "<status",
            "<why",
        ],
        &rows,
    )
}

fn before_after_table(before: &[CaseRow], after: &Snapshot) -> String {
    let rows: Vec<Vec<String>> = after
        .cases
        .iter()
        .map(|a| {
            let b = before.iter().find(|b| b.id == a.id);
            vec![
                escape(&a.id),
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

fn parity(before: &[CaseRow], after: &[CaseRow], omega: bool) -> Result<String, String> {
    let (q, unit) = if omega {
        ("Omega_b", "Hz")
    } else {
        ("U", "mm/s")
    };
    let pick = |c: &CaseRow| {
        if omega {
            (c.omega_obs_hz, c.omega_ci_hz, c.omega_pred_hz)
        } else {
            (c.u_obs_mm_s, c.u_ci_mm_s, c.u_pred_mm_s)
        }
    };
    let mut series = Vec::new();
    let mut all = Vec::new();
    for (label, rows, color, measured) in [
        ("before", before, crate::chart::Rgb(150, 150, 150), false),
        ("after", after, PALETTE[0], true),
    ] {
        let mut pts = Vec::new();
        let mut xe = Vec::new();
        let mut ids = Vec::new();
        for c in rows {
            let (Some(obs), ci, pred) = pick(c) else {
                continue;
            };
            pts.push((obs, pred, 0.0));
            xe.push(ci.unwrap_or(0.0));
            ids.push(if measured {
                c.id.clone()
            } else {
                String::new()
            });
            all.extend([obs, pred]);
        }
        // The measured interval is drawn once, on the points after the
        // step; the points before are named by case in the figure's notes
        // as the labelled ones are.
        let s = if measured {
            Series::measured(label, color, pts).x_errors(xe).labels(ids)
        } else {
            Series::model(label, color, pts).names(ids)
        };
        series.push(s);
    }
    let mut chart = Chart::new(
        &format!("Parity: {q}"),
        &format!("{q} measured ({unit})"),
        &format!("{q} predicted ({unit})"),
    )
    .diagonal();
    if Axis::spans_decade(all.into_iter()) {
        chart = chart.log_x().log_y();
    }
    chart.render(&series)
}

/// The quantity a step's law names (the first case quantity in its
/// formula), else the first of `N_lambda`, `B_o/R_body`, `f` that varies
/// across the cases (one shared value would collapse the axis).
fn feature_of(data: &Dataset, formula: &[String]) -> &'static crate::data::quantities::Quantity {
    let named = formula.iter().find_map(|f| {
        f.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .filter_map(by_id)
            .find(|q| varies(data, q))
    });
    named.unwrap_or_else(|| {
        ["n_waves", "amplitude_ratio", "frequency"]
            .iter()
            .filter_map(|id| by_id(id))
            .find(|q| varies(data, q))
            .unwrap_or(&FEATURES[0])
    })
}

fn varies(data: &Dataset, q: &crate::data::quantities::Quantity) -> bool {
    let v: Vec<f64> = data.cases.iter().map(|c| q.of(c)).collect();
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(*x), h.max(*x))
        });
    hi - lo > 1e-9 * hi.abs().max(1.0)
}

fn residuals(
    data: &Dataset,
    q: &crate::data::quantities::Quantity,
    before: &[CaseRow],
    after: &[CaseRow],
) -> Result<String, String> {
    let x_of = |id: &str| data.cases.iter().find(|c| c.id == id).map(|c| q.of(c));
    let mut series = Vec::new();
    for (label, rows, color, hollow) in [
        ("U before", before, crate::chart::Rgb(150, 150, 150), true),
        ("U after", after, PALETTE[0], false),
        ("Ω_b before", before, crate::chart::Rgb(230, 170, 170), true),
        ("Ω_b after", after, PALETTE[1], false),
    ] {
        let omega = label.starts_with('Ω');
        let pts: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter_map(|c| {
                let e = if omega { c.omega_rel_err } else { c.u_rel_err }?;
                Some((x_of(&c.id)?, 100.0 * e, 0.0))
            })
            .collect();
        series.push(if hollow {
            Series::model(label, color, pts)
        } else {
            Series::measured(label, color, pts)
        });
    }
    let unit = if q.unit.is_empty() || q.unit == "1" {
        String::new()
    } else {
        format!(" ({})", q.unit)
    };
    Chart::new(
        &format!("Relative error against {}", q.name),
        &format!("{}{unit}", q.name),
        "relative error (%)",
    )
    .zero_line()
    .render(&series)
}

fn cases_table(start: &Snapshot) -> String {
    let rows: Vec<Vec<String>> = start
        .cases
        .iter()
        .map(|c| {
            vec![
                escape(&c.id),
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
