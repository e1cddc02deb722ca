//! A located correction: the model's missing physics stated as a simple law
//! at one place of the model ([`super::place`]), scaling with one case
//! quantity ([`crate::data::quantities`]) or with none (a constant).
//!
//! With `x = g / g_ref` (the feature over a reference value, the dataset's
//! median, so that `k` is dimensionless and its bounds sane), the forms are
//!
//! | form | multiplier place | load place (mN, µN m) |
//! |---|---|---|
//! | `constant` | `m = k` | `k` |
//! | `linear` | `m = 1 + k x` | — |
//! | `power` | `m = 1 + k x^p` | — |
//! | `proportional` | `m = k x` | `k x` |
//! | `power-law` | `m = k x^p` | `k x^p` |
//! | `affine` | — | `k (x - x0)` |
//!
//! The affine load changes sign at `x0`: a load that follows a feature
//! about a reference inside the design, as a viscosity that follows the
//! oil's temperature does against the robot's net weight (`W (mu_ref/mu -
//! 1)`, zero at the temperature the nominal viscosity was stated for),
//! which neither `k x` nor `k x^p` can cross. The search offers it for a
//! recorded column only ([`crate::data::Feature`]): where a lab's column
//! has its zero is the lab's convention (degrees Celsius, a day count), so a
//! law in it must not depend on that origin, while a library quantity
//! (a ratio, a rate, a torque) has a physical zero its loads grow from.
//!
//! At most two free parameters each (Burnham & Anderson's parsimony: a
//! search over many laws with many parameters reads noise as physics).
//! A multiplier is floored at [`MIN_MULTIPLIER`] so that a trial step of the
//! fitter never makes a resistance or a rate negative; a fit that ends on
//! the floor is visible as a parameter at its bound or a poor chi-square.
//!
//! A correction is an ordinary [`Effect`], shared through an
//! [`super::EffectRef`] (a diagnosis makes a few hundred, freed with it),
//! so that the fitter ([`crate::workbench::fit`]) varies its parameters
//! like any catalogue effect's.
//!
//! Reference: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), sec. 1.4 (parsimony).

use super::place::Place;
use super::{Effect, EffectError, ParamSpec};
use crate::data::{Case, Feature};
use crate::physics::coefficients::LocalDrag;
use crate::physics::solve::ForceBalance;
use nalgebra::Matrix6;

/// Smallest multiplier a correction gives (see the module docs).
pub const MIN_MULTIPLIER: f64 = 0.01;

/// How a correction scales with its feature `x = g / g_ref`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Form {
    Constant,
    Linear,
    Power,
    Proportional,
    PowerLaw,
    Affine,
}

impl Form {
    pub const ALL: [Form; 6] = [
        Form::Constant,
        Form::Linear,
        Form::Power,
        Form::Proportional,
        Form::PowerLaw,
        Form::Affine,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Form::Constant => "constant",
            Form::Linear => "linear",
            Form::Power => "power",
            Form::Proportional => "proportional",
            Form::PowerLaw => "power-law",
            Form::Affine => "affine",
        }
    }

    /// Whether this form makes sense at `place` (loads have no `1 + ...`,
    /// only loads cross zero).
    pub fn fits(self, place: Place) -> bool {
        match self {
            Form::Linear | Form::Power => !place.is_additive(),
            Form::Affine => place.is_additive(),
            _ => true,
        }
    }

    pub fn needs_feature(self) -> bool {
        self != Form::Constant
    }

    /// Whether it raises its feature to a power (needs a positive feature).
    pub fn has_power(self) -> bool {
        matches!(self, Form::Power | Form::PowerLaw)
    }

    /// Number of free parameters.
    pub fn n_params(self) -> usize {
        match self {
            Form::Power | Form::PowerLaw | Form::Affine => 2,
            _ => 1,
        }
    }

    /// The law in symbols, `x` the scaled feature.
    pub fn symbols(self, additive: bool) -> &'static str {
        match (self, additive) {
            (Form::Constant, _) => "k",
            (Form::Linear, _) => "1 + k x",
            (Form::Power, _) => "1 + k x^p",
            (Form::Proportional, _) => "k x",
            (Form::PowerLaw, _) => "k x^p",
            (Form::Affine, _) => "k (x - x0)",
        }
    }
}

/// A correction `form` at `place`, scaling with `feature / scale`.
#[derive(Clone)]
pub struct LocatedCorrection {
    pub place: Place,
    pub feature: Option<Feature>,
    pub form: Form,
    /// The feature's reference value `g_ref` (same unit as the feature).
    pub scale: f64,
    /// Typical size of a load at a load place (mN or µN m): the bounds of
    /// `k` are +-100 of it.
    pub load_scale: f64,
    name: String,
    params: Vec<ParamSpec>,
}

impl std::fmt::Debug for LocatedCorrection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name)
    }
}

