//! Named model presets: the plain base model and the paper's two calibrated
//! models (section III, Table III).

use super::Model;
use crate::effects::{parse_effect_spec, EffectInstance};
use crate::physics::coefficients::CoefficientSet;

/// `(name, description)` of every preset.
pub const PRESETS: &[(&str, &str)] = &[
    ("base", "Gray-Hancock RFT, spheroid body, no effects"),
    ("paper", "the paper's model: Gray-Hancock + backflow (observed U) + body-correction(16, 1.4)"),
    (
        "paper-lighthill",
        "the paper's model with Lighthill's coefficients: backflow (observed U) + body-correction(4.5, 3.4)",
    ),
];

fn effect(spec: &str) -> EffectInstance {
    parse_effect_spec(spec).expect("preset effect specs are valid")
}

/// A preset by name.
pub fn preset(name: &str) -> Option<Model> {
    let m = Model::base();
    match name {
        "base" => Some(m),
        "paper" => Some(
            m.with_effect(effect("backflow-observed"))
                .with_effect(effect("body-correction:translation=16,rotation=1.4")),
        ),
        "paper-lighthill" => Some(
            m.with_coefficients(CoefficientSet::Lighthill)
                .with_effect(effect("backflow-observed"))
                .with_effect(effect("body-correction:translation=4.5,rotation=3.4")),
        ),
        _ => None,
    }
}
