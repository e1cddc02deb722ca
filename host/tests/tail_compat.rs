//! Every catalogue effect against every tail model: a
//! combination is either refused before any work or the effect changes the
//! prediction, and every refused one is shown to be a true no-op (a
//! local-drag effect changes nothing with a non-local tail) or to ignore
//! the tail model asked for (an effect that replaces the tail matrix
//! gives the same answer whatever tail model is under it). The table in
//! docs/limits.md is this test's outcome (`--nocapture` prints it).
//!
//! The two costly effects (wall-resolved solves of seconds each) are
//! checked here for their refusals only; their action is tested in
//! `nonlocal_effects` and `axisym`.

use swimbot::data::Case;
use swimbot::effects::{EffectInstance, CATALOGUE};
use swimbot::model::{Model, TailMethod};

fn tails() -> Vec<(&'static str, Model)> {
    let with = |method| Model {
        tail_method: method,
        ..Model::base()
    };
    let nonlocal_effect =
        EffectInstance::default_of(swimbot::effects::by_name("nonlocal-tail").unwrap());
    vec![
        ("rft", with(TailMethod::Exact)),
        (
            "rft quadrature",
            with(TailMethod::Quadrature {
                nodes_per_wavelength: 100,
            }),
        ),
        (
            "sbt",
            with(TailMethod::SlenderBody {
                segments_per_turn: 12,
            }),
        ),
        (
            "stokeslets",
            with(TailMethod::Stokeslets {
                segments_per_turn: 12,
            }),
        ),
        (
            "rft + nonlocal-tail",
            Model::base().with_effect(nonlocal_effect),
        ),
    ]
}

/// The effect with every free parameter half-way from its default to a
/// bound (some defaults are neutral: `body-correction` at 1).
fn moved(effect: &'static dyn swimbot::effects::Effect) -> EffectInstance {
    let mut e = EffectInstance::default_of(effect);
    for (v, p) in e.values.iter_mut().zip(effect.params()) {
        if p.free {
            let to = if p.max > p.default { p.max } else { p.min };
            *v = p.default + 0.5 * (to - p.default);
        }
    }
    e
}

fn rel_change(a: &Model, b: &Model, case: &Case) -> f64 {
    let (p, q) = (a.predict(case).unwrap(), b.predict(case).unwrap());
    ((p.u_mm_s - q.u_mm_s) / q.u_mm_s)
        .abs()
        .max(((p.omega_body_hz - q.omega_body_hz) / q.omega_body_hz).abs())
}

#[test]
fn every_catalogue_effect_acts_or_is_refused_with_every_tail_model() {
    // Tail #1: long enough against the tube for `wall-contact` to apply.
    let case = swimbot::data::paper().cases[0].clone();
    let plain = Model::base();
    let mut table = Vec::new();
    for effect in CATALOGUE {
        let mut row = vec![effect.name().to_string()];
        for (tail_name, tail) in tails() {
            if tail.effects.iter().any(|e| e.name() == effect.name()) {
                row.push("(in the model)".into());
                continue;
            }
            let with = tail.clone().with_effect(moved(*effect));
            let refused = with.check_tail_compat().is_err();
            let cell = if refused {
                if effect.costly() {
                    "refused"
                } else if effect.acts_on_local_drag() {
                    let change = rel_change(&with, &tail, &case);
                    assert!(
                        change < 1e-12,
                        "{} with {tail_name}: {change}",
                        effect.name()
                    );
                    "refused (no-op)"
                } else {
                    // It replaces the tail: the tail model under it is ignored.
                    let on_rft = plain
                        .clone()
                        .with_effect(EffectInstance::default_of(*effect));
                    let change = rel_change(&with, &on_rft, &case);
                    assert!(
                        change < 1e-12,
                        "{} with {tail_name}: {change}",
                        effect.name()
                    );
                    "refused (tail model ignored)"
                }
            } else if effect.costly() {
                "acts (not solved here)"
            } else {
                let change = rel_change(&with, &tail, &case);
                assert!(
                    change > 1e-6,
                    "{} with {tail_name} is accepted but changes U and Omega_b by {change:e}",
                    effect.name()
                );
                "acts"
            };
            row.push(cell.into());
        }
        table.push(row);
    }
    for row in &table {
        println!("| {} |", row.join(" | "));
    }
    // The refusals the module promises, by name.
    let cell = |name: &str, col: usize| -> String {
        table.iter().find(|r| r[0] == name).unwrap()[col].clone()
    };
    for col in 3..=5 {
        assert!(cell("tail-confinement", col).starts_with("refused"));
        assert!(cell("tail-confinement-stokeslets", col).starts_with("refused"));
    }
    assert_eq!(cell("tail-confinement", 1), "acts");
    assert_eq!(cell("tail-confinement", 2), "acts");
    assert!(cell("nonlocal-tail", 3).starts_with("refused"));
    assert!(cell("nonlocal-tail", 4).starts_with("refused"));
}
