//! The section on the path `diagnose` takes from the model it starts from,
//! step by step, each with its MARE and reduced chi-square, each drawn
//! against the step before it ([`super::path_chart`]), with the noise floor
//! (the reduced chi-square a perfect model stays below) as a line.
//!
//! The steps, in the order `diagnose` works: the start; the catalogue
//! effect without a fitted parameter that lowers the chi-square most; the
//! best catalogue effect by AICc; the best pair, when it beats that; the
//! best located correction of the verdict.

use super::html::{html, table, Markup};
use super::page::Part;
use super::path_chart::{chart, Metric};
use super::wording::{describe, pct, stat, Change};
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::diagnose::{Candidate, Diagnosis};

/// One step of the path `diagnose` takes, as the chart and the table draw it.
#[derive(Debug, Clone)]
pub struct ChartStep {
    /// Short name (the chart's category label).
    pub label: String,
    /// What the step is, in a sentence fragment.
    pub what: String,
    pub fitted: usize,
    pub mare: f64,
    pub cv_mare: Option<f64>,
    pub chi2_reduced: Option<f64>,
}

fn free_params(m: &Model) -> usize {
    m.effects.iter().map(|e| e.free_indices().len()).sum()
}

/// What `to` changes from `from`, by effect name: "+ X" for an effect
/// added on top, "− Y" for one the step takes out (then the step is an
/// alternative to the one before, and its label says so).
pub fn change_label(from: &Model, to: &Model) -> String {
    let names = |m: &Model| {
        m.effects
            .iter()
            .map(|e| e.name().to_string())
            .collect::<Vec<_>>()
    };
    let (a, b) = (names(from), names(to));
    let removed = a
        .iter()
        .filter(|n| !b.contains(n))
        .map(|n| format!("− {n}"));
    let added = b
        .iter()
        .filter(|n| !a.contains(n))
        .map(|n| format!("+ {n}"));
    let label: Vec<String> = removed.chain(added).collect();
    if label.is_empty() {
        "refitted".into()
    } else {
        label.join(" ")
    }
}

fn from_candidate(c: &Candidate, what: &str) -> ChartStep {
    ChartStep {
        label: format!("+ {}", c.effect),
        what: what.to_string(),
        // every free parameter of the step's model, the start's included
        fitted: free_params(&c.model),
        mare: c.score.mare,
        cv_mare: Some(c.score.cv_mare),
        chi2_reduced: c.score.chi2_reduced,
    }
}

/// The steps of `d` (see the module docs).
pub fn steps(start: &Model, d: &Diagnosis) -> Vec<ChartStep> {
    let mut out = vec![ChartStep {
        label: "start".into(),
        what: format!("the model as given: {}", start.describe()),
        fitted: free_params(start),
        mare: d.baseline.mare,
        cv_mare: None,
        chi2_reduced: d.baseline.chi2_reduced,
    }];
    let zero = d
        .ranking
        .iter()
        .filter(|c| c.params.is_empty() && c.score.chi2 < d.baseline.chi2)
        .min_by(|a, b| a.score.chi2.total_cmp(&b.score.chi2));
    if let Some(z) = zero {
        out.push(from_candidate(
            z,
            "the catalogue effect without a fitted parameter that lowers χ² most",
        ));
    }
    let first = d.ranking.first();
    if let Some(f) = first.filter(|f| zero.is_none_or(|z| z.effect != f.effect)) {
        out.push(from_candidate(
            f,
            "the best catalogue effect by AICc, fitted",
        ));
    }
    let aicc = |c: &Candidate| c.score.aicc.unwrap_or(f64::INFINITY);
    if let Some(p) = d
        .pairs
        .first()
        .filter(|p| first.is_none_or(|f| aicc(p) < aicc(f)))
    {
        out.push(from_candidate(
            p,
            "the best pair of catalogue effects, fitted jointly",
        ));
    }
    if let Some(l) = d.verdict.located.first() {
        // what the law sits on: the effects beyond the start's (the law last)
        let beneath: Vec<&str> = l
            .model
            .effects
            .iter()
            .skip(start.effects.len())
            .map(|e| e.name())
            .collect();
        let under = beneath[..beneath.len().saturating_sub(1)].join(" + ");
        out.push(ChartStep {
            label: if under.is_empty() {
                format!("+ {} law", l.place)
            } else {
                format!("+ {under} + {} law", l.place)
            },
            what: format!(
                "located beyond the catalogue: {} ({})",
                l.describe(),
                l.interpretation
            ),
            fitted: free_params(&l.model),
            mare: l.score.mare,
            cv_mare: Some(l.score.cv_mare),
            chi2_reduced: l.score.chi2_reduced,
        });
    }
    // Label each step by what it changes from the step before, so that
    // "+ X" always means X added on top of the previous step's model.
    let models: Vec<&Model> = std::iter::once(start)
        .chain(zero.map(|c| &c.model))
        .chain(
            first
                .filter(|f| zero.is_none_or(|z| z.effect != f.effect))
                .map(|c| &c.model),
        )
        .chain(
            d.pairs
                .first()
                .filter(|p| first.is_none_or(|f| aicc(p) < aicc(f)))
                .map(|c| &c.model),
        )
        .chain(d.verdict.located.first().map(|l| &l.model))
        .collect();
    for (i, step) in out.iter_mut().enumerate().skip(1) {
        step.label = change_label(models[i - 1], models[i]);
        if step.label.contains('−') {
            step.what
                .push_str(" (an alternative to the step before: what it takes out is marked −)");
        }
    }
    out
}

