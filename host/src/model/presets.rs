//! Named model presets: the plain base model, the paper's two calibrated
//! models (section III, Table III), and `physics`, the project's best model
//! with no fitted parameter.
//!
//! `physics` keeps the paper's reading of the recorded f (the tail's rate in
//! the lab frame; `motor-frame` is the named alternative) and replaces every
//! ad-hoc factor by a Stokes solve of the real geometry: the tail as
//! regularized Stokeslets inside the closed tube with a leak-free wall
//! (`tail-confinement-stokeslets`, which includes the helix's non-local
//! self-interaction), the body's profile inside the closed tube by the
//! axisymmetric boundary-integral solver (`body-confinement-exact`, which
//! includes the back-flow of the displaced oil, so `backflow` is not added),
//! and the coupler's drag (`coupler`). Left out, with their measured size:
//! the body-tail hydrodynamic interaction in the tube (it changes U by
//! -0.5 % and Omega_b by -0.1 % for tail #6, docs/tail-in-tube.md). The first run solves each tail in
//! the tube (tens of seconds per tail on 2 cores); the matrices are cached
//! on disk, so later runs take milliseconds.

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
    (
        "physics",
        "no fitted parameter: tail-confinement-stokeslets + body-confinement-exact + coupler (slow on first use, then cached)",
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
        "physics" => Some(
            m.with_effect(effect("tail-confinement-stokeslets"))
                .with_effect(effect("body-confinement-exact"))
                .with_effect(effect("coupler")),
        ),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_preset_builds_and_physics_has_no_free_parameter() {
        for (name, _) in PRESETS {
            assert!(preset(name).is_some(), "{name}");
        }
        let physics = preset("physics").unwrap();
        assert_eq!(physics.effects.len(), 3);
        for e in &physics.effects {
            assert!(
                e.free_indices().is_empty(),
                "{} has a free parameter",
                e.name()
            );
        }
        // the paper's drive: the recorded f is the tail's lab-frame rate
        assert!(physics.effects.iter().all(|e| e.name() != "motor-frame"));
    }
}
