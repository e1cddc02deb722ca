//! Which effects act with which tail hydrodynamics, and the combinations
//! that would silently change nothing (refused before any work).
//!
//! The tail matrix `B_t` (eq. 3) is built in two steps
//! ([`crate::model::Model::predict`]): local drag coefficients `c_t`, `c_n`
//! (eqs. 4-7), on which [`Effect::local_drag`] acts, are integrated along
//! the helix by local resistive-force theory; then [`Effect::tail`] acts on
//! the matrix. Two things bypass the first step:
//!
//! - a non-local tail model (`--tail-model sbt|stokeslets`: Johnson's
//!   slender-body theory, regularized Stokeslets) solves the Stokes flow of
//!   the whole wire and has no local coefficients at all;
//! - an effect that replaces the tail matrix by its own non-local solve
//!   ([`Effect::replaces_tail`]: `nonlocal-tail`,
//!   `tail-confinement-stokeslets`, and so `--preset physics`).
//!
//! So, refused (each with the effect's name, why, and what to use):
//!
//! 1. an effect at the local drag coefficients ([`Effect::acts_on_local_drag`]:
//!    `tail-confinement`, a user effect at `tail.c_t|c_n|viscosity`) with a
//!    non-local tail of either kind: it would change nothing;
//! 2. an effect that replaces the tail matrix with a non-local
//!    `--tail-model`: the tail model would be ignored;
//! 3. two effects that replace the tail matrix: only the last would act;
//!    likewise two that replace the body's axial resistances
//!    ([`Effect::replaces_body`]: `body-confinement`,
//!    `body-confinement-exact`, the latter in `--preset physics`).
//!
//! Every other catalogue effect acts at the tail matrix (`coupler`), the
//! body matrix or the force balance, which every tail model has.
//! docs/limits.md has the table of catalogue effects against tail models,
//! and `tests/tail_compat` checks it by prediction.
//!
//! References: the paper's eqs. 3-7 (local RFT); G. J. Hancock, Proc. R.
//! Soc. A 217 (1953) 96 and J. Lighthill, SIAM Rev. 18 (1976) 161 (the
//! local drag coefficients exist only in the local theory).

use super::Effect;

/// What computes the tail matrix before the effects act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TailModel {
    /// Local RFT from drag coefficients (closed form or quadrature).
    Local,
    /// A non-local model of the whole wire, named as `--tail-model` spells it.
    NonLocal(&'static str),
}

/// The first combination of `effects` (in the model's order) that cannot
/// act with `tail`: the effect, why, and what to use.
pub fn check(tail: TailModel, effects: &[&dyn Effect]) -> Result<(), TailConflict> {
    for (i, e) in effects.iter().enumerate() {
        let others: Vec<&dyn Effect> = effects
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, o)| *o)
            .collect();
        if let Some(why) = conflict(*e, &others, tail) {
            return Err(why);
        }
    }
    Ok(())
}

/// Why `effect` cannot act beside `others` with `tail`; `None` when it acts.
pub fn conflict(
    effect: &dyn Effect,
    others: &[&dyn Effect],
    tail: TailModel,
) -> Option<TailConflict> {
    let replacer = others.iter().find(|o| o.replaces_tail());
    if effect.acts_on_local_drag() {
        if let TailModel::NonLocal(tail) = tail {
            return Some(TailConflict::LocalDragWithNonLocalTail {
                tail,
                effect: describe(effect),
            });
        }
        if let Some(r) = replacer {
            return Some(TailConflict::LocalDragWithTailReplaced {
                effect: describe(effect),
                replacer: r.name().to_string(),
            });
        }
    }
    if effect.replaces_body() {
        if let Some(r) = others.iter().find(|o| o.replaces_body()) {
            return Some(TailConflict::BodyReplacedTwice {
                first: effect.name().to_string(),
                second: r.name().to_string(),
            });
        }
    }
    if effect.replaces_tail() {
        if let TailModel::NonLocal(tail) = tail {
            return Some(TailConflict::TailReplacedWithNonLocalTail {
                tail,
                effect: effect.name().to_string(),
            });
        }
        if let Some(r) = replacer {
            return Some(TailConflict::TailReplacedTwice {
                first: effect.name().to_string(),
                second: r.name().to_string(),
            });
        }
    }
    None
}

