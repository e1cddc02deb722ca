//! `diagnose --write-effect F.toml`: a located correction as a user-effect
//! file in the project's agreed format (`[[effect]]` with `[[effect.param]]`
//! and `[effect.places]`, formulas over quantity ids), fitted values as
//! defaults, ready to rename, refine and load with `--effect-file F.toml`;
//! each carries its base (`base = ["NAME:k=v,...", ...]`), the model it
//! was fitted on top of, which commands add when they load it.
//!
//! A law in one of the model's own quantities (`model_tail_torque_n_m`,
//! ...) is written as it is: the formula language reads the quantity by
//! its id, and a model that holds the law computes it from the effects
//! beneath the law ([`crate::model::columns`]), the model `diagnose`
//! fitted it on, so the written law means the same thing.
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

/// The names the file gives `steps`, in order. A name used beneath a law
/// (a law loaded from an earlier step's file), by an earlier law of the
/// file or by any known effect would clash when both files are loaded, and
/// the base would name the new law itself (its own base then lost,
/// silently): such a law takes the next free `-2`, `-3`, ... of
/// [`effect_name`]. The study's proposals name the laws by these names.
pub fn written_names(steps: &[Located]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for l in steps {
        let beneath = &l.model.effects[..l.model.effects.len().saturating_sub(1)];
        let stem = effect_name(l);
        let taken = |n: &str| {
            names.iter().any(|w| w == n)
                || beneath.iter().any(|e| e.name() == n)
                || crate::effects::by_name(n).is_some()
        };
        let mut name = stem.clone();
        let mut k = 1;
        while taken(&name) {
            k += 1;
            name = format!("{stem}-{k}");
        }
        names.push(name);
    }
    names
}

/// The effect file for one located correction found on `dataset`.
pub fn to_toml(l: &Located, dataset: &str) -> String {
    to_toml_steps(std::slice::from_ref(l), dataset)
}

/// The effect file for located corrections found in order by the
/// search over subsets, each with its base: the model it was fitted on top
/// of, where an earlier law of the file is named by its name in the file
/// (and a second law at one place gets `-2`, ...).
pub fn to_toml_steps(steps: &[Located], dataset: &str) -> String {
    let written = written_names(steps);
    let mut names: Vec<(&str, String)> = Vec::new();
    let mut specs = Vec::new();
    let mut header =
        String::from("# Corrections located by `swimbot diagnose`, in the order found:\n");
    for (i, (l, name)) in steps.iter().zip(written).enumerate() {
        // The model it was fitted on top of, machine-readable: every effect
        // beneath it at full precision, in order.
        let mut beneath = l.model.clone();
        beneath.effects.pop();
        let base = beneath
            .effects
            .iter()
            .map(
                |e| match names.iter().find(|(internal, _)| *internal == e.name()) {
                    Some((_, written)) => exact_spec(e).replacen(e.name(), written, 1),
                    None => exact_spec(e),
                },
            )
            .collect::<Vec<_>>();
        header.push_str(&format!(
            "# {}. {}: {}\n#    MARE {:.2} %, cross-validated {:.2} %, explained fraction {}; fitted on top of: {} (the `base` field: a command that loads it adds what is missing).\n",
            i + 1,
            name,
            l.describe(),
            100.0 * l.score.mare,
            100.0 * l.score.cv_mare,
            l.explained_fraction
                .map(|f| format!("{f:.3}"))
                .unwrap_or_else(|| "n/a".into()),
            beneath.describe()
        ));
        specs.push(spec_of(l, name.clone(), base, dataset));
        names.push((crate::effects::Effect::name(&*l.correction), name));
    }
    if steps.iter().any(|l| {
        l.correction
            .feature
            .as_ref()
            .and_then(crate::data::Feature::quantity)
            .is_some_and(crate::data::model_quantities::is_model_quantity)
    }) {
        header.push_str(
            "# A `model_*` name in a formula is the model's own quantity (`swimbot effects --quantities`): a command that loads the law computes it from the model beneath the law (its base, and any effect listed before it), once per case, as `diagnose` did.\n",
        );
    }
    header.push_str("# Rename them, refine the formulas, and use them with --effect-file FILE.\n");
    format!("{header}{}", formula::to_toml(&specs))
}

fn spec_of(l: &Located, name: String, base: Vec<String>, dataset: &str) -> UserEffectSpec {
    let specs = crate::effects::Effect::params(&*l.correction);
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
    UserEffectSpec {
        name,
        statement: l.interpretation.clone(),
        reference: format!("located by swimbot diagnose on {dataset}"),
        applies_to: Some("all cases".into()),
        params,
        places: vec![(place, l.formula.clone())],
        base,
    }
}

/// `name:k=v,...` with every value at full precision, so that the base a
/// command applies is the model the law was fitted on, not a rounding of it.
pub fn exact_spec(e: &crate::effects::EffectInstance) -> String {
    let params = e.effect.params();
    if params.is_empty() {
        return e.name().to_string();
    }
    let kv: Vec<String> = params
        .iter()
        .zip(&e.values)
        .map(|(p, v)| format!("{}={v}", p.name))
        .collect();
    format!("{}:{}", e.name(), kv.join(","))
}
