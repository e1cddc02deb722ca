//! Physical effects: the open extension point of the model.
//!
//! An effect changes the base RFT model (paper eqs. 1-11) in one physically
//! stated way, at one or more of four stages of [`crate::model::Model::predict`]:
//!
//! 1. [`Effect::local_drag`]: the tail's local coefficients `c_t`, `c_n`;
//! 2. [`Effect::tail`]: the integrated tail matrix `B_t`;
//! 3. [`Effect::body`]: the body matrix `B_b`;
//! 4. [`Effect::balance`]: the force balance itself: extra resistances on
//!    the robot's velocity, external loads, the tail's kinematics.
//!
//! Effects are stateless values; their parameter values travel beside them
//! in an [`EffectInstance`], so a fitter can vary them freely.
//!
//! ## Adding an effect
//! Write one file in this folder with a unit struct implementing [`Effect`],
//! declare it (`mod your_file;`) and add one line (`&your_file::YourEffect,`)
//! to [`CATALOGUE`]. The shortest catalogue effects are complete examples to
//! copy: `body_correction.rs` (two free factors at the body stage) and
//! `buoyancy.rs` (a load at the force balance, with an applicability rule).
//! Without recompiling: state the effect as formulas in an effects file
//! (docs/effects-format.md, [`formula`]) and pass `--effect-file FILE.toml`;
//! the command's [`Catalogue`] then knows it too.

mod backflow;
mod body_confinement;
mod body_confinement_exact;
mod body_correction;
mod buoyancy;
mod catalogue;
pub mod correction;
mod coupler;
mod error;
pub mod expr;
mod expr_lex;
mod expr_parse;
pub mod formula;
mod handle;
mod motor_frame;
mod nonlocal_tail;
pub mod place;
mod spec;
pub mod tail_compat;
mod tail_confinement;
mod toml_position;
mod tube_tail;
pub mod user_file;
mod wall_contact;

pub use catalogue::{Catalogue, RegistryError};
pub use error::{EffectError, UnusablePlace};
pub use handle::EffectRef;
pub use spec::{parse_effect_list, parse_effect_spec, EffectSpecError};

use crate::data::Case;
use crate::physics::coefficients::LocalDrag;
use crate::physics::solve::ForceBalance;
use nalgebra::Matrix6;
use std::borrow::Cow;

/// Every effect the model knows, in the order `swimbot effects` lists them.
pub static CATALOGUE: &[&dyn Effect] = &[
    &backflow::Backflow,
    &backflow::BackflowObserved,
    &body_correction::BodyCorrection,
    &body_confinement::BodyConfinement,
    &tail_confinement::TailConfinement,
    &wall_contact::WallContact,
    &motor_frame::MotorFrame,
    &buoyancy::Buoyancy,
    &coupler::Coupler,
    &nonlocal_tail::NonlocalTail,
    &tube_tail::TubeTail,
    &body_confinement_exact::BodyConfinementExact,
];

/// Look a compiled-in effect up by its command-line name (user effects:
/// [`Catalogue::by_name`]).
pub fn by_name(name: &str) -> Option<&'static dyn Effect> {
    CATALOGUE.iter().copied().find(|e| e.name() == name)
}

/// One parameter of an effect.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParamSpec {
    pub name: Cow<'static, str>,
    pub unit: Cow<'static, str>,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    /// Free parameters are fitted by `diagnose` and `fit`; fixed ones are
    /// settings (e.g. an applicability threshold) a user may still change.
    pub free: bool,
    pub doc: Cow<'static, str>,
}

