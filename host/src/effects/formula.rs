//! User effects stated as formulas: a [`UserEffectSpec`] (what an effects
//! file holds, docs/effects-format.md) compiled into a [`FormulaEffect`]
//! that implements [`Effect`] like any catalogue entry.
//!
//! Each place of the effect (host/src/effects/place.rs) carries a formula
//! over the effect's parameters and the case quantities
//! ([`crate::data::quantities`]); at a multiplier place the formula is the
//! multiplier `m` (finite, within 1e-6..=1e6, see `data::limits`), at `load.force` a force in mN, at
//! `load.torque` a torque in µN m. The formula acts at the stage of
//! [`crate::model::Model::predict`] its place belongs to, through
//! [`Place::apply_local_drag`] and its siblings, so a user effect changes
//! the model exactly as a hand-written effect acting there would.
//!
//! Formulas are compiled once ([`super::expr`]) with parameters bound by
//! index; evaluating one is a walk of a few tree nodes per case.
//!
//! A user effect owns its names and parameter table; models share it
//! through an [`super::EffectRef`], so it is freed with the last of them.

use super::error::UnusablePlace;
use super::expr::{Expr, ExprError};
use super::place::Place;
use super::{Effect, EffectError, ParamSpec};
use crate::data::limits::{echo, show};
use crate::data::Case;
use crate::physics::coefficients::LocalDrag;
use crate::physics::solve::ForceBalance;
use nalgebra::Matrix6;

/// One parameter of a user effect.
#[derive(Debug, Clone, PartialEq)]
pub struct UserParam {
    pub name: String,
    pub unit: String,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    pub free: bool,
    pub doc: String,
}

/// A user effect as written in an effects file.
#[derive(Debug, Clone, PartialEq)]
pub struct UserEffectSpec {
    pub name: String,
    pub statement: String,
    pub reference: String,
    /// Free text for `swimbot effects`; "all cases" when absent.
    pub applies_to: Option<String>,
    pub params: Vec<UserParam>,
    /// Each place at most once, with its formula.
    pub places: Vec<(Place, String)>,
    /// The effects (`NAME:k=v,...`, in order) this one was fitted on top
    /// of; commands add those missing from the model when they load it.
    pub base: Vec<String>,
}

/// Which stage of the prediction a place acts in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    LocalDrag,
    Tail,
    Body,
    Balance,
}

fn stage(place: Place) -> Stage {
    match place {
        Place::TailTangential | Place::TailNormal | Place::TailViscosity => Stage::LocalDrag,
        Place::TailDrag | Place::TailThrust | Place::TailTorque => Stage::Tail,
        Place::BodyTranslation | Place::BodyRotation => Stage::Body,
        Place::LoadForce | Place::LoadTorque | Place::DriveRate => Stage::Balance,
    }
}

/// A compiled user effect.
pub struct FormulaEffect {
    spec: UserEffectSpec,
    /// Where it was loaded from ("" when built in memory).
    source: String,
    applies_to: String,
    params: Vec<ParamSpec>,
    places: Vec<(Place, Expr)>,
    /// Whether a formula reads a model quantity (computed once here).
    reads_model: bool,
}

/// A place's formula that does not compile.
#[derive(Debug, Clone, PartialEq)]
pub struct FormulaError {
    pub place: Place,
    pub error: ExprError,
}