/// Effects that cannot act together, or with the tail model: the names as
/// data, the sentence saying why and what to use instead.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TailConflict {
    /// A local drag effect (`effect`: its description) with a non-local
    /// tail model (`tail`, as `--tail-model` spells it).
    #[error(
        "--tail-model {tail}: {effect}, a local drag coefficient of resistive-force theory, \
         which the non-local tail models do not have (it would change nothing); \
         use --tail-model rft with it, or an effect at the tail matrix{INSTEAD}"
    )]
    LocalDragWithNonLocalTail { tail: &'static str, effect: String },
    /// A local drag effect beside an effect that replaces the tail matrix.
    #[error(
        "{effect}, a local drag coefficient of resistive-force theory, but effect `{replacer}` replaces \
         the whole tail matrix by its own non-local solve (it would change nothing); \
         give one of the two{INSTEAD}"
    )]
    LocalDragWithTailReplaced { effect: String, replacer: String },
    #[error(
        "effects `{first}` and `{second}` both replace the body's axial resistances: only the one \
         applied last would act; give one of them"
    )]
    BodyReplacedTwice { first: String, second: String },
    #[error(
        "--tail-model {tail}: effect `{effect}` replaces the tail matrix by its own non-local solve, \
         so the tail model would be ignored; drop --tail-model {tail} (the effect already \
         includes the helix's non-local hydrodynamics) or drop the effect"
    )]
    TailReplacedWithNonLocalTail { tail: &'static str, effect: String },
    #[error(
        "effects `{first}` and `{second}` both replace the tail matrix by a non-local solve: only the \
         one applied last would act; give one of them (`tail-confinement-stokeslets` \
         includes the helix's non-local hydrodynamics and the tube wall)"
    )]
    TailReplacedTwice { first: String, second: String },
}

const INSTEAD: &str = " (`tail-confinement-stokeslets` resolves the tube wall around the \
    non-local tail; a user effect can act at `tail.drag`, `tail.thrust` or `tail.torque`)";

/// "effect `x` acts on c_t, c_n" or, for a user effect, "effect `x` (FILE)
/// acts at `tail.c_t`".
fn describe(effect: &dyn Effect) -> String {
    match effect.as_formula() {
        Some(u) => {
            let place = u
                .spec()
                .places
                .iter()
                .find(|(p, _)| p.is_local_drag())
                .map_or("tail.c_t".to_string(), |(p, _)| p.name().to_string());
            let file = if u.source().is_empty() {
                String::new()
            } else {
                format!(" ({})", u.source())
            };
            format!("effect `{}`{file} acts at `{place}`", effect.name())
        }
        None => format!("effect `{}` acts on the tail's c_t and c_n", effect.name()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{by_name, CATALOGUE};

    fn e(name: &str) -> &'static dyn Effect {
        by_name(name).unwrap()
    }

    #[test]
    fn local_drag_effects_are_refused_with_either_kind_of_non_local_tail() {
        let tc = e("tail-confinement");
        assert!(check(TailModel::Local, &[tc]).is_ok());
        let err = check(TailModel::NonLocal("sbt"), &[tc])
            .unwrap_err()
            .to_string();
        assert!(err.contains("`tail-confinement`") && err.contains("--tail-model sbt"));
        let err = check(TailModel::Local, &[e("tail-confinement-stokeslets"), tc])
            .unwrap_err()
            .to_string();
        assert!(err.contains("`tail-confinement`") && err.contains("replaces"));
    }

    #[test]
    fn a_replaced_tail_model_and_two_replacing_effects_are_refused() {
        let (nl, tube) = (e("nonlocal-tail"), e("tail-confinement-stokeslets"));
        assert!(check(TailModel::Local, &[nl]).is_ok());
        assert!(check(TailModel::NonLocal("stokeslets"), &[tube])
            .unwrap_err()
            .to_string()
            .contains("would be ignored"));
        assert!(check(TailModel::Local, &[nl, tube])
            .unwrap_err()
            .to_string()
            .contains("both replace"));
    }

    #[test]
    fn two_body_replacing_effects_are_refused() {
        let (approx, exact) = (e("body-confinement"), e("body-confinement-exact"));
        assert!(check(TailModel::Local, &[approx]).is_ok());
        let err = check(TailModel::Local, &[exact, approx])
            .unwrap_err()
            .to_string();
        assert!(err.contains("both replace the body"), "{err}");
    }

    #[test]
    fn every_other_catalogue_effect_acts_with_every_tail() {
        for c in CATALOGUE {
            if c.acts_on_local_drag() || c.replaces_tail() {
                continue;
            }
            assert!(check(TailModel::Local, &[*c, e("nonlocal-tail")]).is_ok());
            assert!(
                check(TailModel::NonLocal("sbt"), &[*c]).is_ok(),
                "{}",
                c.name()
            );
        }
    }
}