fn spec(name: &'static str, default: f64, min: f64, max: f64, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name: name.into(),
        unit: "1".into(),
        default,
        min,
        max,
        free: true,
        doc: doc.into(),
    }
}

impl LocatedCorrection {
    /// A correction with its parameter table; `None` when the form needs a
    /// feature and none is given (or the reverse), or the form does not
    /// apply at the place.
    pub fn new(
        place: Place,
        feature: Option<Feature>,
        form: Form,
        scale: f64,
        load_scale: f64,
    ) -> Option<LocatedCorrection> {
        if form.needs_feature() != feature.is_some() || !form.fits(place) {
            return None;
        }
        let additive = place.is_additive();
        let l = load_scale.abs().max(1e-9);
        let unit: &'static str = if additive { place.unit() } else { "1" };
        let k = |default, min, max, doc| ParamSpec {
            unit: unit.into(),
            ..spec("k", default, min, max, doc)
        };
        let p = spec("p", 1.0, -6.0, 6.0, "exponent of the scaled feature");
        let x0 = spec(
            "x0",
            1.0,
            -10.0,
            10.0,
            "the scaled feature where the load is 0",
        );
        let params: Vec<ParamSpec> = match (form, additive) {
            (Form::Constant, true) => vec![k(0.0, -100.0 * l, 100.0 * l, "the load")],
            (Form::Constant, false) => vec![k(1.0, 0.02, 50.0, "the multiplier")],
            (Form::Linear, _) => vec![k(0.0, -20.0, 20.0, "strength")],
            (Form::Power, _) => vec![k(0.0, -20.0, 20.0, "strength"), p],
            (Form::Affine, _) => vec![k(0.0, -100.0 * l, 100.0 * l, "the load per unit x"), x0],
            (Form::Proportional | Form::PowerLaw, true) => {
                let mut v = vec![k(0.0, -100.0 * l, 100.0 * l, "the load at x = 1")];
                if form == Form::PowerLaw {
                    v.push(p);
                }
                v
            }
            (Form::Proportional | Form::PowerLaw, false) => {
                let mut v = vec![k(1.0, 0.02, 50.0, "the multiplier at x = 1")];
                if form == Form::PowerLaw {
                    v.push(p);
                }
                v
            }
        };
        let name = match &feature {
            Some(q) => format!(
                "{} = {} (x = {}/{})",
                place.name(),
                form.symbols(additive),
                q.id(),
                crate::format::fmt_trim(scale, 4)
            ),
            None => format!("{} = {}", place.name(), form.symbols(additive)),
        };
        Some(LocatedCorrection {
            place,
            feature,
            form,
            scale,
            load_scale: l,
            name,
            params,
        })
    }

    /// The scaled feature of a case (1 for a constant).
    pub fn x(&self, case: &Case) -> f64 {
        self.feature
            .as_ref()
            .map_or(1.0, |q| q.of(case) / self.scale)
    }

    /// The law at scaled feature `x` with parameters `p`, before flooring.
    pub fn law(&self, p: &[f64], x: f64) -> f64 {
        match self.form {
            Form::Constant => p[0],
            Form::Linear => 1.0 + p[0] * x,
            Form::Power => 1.0 + p[0] * x.powf(p[1]),
            Form::Proportional => p[0] * x,
            Form::PowerLaw => p[0] * x.powf(p[1]),
            Form::Affine => p[0] * (x - p[1]),
        }
    }

    /// [`Self::law`] with `ln x` at hand: `x^q` as `exp(q ln x)`, for the
    /// screen, which evaluates each law tens of times per case (equal to
    /// `law` to round-off; the exact fits keep `law`).
    pub fn law_with_ln(&self, p: &[f64], x: f64, ln_x: f64) -> f64 {
        match self.form {
            Form::Constant => p[0],
            Form::Linear => 1.0 + p[0] * x,
            Form::Power => 1.0 + p[0] * (p[1] * ln_x).exp(),
            Form::Proportional => p[0] * x,
            Form::PowerLaw => p[0] * (p[1] * ln_x).exp(),
            Form::Affine => p[0] * (x - p[1]),
        }
    }

    /// The multiplier (floored) or the load of a case.
    pub fn value(&self, p: &[f64], case: &Case) -> f64 {
        let v = self.law(p, self.x(case));
        if self.place.is_additive() {
            v
        } else {
            v.max(MIN_MULTIPLIER)
        }
    }

    /// The law with quantity ids, for an effect file:
    /// `1 + k * (wire_over_gap / 0.1)^p`.
    pub fn formula(&self) -> String {
        let x = self.feature.as_ref().map_or(String::new(), |q| {
            format!("({} / {})", q.id(), crate::format::fmt_trim(self.scale, 6))
        });
        match self.form {
            Form::Constant => "k".into(),
            Form::Linear => format!("1 + k * {x}"),
            Form::Power => format!("1 + k * {x}^p"),
            Form::Proportional => format!("k * {x}"),
            Form::PowerLaw => format!("k * {x}^p"),
            Form::Affine => format!("k * ({x} - x0)"),
        }
    }
}

