//! `diagnose --write-effect F.toml`: a located correction as a user-effect
//! file in the project's agreed format (`[[effect]]` with `[[effect.param]]`
//! and `[effect.places]`, formulas over quantity ids), fitted values as
//! defaults, ready to rename, refine and load with `--effect-file F.toml`.
//!
//! Serialised by the effect file's own writer
//! ([`crate::effects::formula::to_toml`]), so what is written is exactly
//! what the loader reads back.

use super::Located;
use crate::effects::formula::{self, UserEffectSpec, UserParam};
use crate::effects::place::Place;

/// `located-tail-c-n`: kebab-case, `[a-z][a-z0-9-]*`, no catalogue clash.
pub fn effect_name(l: &Located) -> String {
    let mut s = String::from("located-");
    for ch in l.place.chars() {
        s.push(if ch.is_ascii_alphanumeric() {
            ch.to_ascii_lowercase()
        } else {
            '-'
        });
    }
    s
}

/// The effect file for one located correction found on `dataset`.
pub fn to_toml(l: &Located, dataset: &str) -> String {
    let specs = crate::effects::Effect::params(l.correction);
    let params = specs
        .iter()
        .zip(&l.params)
        .map(|(s, e)| UserParam {
            name: s.name.to_string(),
            unit: s.unit.to_string(),
            default: e.value,
            min: s.min,
            max: s.max,
            free: true,
            doc: match e.ci95 {
                Some(ci) => format!(
                    "{} (fitted {} at 95 %)",
                    s.doc,
                    crate::format::fmt_estimate(e.value, Some(ci))
                ),
                None => format!(
                    "{} (fitted {}, CI not identifiable)",
                    s.doc,
                    crate::format::fmt_sig(e.value, 4)
                ),
            },
        })
        .collect();
    let place = Place::from_name(l.place).expect("a located correction acts at a known place");
    let spec = UserEffectSpec {
        name: effect_name(l),
        statement: l.interpretation.clone(),
        reference: format!("located by swimbot diagnose on {dataset}"),
        applies_to: Some("all cases".into()),
        params,
        places: vec![(place, l.formula.clone())],
    };
    let body = formula::to_toml(&[spec]);
    // The model it was fitted on top of: use it with the same effects.
    let mut beneath = l.model.clone();
    beneath.effects.pop();
    format!(
        "# A correction located by `swimbot diagnose`: {}\n# MARE {:.2} %, cross-validated {:.2} %, explained fraction of the excess chi-square {}.\n# Fitted on top of: {}.\n# Rename it, refine the formula, and use it with --effect-file FILE.\n{body}",
        l.describe(),
        100.0 * l.mare,
        100.0 * l.cv_mare,
        l.explained_fraction
            .map(|f| format!("{f:.3}"))
            .unwrap_or_else(|| "n/a".into()),
        beneath.describe()
    )
}