/// A physically stated change to the model.
pub trait Effect: Send + Sync {
    /// Command-line name, kebab-case.
    fn name(&self) -> &str;
    /// The physics in one line.
    fn statement(&self) -> &str;
    /// Where the physics comes from.
    fn reference(&self) -> &str;
    /// Parameters with units, defaults and bounds (none where physics fixes it).
    fn params(&self) -> &[ParamSpec] {
        &[]
    }
    /// Which cases the effect acts on (all by default).
    fn applies_to(&self, _case: &Case, _p: &[f64]) -> bool {
        true
    }
    /// Whether `diagnose` may propose it (false for variants that only
    /// reproduce the paper's procedure, such as `backflow-observed`).
    fn candidate(&self) -> bool {
        true
    }
    /// Too expensive for the default diagnosis (seconds per case, e.g. a
    /// discretised tube wall); `diagnose --nonlocal` includes it.
    fn costly(&self) -> bool {
        false
    }
    /// Human-readable applicability, for `swimbot effects`.
    fn applicability(&self) -> &str {
        "all cases"
    }
    /// Effects that replace a resistance (0) run before those that scale or
    /// add to it (1, the default), whatever order the user lists them in.
    fn order(&self) -> u8 {
        1
    }
    /// Whether the effect can act on `case` with values `p`, checked by the
    /// model before any stage runs: stages that cannot fail themselves rely
    /// on it (a user formula giving a non-positive multiplier, say), so a bad
    /// value surfaces as an error naming the case and the effect, never as a
    /// NaN prediction.
    fn check(&self, _p: &[f64], _case: &Case) -> Result<(), EffectError> {
        Ok(())
    }
    /// Whether the effect acts on the tail's local drag coefficients
    /// ([`Effect::local_drag`]), which only local RFT has: with a
    /// non-local tail it would change nothing ([`tail_compat`]).
    fn acts_on_local_drag(&self) -> bool {
        false
    }
    /// Whether [`Effect::tail`] replaces the tail matrix by a non-local
    /// solve of its own, deciding the tail's hydrodynamics ([`tail_compat`]).
    fn replaces_tail(&self) -> bool {
        false
    }
    /// Whether [`Effect::body`] replaces the body's axial resistances by
    /// its own (a confined-body law or solve): two such effects cannot
    /// both act ([`tail_compat`]).
    fn replaces_body(&self) -> bool {
        false
    }
    /// Whether a law of the effect reads one of the model's own quantities
    /// ([`crate::data::model_quantities`]): the model then computes them
    /// from the effects beneath it ([`crate::model::columns`]).
    fn reads_model_quantities(&self) -> bool {
        false
    }
    /// The effect's definition as formulas, for a user effect (its places
    /// and the file it came from name it in messages).
    fn as_formula(&self) -> Option<&formula::FormulaEffect> {
        None
    }
    fn local_drag(&self, _p: &[f64], _case: &Case, _drag: &mut LocalDrag) {}
    /// Errors (e.g. a failed non-local solve) stop the prediction.
    fn tail(&self, _p: &[f64], _case: &Case, _tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        Ok(())
    }
    fn body(&self, _p: &[f64], _case: &Case, _body: &mut Matrix6<f64>) {}
    fn balance(&self, _p: &[f64], _case: &Case, _fb: &mut ForceBalance) {}
}

/// An effect with its parameter values.
#[derive(Clone)]
pub struct EffectInstance {
    pub effect: EffectRef,
    pub values: Vec<f64>,
}

impl EffectInstance {
    /// The effect at its default parameters.
    pub fn default_of(effect: impl Into<EffectRef>) -> Self {
        let effect = effect.into();
        let values = effect.params().iter().map(|p| p.default).collect();
        EffectInstance { effect, values }
    }

    pub fn name(&self) -> &str {
        self.effect.name()
    }

    /// Indices of the free parameters.
    pub fn free_indices(&self) -> Vec<usize> {
        (0..self.values.len())
            .filter(|&i| self.effect.params()[i].free)
            .collect()
    }

    /// `name:k=v,...` with every parameter, as the command line takes it.
    pub fn spec(&self) -> String {
        let params = self.effect.params();
        if params.is_empty() {
            return self.name().to_string();
        }
        let kv: Vec<String> = params
            .iter()
            .zip(&self.values)
            .map(|(p, v)| format!("{}={}", p.name, crate::format::fmt_trim(*v, 4)))
            .collect();
        format!("{}:{}", self.name(), kv.join(","))
    }
}

impl std::fmt::Debug for EffectInstance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.spec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_names_are_unique_kebab_case_and_documented() {
        for (i, e) in CATALOGUE.iter().enumerate() {
            assert!(
                e.name().chars().all(|c| c.is_ascii_lowercase() || c == '-'),
                "{}",
                e.name()
            );
            assert!(
                CATALOGUE[..i].iter().all(|o| o.name() != e.name()),
                "duplicate {}",
                e.name()
            );
            assert!(!e.statement().is_empty() && !e.reference().is_empty());
            for p in e.params() {
                assert!(
                    p.min <= p.default && p.default <= p.max,
                    "{}: {}",
                    e.name(),
                    p.name
                );
                assert!(!p.unit.is_empty() && !p.doc.is_empty());
            }
        }
    }

    #[test]
    fn every_catalogue_effect_is_registered() {
        for name in [
            "backflow",
            "body-correction",
            "body-confinement",
            "tail-confinement",
            "wall-contact",
            "motor-frame",
            "buoyancy",
            "coupler",
        ] {
            assert!(by_name(name).is_some(), "missing {name}");
        }
    }
}