impl FormulaEffect {
    /// Compile `spec`; `source` names its file for listings and messages.
    /// The spec's other rules (names, bounds) are checked by the loader
    /// ([`super::user_file`]); here only the formulas can fail.
    pub fn new(spec: UserEffectSpec, source: &str) -> Result<FormulaEffect, FormulaError> {
        let names: Vec<&str> = spec.params.iter().map(|p| p.name.as_str()).collect();
        let places = spec
            .places
            .iter()
            .map(|(place, text)| {
                Expr::parse(text, &names)
                    .map(|e| (*place, e))
                    .map_err(|error| FormulaError {
                        place: *place,
                        error,
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let params: Vec<ParamSpec> = spec
            .params
            .iter()
            .map(|p| ParamSpec {
                name: p.name.clone().into(),
                unit: p.unit.clone().into(),
                default: p.default,
                min: p.min,
                max: p.max,
                free: p.free,
                doc: p.doc.clone().into(),
            })
            .collect();
        let reads_model = places.iter().any(|(_, e)| {
            e.quantities_used()
                .iter()
                .any(|id| id.starts_with(crate::data::model_quantities::PREFIX))
        });
        Ok(FormulaEffect {
            reads_model,
            applies_to: spec.applies_to.as_deref().unwrap_or("all cases").into(),
            params,
            places,
            source: source.to_string(),
            spec,
        })
    }

    pub fn spec(&self) -> &UserEffectSpec {
        &self.spec
    }

    /// The file the effect was loaded from ("" when built in memory).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The value of each place's formula for `case`.
    pub fn values(&self, p: &[f64], case: &Case) -> Vec<(Place, f64)> {
        self.places
            .iter()
            .map(|(place, e)| (*place, e.eval(p, case)))
            .collect()
    }

    fn apply(&self, stage_of: Stage, p: &[f64], case: &Case, mut f: impl FnMut(Place, f64)) {
        for (place, e) in self.places.iter().filter(|(pl, _)| stage(*pl) == stage_of) {
            f(*place, e.eval(p, case));
        }
    }
}

/// Why a place's value is unusable, or `None` when it is fine; the ranges
/// and their reasons are in [`crate::data::limits`].
fn invalid(place: Place, value: f64) -> Option<String> {
    use crate::data::limits::{MAX_USER_LOAD, USER_MULTIPLIER_RANGE};
    if place.is_additive() {
        (!(value.is_finite() && value.abs() <= MAX_USER_LOAD)).then(|| {
            format!(
                "{} must be finite, at most {MAX_USER_LOAD:e} in magnitude",
                place.unit()
            )
        })
    } else {
        let (lo, hi) = USER_MULTIPLIER_RANGE;
        (!(value.is_finite() && (lo..=hi).contains(&value))).then(|| {
            format!(
                "a multiplier must be finite and within [{lo:e}, {hi:e}]: a factor beyond a million is no physical effect and carries the model out of floating-point range"
            )
        })
    }
}

impl Effect for FormulaEffect {
    fn name(&self) -> &str {
        &self.spec.name
    }
    fn statement(&self) -> &str {
        &self.spec.statement
    }
    fn reference(&self) -> &str {
        &self.spec.reference
    }
    fn params(&self) -> &[ParamSpec] {
        &self.params
    }
    fn applicability(&self) -> &str {
        &self.applies_to
    }
    fn as_formula(&self) -> Option<&FormulaEffect> {
        Some(self)
    }

    fn check(&self, p: &[f64], case: &Case) -> Result<(), EffectError> {
        for ((place, e), (_, text)) in self.places.iter().zip(&self.spec.places) {
            let value = e.eval(p, case);
            if let Some(why) = invalid(*place, value) {
                let values: Vec<String> = self
                    .params
                    .iter()
                    .zip(p)
                    .map(|(s, v)| format!("{}={}", s.name, show(*v)))
                    .collect();
                return Err(EffectError::Place(Box::new(UnusablePlace {
                    place: place.to_string(),
                    formula: echo(text),
                    value: show(value),
                    parameters: if values.is_empty() {
                        "no parameters".to_string()
                    } else {
                        values.join(", ")
                    },
                    why,
                    defined_in: (!self.source.is_empty()).then(|| self.source.to_string()),
                })));
            }
        }
        Ok(())
    }

    fn reads_model_quantities(&self) -> bool {
        self.reads_model
    }

    fn acts_on_local_drag(&self) -> bool {
        self.spec.places.iter().any(|(p, _)| p.is_local_drag())
    }

    fn local_drag(&self, p: &[f64], case: &Case, drag: &mut LocalDrag) {
        self.apply(Stage::LocalDrag, p, case, |pl, m| {
            pl.apply_local_drag(m, drag)
        });
    }

    fn tail(&self, p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        self.apply(Stage::Tail, p, case, |pl, m| pl.apply_tail(m, tail));
        Ok(())
    }

    fn body(&self, p: &[f64], case: &Case, body: &mut Matrix6<f64>) {
        self.apply(Stage::Body, p, case, |pl, m| pl.apply_body(m, body));
    }

    fn balance(&self, p: &[f64], case: &Case, fb: &mut ForceBalance) {
        self.apply(Stage::Balance, p, case, |pl, v| pl.apply_balance(v, fb));
    }
}

/// Write specs as an effects file that [`super::user_file::parse`] reads back
/// to the same specs (used by `diagnose --write-effect`).
pub fn to_toml(specs: &[UserEffectSpec]) -> String {
    let s = |x: &str| toml::Value::String(x.to_string()).to_string();
    let f = |x: f64| toml::Value::Float(x).to_string();
    let mut out = String::from("# swimbot user effects (docs/effects-format.md)\n");
    for e in specs {
        out.push_str("\n[[effect]]\n");
        out.push_str(&format!("name = {}\n", s(&e.name)));
        out.push_str(&format!("statement = {}\n", s(&e.statement)));
        out.push_str(&format!("reference = {}\n", s(&e.reference)));
        if let Some(a) = &e.applies_to {
            out.push_str(&format!("applies_to = {}\n", s(a)));
        }
        if !e.base.is_empty() {
            let list: Vec<String> = e.base.iter().map(|b| s(b)).collect();
            out.push_str(&format!("base = [{}]\n", list.join(", ")));
        }
        for p in &e.params {
            out.push_str("\n[[effect.param]]\n");
            out.push_str(&format!("name = {}\n", s(&p.name)));
            out.push_str(&format!("unit = {}\n", s(&p.unit)));
            out.push_str(&format!("default = {}\n", f(p.default)));
            out.push_str(&format!("min = {}\n", f(p.min)));
            out.push_str(&format!("max = {}\n", f(p.max)));
            out.push_str(&format!("free = {}\n", p.free));
            out.push_str(&format!("doc = {}\n", s(&p.doc)));
        }
        out.push_str("\n[effect.places]\n");
        for (place, formula) in &e.places {
            out.push_str(&format!("{} = {}\n", s(place.name()), s(formula)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::user_file::parse;
    use proptest::prelude::*;

    fn spec(places: Vec<(Place, String)>) -> UserEffectSpec {
        UserEffectSpec {
            name: "test-effect".into(),
            statement: "a \"quoted\" statement\nwith a newline".into(),
            reference: "nobody (2026)".into(),
            applies_to: None,
            params: vec![UserParam {
                name: "k".into(),
                unit: "1".into(),
                default: 0.25,
                min: -1.0,
                max: 2.0,
                free: true,
                doc: "strength".into(),
            }],
            places,
            base: vec!["body-correction:translation=25.72,rotation=2.638".into()],
        }
    }

    #[test]
    fn each_place_acts_at_its_own_stage_only() {
        let case = &crate::data::paper().cases[0];
        let e = FormulaEffect::new(
            spec(vec![
                (Place::TailNormal, "1 + k".into()),
                (Place::TailDrag, "2 * (1 + k)".into()),
                (Place::BodyTranslation, "3 + k".into()),
                (Place::LoadForce, "k - 1".into()),
            ]),
            "",
        )
        .unwrap();
        let p = [0.5];
        let mut drag = LocalDrag {
            tangential: 1.0,
            normal: 1.0,
        };
        e.local_drag(&p, case, &mut drag);
        assert_eq!((drag.tangential, drag.normal), (1.0, 1.5));
        let mut tail = Matrix6::identity();
        e.tail(&p, case, &mut tail).unwrap();
        assert_eq!((tail[(0, 0)], tail[(3, 3)]), (3.0, 1.0));
        let mut body = Matrix6::identity();
        e.body(&p, case, &mut body);
        assert_eq!((body[(0, 0)], body[(3, 3)]), (3.5, 1.0));
        let mut fb = ForceBalance::new(body, tail, 2.0);
        e.balance(&p, case, &mut fb);
        assert_eq!((fb.load[0], fb.tail_rate_rad_s), (-0.5e-3, 2.0));
        assert!(e.check(&p, case).is_ok());
        let err = e.check(&[-1.0], case).unwrap_err().to_string();
        assert!(err.contains("tail.c_n") && err.contains("within") && err.contains("k=-1"));
    }

    #[test]
    fn a_load_may_be_negative_but_not_infinite() {
        let case = &crate::data::paper().cases[0];
        let e =
            FormulaEffect::new(spec(vec![(Place::LoadTorque, "k / (k - 1)".into())]), "").unwrap();
        assert!(e.check(&[0.5], case).is_ok());
        assert!(e
            .check(&[1.0], case)
            .unwrap_err()
            .to_string()
            .contains("finite"));
    }

    fn any_place() -> impl Strategy<Value = Place> {
        (0..Place::ALL.len()).prop_map(|i| Place::ALL[i])
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn written_files_read_back_to_the_same_specs(
            default in -1.0f64..2.0,
            width in 1e-6f64..1e6,
            free in any::<bool>(),
            coeff in -1e3f64..1e3,
            places in proptest::collection::btree_set(any_place(), 1..4),
            doc in "[ -~]{0,20}",
            applies in proptest::option::of("[a-z =<>.0-9]{1,12}"),
        ) {
            let mut s = spec(places.into_iter().map(|p| (p, format!("1 + k * {coeff:e} * tail_gap_ratio"))).collect());
            s.params[0].default = default;
            s.params[0].min = default - width;
            s.params[0].max = default + width;
            s.params[0].free = free;
            s.params[0].doc = doc;
            s.applies_to = applies;
            let text = to_toml(std::slice::from_ref(&s));
            let back = parse(&text, "written.toml").map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
            prop_assert_eq!(back, vec![s]);
        }
    }
}
