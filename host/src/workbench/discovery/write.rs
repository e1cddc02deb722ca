//! `diagnose --write-effect F.toml`: a located correction as a user-effect
//! file in the project's agreed format (`[[effect]]` with `[[effect.param]]`
//! and `[effect.places]`, formulas over quantity ids), fitted values as
//! defaults, ready to rename, refine and load with `--effects F.toml`.
//!
//! Serialised with the `toml` crate from plain structs, so quoting and
//! number formats are TOML's own.

use super::Located;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Serialize)]
struct File {
    effect: Vec<EffectToml>,
}

#[derive(Serialize)]
struct EffectToml {
    name: String,
    statement: String,
    reference: String,
    applies_to: String,
    param: Vec<ParamToml>,
    places: BTreeMap<String, String>,
}

#[derive(Serialize)]
struct ParamToml {
    name: String,
    unit: String,
    default: f64,
    min: f64,
    max: f64,
    free: bool,
    doc: String,
}

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
    let param = specs
        .iter()
        .zip(&l.params)
        .map(|(s, e)| ParamToml {
            name: s.name.to_string(),
            unit: s.unit.to_string(),
            default: e.value,
            min: s.min,
            max: s.max,
            free: true,
            doc: match e.ci95 {
                Some(ci) => format!("{} (fitted {} ± {} at 95 %)", s.doc, e.value, ci),
                None => format!("{} (fitted {}, CI not identifiable)", s.doc, e.value),
            },
        })
        .collect();
    let file = File {
        effect: vec![EffectToml {
            name: effect_name(l),
            statement: l.interpretation.clone(),
            reference: format!("located by swimbot diagnose on {dataset}"),
            applies_to: "all cases".into(),
            param,
            places: BTreeMap::from([(l.place.to_string(), l.formula.clone())]),
        }],
    };
    let body = toml::to_string(&file).expect("plain structs serialise");
    // The model it was fitted on top of: use it with the same effects.
    let mut beneath = l.model.clone();
    beneath.effects.pop();
    format!(
        "# A correction located by `swimbot diagnose`: {}\n# MARE {:.2} %, cross-validated {:.2} %, explained fraction of the excess chi-square {}.\n# Fitted on top of: {}.\n# Rename it, refine the formula, and use it with --effects FILE.\n{body}",
        l.describe(),
        100.0 * l.mare,
        100.0 * l.cv_mare,
        l.explained_fraction
            .map(|f| format!("{f:.3}"))
            .unwrap_or_else(|| "n/a".into()),
        beneath.describe()
    )
}
