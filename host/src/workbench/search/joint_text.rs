//! How what a found set's joint fit fixes only together
//! ([`super::joint`]) is worded in the note of `diagnose`: one
//! sentence per group of parameters that trade, per place with two laws,
//! and per strength whose interval spans no effect.

use super::joint::{traded_groups, JointReading, StepParam};
use crate::format::fmt_sig;

/// A parameter of a step: "step 2's body.E_x k = -0.98 +- 0.05".
fn step_param(p: &StepParam) -> String {
    let ci = p.ci95.map_or_else(
        || " (no interval)".to_string(),
        |c| format!(" ± {}", fmt_sig(c, 2)),
    );
    format!(
        "step {}'s {} {} = {}{ci}",
        p.step,
        p.of,
        p.param,
        fmt_sig(p.value, 3)
    )
}

/// "a", "a and b", "a, b and c".
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// What a found set's joint fit fixes only together, in sentences (empty
/// when it fixes each part).
pub fn joint_sentences(j: &JointReading) -> Vec<String> {
    let mut out: Vec<String> = traded_groups(&j.traded)
        .iter()
        .map(|(params, pairs)| {
            let rs: Vec<f64> = pairs.iter().filter_map(|t| t.correlation).collect();
            let lo = rs.iter().fold(f64::INFINITY, |m, r| m.min(r.abs()));
            let hi = rs.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
            let free = rs.len() < pairs.len();
            let r = match (rs.is_empty(), free) {
                (true, _) => "they span a combination the data leave free".to_string(),
                (false, f) => format!(
                    "|r| {} between steps in their joint fit{}",
                    if hi - lo < 5e-4 {
                        format!("= {hi:.3}")
                    } else {
                        format!("from {lo:.3} to {hi:.3}")
                    },
                    if f {
                        ", and a combination the data leave free"
                    } else {
                        ""
                    }
                ),
            };
            let names: Vec<String> = params.iter().map(step_param).collect();
            format!(
                "the data fix a combination of {}, not each ({r})",
                and_list(&names)
            )
        })
        .collect();
    out.extend(j.shared_places.iter().map(|s| {
        let [a, b] = s.steps;
        match s.combined {
            Some(c) => format!(
                "{} carries two laws (steps {a} and {b}): one place, whose {} is the {c} of the two",
                s.places[0],
                if c == "sum" { "load" } else { "multiplier" }
            ),
            None if s.relation == "reciprocal" => format!(
                "the laws of steps {a} ({}) and {b} ({}) are at places the axial model cannot tell apart (reciprocal): together they act as one law",
                s.places[0], s.places[1]
            ),
            // The speed-only places (`interpret::equivalents`).
            None => format!(
                "the laws of steps {a} ({}) and {b} ({}) set the speed only together, as the thrust over the axial drag of body and tail (eq. 11): the data fix their combined effect on it, not each",
                s.places[0], s.places[1]
            ),
        }
    }));
    out.extend(
        j.no_effect_within
            .iter()
            .map(|p| format!("the 95 % interval of {} contains no effect", step_param(p))),
    );
    out
}