impl Effect for LocatedCorrection {
    fn name(&self) -> &str {
        &self.name
    }
    fn statement(&self) -> &'static str {
        "a correction located by `diagnose`: a simple law at one place of the model"
    }
    fn reference(&self) -> &'static str {
        "swimbot diagnose (sparse search over place, feature and form)"
    }
    fn params(&self) -> &[ParamSpec] {
        &self.params
    }
    fn acts_on_local_drag(&self) -> bool {
        self.place.is_local_drag()
    }
    fn reads_model_quantities(&self) -> bool {
        self.feature
            .as_ref()
            .and_then(Feature::quantity)
            .is_some_and(crate::data::model_quantities::is_model_quantity)
    }
    fn local_drag(&self, p: &[f64], case: &Case, drag: &mut LocalDrag) {
        self.place.apply_local_drag(self.value(p, case), drag);
    }
    fn tail(&self, p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        self.place.apply_tail(self.value(p, case), tail);
        Ok(())
    }
    fn body(&self, p: &[f64], case: &Case, body: &mut Matrix6<f64>) {
        self.place.apply_body(self.value(p, case), body);
    }
    fn balance(&self, p: &[f64], case: &Case, fb: &mut ForceBalance) {
        self.place.apply_balance(self.value(p, case), fb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::quantities::by_id;
    use crate::effects::EffectInstance;
    use crate::model::Model;

    #[test]
    fn the_neutral_parameters_leave_the_model_unchanged() {
        let paper = crate::data::paper();
        let g = Feature::Quantity(by_id("wire_over_gap").unwrap());
        for place in Place::ALL {
            for form in Form::ALL {
                let feature = form.needs_feature().then(|| g.clone());
                let Some(c) = LocatedCorrection::new(place, feature, form, 0.1, 1.0) else {
                    continue;
                };
                let c = std::sync::Arc::new(c);
                // Neutral: loads 0, `1 + ...` at k = 0, `k x...` at x = 1.
                let mut values: Vec<f64> = c.params().iter().map(|p| p.default).collect();
                if matches!(form, Form::Proportional | Form::PowerLaw) && !place.is_additive() {
                    values[0] = 1.0;
                }
                let m = Model::base().with_effect(EffectInstance {
                    effect: c.clone().into(),
                    values,
                });
                let case = &paper.cases[1];
                let mut at_one = case.clone();
                // Put the feature at its reference value so that x = 1.
                at_one.channel_diameter_mm = 2.0
                    * (case.amplitude_mm + 0.5 * case.wire_diameter_mm)
                    + case.wire_diameter_mm / 0.1;
                assert!((c.x(&at_one) - 1.0).abs() < 1e-12);
                let a = Model::base().predict(&at_one).unwrap();
                let b = m.predict(&at_one).unwrap();
                assert!(
                    (a.u_mm_s - b.u_mm_s).abs() < 1e-12 * a.u_mm_s.abs(),
                    "{c:?}"
                );
                assert!((a.omega_body_hz - b.omega_body_hz).abs() < 1e-12, "{c:?}");
            }
        }
    }

    #[test]
    fn a_drive_rate_multiplier_scales_both_velocities_exactly() {
        let paper = crate::data::paper();
        let c = LocatedCorrection::new(Place::DriveRate, None, Form::Constant, 1.0, 1.0).unwrap();
        let m = Model::base().with_effect(EffectInstance {
            effect: std::sync::Arc::new(c).into(),
            values: vec![0.8],
        });
        for case in &paper.cases {
            let a = Model::base().predict(case).unwrap();
            let b = m.predict(case).unwrap();
            assert!((b.u_mm_s / a.u_mm_s - 0.8).abs() < 1e-12);
            assert!((b.omega_body_hz / a.omega_body_hz - 0.8).abs() < 1e-12);
        }
    }

    #[test]
    fn forms_refuse_places_and_features_they_do_not_fit() {
        let g = Feature::Quantity(by_id("body_ratio").unwrap());
        assert!(
            LocatedCorrection::new(Place::LoadForce, Some(g.clone()), Form::Power, 1.0, 1.0)
                .is_none()
        );
        assert!(LocatedCorrection::new(Place::TailNormal, None, Form::Linear, 1.0, 1.0).is_none());
        assert!(LocatedCorrection::new(
            Place::TailNormal,
            Some(g.clone()),
            Form::Constant,
            1.0,
            1.0
        )
        .is_none());
        let c = LocatedCorrection::new(Place::TailNormal, Some(g.clone()), Form::Power, 0.5, 1.0)
            .unwrap();
        assert_eq!(c.formula(), "1 + k * (body_ratio / 0.5)^p");
        assert_eq!(c.params().len(), 2);
    }
}
