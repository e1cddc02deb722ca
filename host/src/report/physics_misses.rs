//! The physics section's list of the quantities the zero-parameter model misses by
//! more than the coverage interval (2 combined standard deviations:
//! measurement and inputs in quadrature), each with what the rest of the
//! page names for it: the audit's flags on that case, the catalogue
//! model of `diagnose` (a ranked candidate or the located correction, each
//! fitted to all cases) that moves that quantity most, and whether every
//! model compared errs the same way there (a shortfall no model of the
//! family reaches). Nothing is named by hand: every clause is computed from
//! the comparisons, the diagnosis and the audit given.
//!
//! References: JCGM 100:2008 (GUM) 6.2-6.3 (coverage factor k = 2).

use super::html::{html, omega_b, Markup};
use super::wording::{pct, signed_pct};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::workbench::audit::Audit;
use crate::workbench::compare::{compare, Comparison, Outside, Quantity};
use crate::workbench::diagnose::Diagnosis;

/// `quantity`'s relative error for `case` in `cmp`.
fn rel_err(cmp: &Comparison, case: &str, q: Quantity) -> Option<f64> {
    let k = cmp.cases.iter().find(|k| k.id == case)?;
    match q {
        Quantity::U => k.u().rel_err,
        Quantity::Omega => k.omega().rel_err,
    }
}

fn label(q: Quantity) -> Markup {
    match q {
        Quantity::U => html! { "U" },
        Quantity::Omega => omega_b(),
    }
}

/// The diagnosis's fitted models, `(name, comparison)`: every ranked
/// catalogue candidate (each fitted to all cases, a few local predictions
/// each) and the best located correction.
pub fn candidates(data: &Dataset, d: Option<&Diagnosis>) -> Vec<(Markup, Comparison)> {
    let Some(d) = d else { return Vec::new() };
    let located = d
        .verdict
        .located
        .first()
        .map(|l| (format!("located: {}", l.describe()), &l.model));
    d.ranking
        .iter()
        .map(|c| (c.effect.clone(), &c.model))
        .chain(located)
        .filter_map(|(name, m)| Some((with_reach(name, m, data), compare(m, data, 0).ok()?)))
        .collect()
}

/// The name as code, with how many cases the model's last effect acts on
/// when it is not all of them: an effect fitted to one case fits it
/// trivially.
fn with_reach(name: String, m: &crate::model::Model, data: &Dataset) -> Markup {
    let Some(e) = m.effects.last() else {
        return html! { (name) };
    };
    let acts = data
        .cases
        .iter()
        .filter(|c| e.effect.applies_to(c, &e.values))
        .count();
    let total = data.cases.len();
    html! {
        code { (name) }
        @if acts < total {
            " (which acts on " (acts) " of " (total) " cases)"
        }
    }
}

/// What the page names for one quantity outside the interval.
fn named(
    o: &Outside,
    own: f64,
    models: &[(String, &Comparison)],
    fitted: &[(Markup, Comparison)],
    audit: Option<&Audit>,
) -> Vec<Markup> {
    let mut says = Vec::new();
    let errs: Vec<f64> = models
        .iter()
        .map(|(_, c)| *c)
        .chain(fitted.iter().map(|(_, c)| c))
        .filter_map(|c| rel_err(c, &o.case, o.quantity))
        .chain([own])
        .collect();
    if errs.len() > 1 && errs.iter().all(|e| e.signum() == own.signum()) {
        let lo = errs.iter().map(|e| e.abs()).fold(f64::MAX, f64::min);
        let hi = errs.iter().map(|e| e.abs()).fold(0.0, f64::max);
        let way = if own > 0.0 {
            "over-predicts"
        } else {
            "under-predicts"
        };
        says.push(html! {
            "every model compared here " (way) " it, by " (pct(lo)) " to " (pct(hi))
            " (this one, the paper's two and " code { "diagnose" } "'s " (fitted.len())
            " fitted models)"
        });
    }
    let best = fitted
        .iter()
        .filter_map(|(e, c)| Some((e, rel_err(c, &o.case, o.quantity)?)))
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
    if let Some((effect, e)) = best.filter(|(_, e)| e.abs() < 0.5 * own.abs()) {
        says.push(html! {
            code { "diagnose" } "'s " (effect) ", fitted to all cases, brings it to "
            (signed_pct(Some(e)))
        });
    }
    for f in audit
        .map(|a| {
            a.flags
                .iter()
                .filter(|f| f.case == o.case)
                .collect::<Vec<_>>()
        })
        .unwrap_or_default()
    {
        says.push(html! { "the audit flags this case (" (f.kind) "): " (f.detail) });
    }
    says
}

/// The list, or one sentence when every quantity is inside.
pub fn list(
    data: &Dataset,
    cmp: &Comparison,
    models: &[(String, &Comparison)],
    d: Option<&Diagnosis>,
    audit: Option<&Audit>,
) -> Markup {
    let Some(cov) = &cmp.coverage else {
        return html! {};
    };
    let head = html! {
        b { "Coverage: " (cov.describe()) } " (against measurement and inputs: "
        (super::correlated::statistic(cmp)) ")."
    };
    if cov.outside.is_empty() {
        return html! { p id="physics-coverage" { (head) } };
    }
    let fitted = candidates(data, d);
    html! {
        p id="physics-coverage" { (head) " Outside, and what this page names for each:" }
        ul {
            @for o in &cov.outside {
                @let own = rel_err(cmp, &o.case, o.quantity).unwrap_or(f64::NAN);
                @let says = named(o, own, models, &fitted, audit);
                li {
                    b { (o.case) " " (label(o.quantity)) } ": " (signed_pct(Some(own))) " ("
                    (fmt_sig(o.sigmas, 3)) " combined standard deviations); "
                    @if says.is_empty() {
                        "neither the audit nor the diagnosis on this page names a cause"
                    }
                    @for (i, s) in says.iter().enumerate() {
                        @if i > 0 { "; " }
                        (s)
                    }
                    "."
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The base model's comparison with tail-3's U error set to `e`.
    fn with_tail3_u(e: f64) -> Comparison {
        let data = crate::data::paper();
        let mut c = compare(&crate::model::Model::base(), &data, 0).unwrap();
        c.cases[2][crate::workbench::compare::Quantity::U].rel_err = Some(e);
        c
    }

    fn joined(says: Vec<Markup>) -> String {
        let says: Vec<String> = says.into_iter().map(Markup::into_string).collect();
        says.join("; ")
    }

    #[test]
    fn the_same_sign_everywhere_is_said_and_a_mixed_sign_is_not() {
        let o = Outside {
            case: "tail-3".into(),
            quantity: Quantity::U,
            sigmas: 3.5,
        };
        let (a, b) = (with_tail3_u(0.4), with_tail3_u(2.0));
        let models = [("a".to_string(), &a), ("b".to_string(), &b)];
        let fitted = vec![(html! { code { "x" } }, with_tail3_u(0.3))];
        let says = joined(named(&o, 1.0, &models, &fitted, None));
        assert!(
            says.contains("over-predicts it, by 30.0 % to 200.0 %"),
            "{says}"
        );
        // 0.3 is below half of 1.0: the fitted model is named
        assert!(says.contains("<code>x</code>, fitted to all cases, brings it to +30.0 %"));
        let mixed = vec![(html! { code { "y" } }, with_tail3_u(-0.8))];
        let says = joined(named(&o, 1.0, &models, &mixed, None));
        assert!(!says.contains("every model"), "{says}");
        assert!(
            !says.contains("<code>y</code>"),
            "-80 % is no halving: {says}"
        );
    }
}