/// The MARE a perfect model would show: the mean |relative error| of a
/// normal variable with the data's median relative standard error,
/// `sqrt(2/pi)` times it. Changes of MARE below it are noise.
pub fn noise_mare(data: &Dataset) -> f64 {
    crate::workbench::experiments::separation::median_rel_se(data)
        * (2.0 / std::f64::consts::PI).sqrt()
}

fn class(c: Change) -> &'static str {
    match c {
        Change::Falls => "fall",
        Change::Rises => "rise",
        Change::Flat => "flat",
    }
}

/// `describe`'s words for a change from the step before, in its colour.
fn change_cell(prev: f64, cur: f64, noise: f64, show: &dyn Fn(f64) -> String) -> Markup {
    html! {
        span class=(class(Change::of(prev, cur, noise))) { (describe(prev, cur, noise, show)) }
    }
}

pub fn section(start: &Model, data: &Dataset, d: Option<&Diagnosis>) -> Part {
    let Some(d) = d else {
        return html! {
            p {
                "This page was written without a diagnosis (" code { "swimbot compare" } "); "
                code { "swimbot report" } " adds the path " code { "diagnose" } " takes."
            }
        }
        .into();
    };
    let floor = d.baseline.noise_floor_chi2_reduced;
    let noise = noise_mare(data);
    let steps = steps(start, d);
    let searched = d
        .remainder
        .as_ref()
        .map(|r| r.discovery.screened)
        .or(d.discovery.as_ref().map(|x| x.screened));
    let mut rows = Vec::new();
    for (i, s) in steps.iter().enumerate() {
        let change = |prev: Option<f64>,
                      cur: Option<f64>,
                      noise: f64,
                      show: &dyn Fn(f64) -> String| match (i, prev, cur) {
            (0, _, _) => html! { "-" },
            (_, Some(p), Some(c)) => change_cell(p, c, noise, show),
            _ => html! { "n/a" },
        };
        let prev = i.checked_sub(1).map(|j| &steps[j]);
        rows.push(vec![
            html! { (s.label) },
            html! { (s.what) },
            html! { (s.fitted) },
            html! { (pct(s.mare)) },
            html! { (s.cv_mare.map_or("-".into(), pct)) },
            html! { (stat(s.chi2_reduced)) },
            change(prev.map(|p| p.mare), Some(s.mare), noise, &|x| pct(x)),
            change(
                prev.and_then(|p| p.chi2_reduced),
                s.chi2_reduced,
                floor.unwrap_or(0.0),
                &|x| stat(Some(x)),
            ),
        ]);
    }
    Part::from(html! {
        p {
            code { "swimbot diagnose" } " starts from " code { (start.describe()) } ", fits \
            every effect of its catalogue in turn (weighted by the CIs, scored by AICc and \
            cross-validated MARE), pairs them when none suffices, then searches beyond the \
            catalogue"
            @if let Some(m) = searched {
                " (" (m) " laws: place in the model × case feature × form)"
            }
            ". Each step is labelled by what it changes from the step before: \"+ X\" adds X \
            on top of it; \"− Y\" takes Y out, and marks a step that is an alternative rather \
            than an addition. The noise floor is the reduced χ² a perfect model stays below (at \
            diagnose's confidence level) given only the measurements' scatter: " (stat(floor))
            ". Each step is drawn against the one before it: green where it falls, red where \
            it rises, grey where the change is within the noise (MARE " (pct(noise))
            ") or below " (format!("{:.0}", 100.0 * super::wording::FLAT_SHARE)) " % of the \
            value."
        }
    })
    .with(super::html::figure(
        "path-chart",
        &[
            chart(&steps, Metric::Chi2, floor, noise),
            chart(&steps, Metric::Mare, None, noise),
        ],
        2,
        html! {
            b { "The path." } " Left: reduced χ² (log scale) with the noise floor (dashed); \
            right: MARE. Each arrow goes from the previous step's value to this step's."
        },
    ))
    .with(table(
        &[
            "<step",
            "<what",
            "fitted parameters",
            "MARE",
            "cross-validated MARE",
            "reduced χ²",
            "<MARE against the step before",
            "<reduced χ² against the step before",
        ],
        &rows,
    ))
}
