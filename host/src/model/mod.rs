//! The swimmer model: a composition of a local-drag coefficient set, a way
//! of integrating the tail (eq. 3), the body (eq. 10), degrees of freedom,
//! and a list of effects; [`Model::predict`] runs eq. 11 for one case.
//!
//! Output conventions: `U > 0` is body-first swimming (up the channel);
//! the body rate is reported as the counter-rotation rate (positive when
//! opposite to the tail), as the paper's Table IV does.

pub mod columns;
mod presets;
pub mod time_domain;

pub use presets::{preset, PRESETS};

use crate::data::Case;
use crate::effects::tail_compat::{self, TailModel};
use crate::effects::{Effect, EffectError, EffectInstance};
use crate::physics::body::{BodyError, BodyResistance};
use crate::physics::coefficients::{CoefficientError, CoefficientSet};
use crate::physics::solve::{Dofs, ForceBalance, SolveError};
use crate::physics::tail;
use nalgebra::{Matrix6, Vector6};
use std::f64::consts::PI;

// Instrumentation of the test build only: the audit's time estimate counts
// force balances, and a test holds the count to what the audit makes, on a
// thread pool of its own (per thread, so that other tests do not count).
// The library itself keeps no state between calls.
#[cfg(test)]
thread_local! {
    static FORCE_BALANCES: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many force balances (eq. 11) this thread has assembled so far.
#[cfg(test)]
pub fn force_balances_on_this_thread() -> u64 {
    FORCE_BALANCES.with(std::cell::Cell::get)
}

/// How eq. 3 is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TailMethod {
    /// Closed form (exact for any turns and phase).
    Exact,
    /// The paper's trapezoidal quadrature with this many nodes per wavelength.
    Quadrature { nodes_per_wavelength: usize },
    /// Regularized Stokeslets (non-local; [`crate::nonlocal`]), memoised.
    Stokeslets { segments_per_turn: usize },
    /// Johnson's slender-body theory (non-local), memoised.
    SlenderBody { segments_per_turn: usize },
}

/// The model: build with [`Model::base`] or [`preset`], then adjust.
///
/// Defaults of [`Model::base`]: Gray-Hancock coefficients, exact tail
/// integration, x-translation and x-rotation only (the paper's runs), no
/// effects.
#[derive(Debug, Clone)]
pub struct Model {
    pub coefficients: CoefficientSet,
    pub tail_method: TailMethod,
    pub dofs: Dofs,
    pub effects: Vec<EffectInstance>,
}

/// What the model predicts for one case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    /// Swimming speed, body first (mm/s).
    pub u_mm_s: f64,
    /// Body counter-rotation rate (Hz).
    pub omega_body_hz: f64,
    /// `U / (lambda f)`.
    pub u_over_u_wave: f64,
    /// `Omega_b / omega`.
    pub omega_ratio: f64,
    /// The full rigid-body velocity `[U; Omega_b]` in SI, swimmer frame.
    pub velocity: Vector6<f64>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("case `{case}`: {source}")]
    Coefficients {
        case: String,
        source: CoefficientError,
    },
    #[error("case `{case}`: {source}")]
    Body { case: String, source: BodyError },
    #[error("case `{case}`: {source}")]
    Solve { case: String, source: SolveError },
    #[error("case `{case}`: effect `{effect}`: {source}")]
    Effect {
        case: String,
        effect: String,
        source: EffectError,
    },
    #[error("case `{case}`: non-local tail: {message}")]
    Nonlocal { case: String, message: String },
    #[error("case `{case}`: the prediction is not finite (U = {u}, Omega_b = {omega})")]
    NonFinite { case: String, u: f64, omega: f64 },
}

impl Model {
    /// The plain RFT model (see the type's docs for the defaults).
    pub fn base() -> Self {
        Model {
            coefficients: CoefficientSet::GrayHancock,
            tail_method: TailMethod::Exact,
            dofs: Dofs::AXIAL,
            effects: Vec::new(),
        }
    }

    pub fn with_coefficients(mut self, set: CoefficientSet) -> Self {
        self.coefficients = set;
        self
    }

    pub fn with_effect(mut self, effect: EffectInstance) -> Self {
        self.effects.push(effect);
        self
    }

    /// "gray-hancock + backflow + body-correction:..." for reports.
    pub fn describe(&self) -> String {
        let mut parts = vec![self.coefficients.to_string()];
        parts.extend(self.effects.iter().map(EffectInstance::spec));
        parts.join(" + ")
    }

    /// What computes the tail matrix before the effects act.
    pub fn tail_model(&self) -> TailModel {
        match self.tail_method {
            TailMethod::Exact | TailMethod::Quadrature { .. } => TailModel::Local,
            TailMethod::Stokeslets { .. } => TailModel::NonLocal("stokeslets"),
            TailMethod::SlenderBody { .. } => TailModel::NonLocal("sbt"),
        }
    }

    /// Refuses effects that would change nothing with this model's tail
    /// (a local drag effect with a non-local tail, ...): [`tail_compat`].
    pub fn check_tail_compat(&self) -> Result<(), tail_compat::TailConflict> {
        let effects: Vec<&dyn Effect> = self.effects.iter().map(|e| &*e.effect).collect();
        tail_compat::check(self.tail_model(), &effects)
    }

    /// Whether `effect`, added to this model, would act with its tail: the
    /// candidates `diagnose` and `audit` add are filtered by it.
    pub fn can_take(&self, effect: &dyn Effect) -> bool {
        let effects: Vec<&dyn Effect> = self.effects.iter().map(|e| &*e.effect).collect();
        tail_compat::conflict(effect, &effects, self.tail_model()).is_none()
    }

    /// The effects acting on `case`, replacing ones first (see [`crate::effects::Effect::order`]).
    fn active<'a>(&'a self, case: &'a Case) -> impl Iterator<Item = &'a EffectInstance> + 'a {
        // No orders to visit without effects: a sweep of the base model
        // asks five times per geometry.
        let orders = 0..if self.effects.is_empty() { 0 } else { 2u8 };
        orders.flat_map(move |order| {
            self.effects
                .iter()
                .filter(move |e| e.effect.order() == order && e.effect.applies_to(case, &e.values))
        })
    }

    /// Every active effect's [`crate::effects::Effect::check`] for `case`.
    fn check_effects(&self, case: &Case) -> Result<(), ModelError> {
        for e in self.active(case) {
            e.effect
                .check(&e.values, case)
                .map_err(|source| ModelError::Effect {
                    case: case.id.clone(),
                    effect: e.name().to_string(),
                    source,
                })?;
        }
        Ok(())
    }

    /// The tail matrix for a case, all stages of the effects applied.
    pub fn tail_matrix(&self, case: &Case) -> Result<Matrix6<f64>, ModelError> {
        self.tail_matrix_at(case, 0.0)
    }

    /// The tail matrix with the helix turned to phase `phase_rad` (see
    /// [`crate::physics::geometry::Helix::phase_rad`]).
    pub fn tail_matrix_at(&self, case: &Case, phase_rad: f64) -> Result<Matrix6<f64>, ModelError> {
        self.check_effects(case)?;
        self.tail_matrix_checked(case, phase_rad)
    }

    /// [`Self::tail_matrix_at`] once the effects are checked.
    fn tail_matrix_checked(&self, case: &Case, phase_rad: f64) -> Result<Matrix6<f64>, ModelError> {
        let helix = crate::physics::geometry::Helix {
            phase_rad,
            ..case.helix()
        };
        let mut drag = self
            .coefficients
            .local_drag(&helix, case.viscosity_pa_s)
            .map_err(|source| ModelError::Coefficients {
                case: case.id.clone(),
                source,
            })?;
        for e in self.active(case) {
            e.effect.local_drag(&e.values, case, &mut drag);
        }
        let nonlocal = |method, segments_per_turn| {
            crate::nonlocal::memo::nonlocal_tail(
                &helix,
                case.viscosity_pa_s,
                method,
                segments_per_turn,
            )
            .map_err(|e| ModelError::Nonlocal {
                case: case.id.clone(),
                message: e.to_string(),
            })
        };
        let mut m = match (self.tail_method, self.dofs == Dofs::AXIAL) {
            // The x-only solve reads only the axial block: skip the 36-entry integration.
            (TailMethod::Exact, true) => axial_only(tail::axial_closed_form(&helix, drag)),
            (TailMethod::Exact, false) => tail::matrix_exact(&helix, drag),
            (
                TailMethod::Quadrature {
                    nodes_per_wavelength,
                },
                _,
            ) => tail::matrix_quadrature(&helix, drag, nodes_per_wavelength),
            (TailMethod::Stokeslets { segments_per_turn }, _) => nonlocal(
                crate::nonlocal::TailMethod::RegularizedStokeslets,
                segments_per_turn,
            )?,
            (TailMethod::SlenderBody { segments_per_turn }, _) => {
                nonlocal(crate::nonlocal::TailMethod::SlenderBody, segments_per_turn)?
            }
        };
        for e in self.active(case) {
            e.effect
                .tail(&e.values, case, &mut m)
                .map_err(|source| ModelError::Effect {
                    case: case.id.clone(),
                    effect: e.name().to_string(),
                    source,
                })?;
        }
        Ok(m)
    }

    /// The body matrix for a case, effects applied.
    pub fn body_matrix(&self, case: &Case) -> Result<Matrix6<f64>, ModelError> {
        self.check_effects(case)?;
        self.body_matrix_checked(case)
    }

    /// [`Self::body_matrix`] once the effects are checked.
    fn body_matrix_checked(&self, case: &Case) -> Result<Matrix6<f64>, ModelError> {
        let mut b = BodyResistance::prolate_spheroid(&case.body(), case.viscosity_pa_s)
            .map_err(|source| ModelError::Body {
                case: case.id.clone(),
                source,
            })?
            .matrix();
        for e in self.active(case) {
            e.effect.body(&e.values, case, &mut b);
        }
        Ok(b)
    }

    /// Whether an effect reads the model's own quantities
    /// ([`crate::data::model_quantities`]).
    pub fn reads_model_quantities(&self) -> bool {
        self.effects
            .iter()
            .any(|e| e.effect.reads_model_quantities())
    }

    /// The model whose quantities a law in a model quantity reads: the
    /// effects before the first effect that reads one ([`columns`]).
    pub fn quantities_model(&self) -> Model {
        let first = self
            .effects
            .iter()
            .position(|e| e.effect.reads_model_quantities())
            .unwrap_or(self.effects.len());
        Model {
            effects: self.effects[..first].to_vec(),
            ..self.clone()
        }
    }

    /// Eq. 11 assembled for a case, before solving.
    pub fn force_balance(&self, case: &Case) -> Result<ForceBalance, ModelError> {
        self.force_balance_at(case, 0.0)
    }

    /// Eq. 11 with the tail at phase `phase_rad`.
    pub fn force_balance_at(
        &self,
        case: &Case,
        phase_rad: f64,
    ) -> Result<ForceBalance, ModelError> {
        // A law in a model quantity reads those of the model beneath it:
        // attached once per dataset by a diagnosis (then the key matches
        // and this costs a hash), solved here once per call otherwise (a
        // case read from a file, or a law found on top of another model).
        if self.reads_model_quantities() {
            let beneath = self.quantities_model();
            if case.derived.model.is_none() || case.derived.key != columns::key(&beneath) {
                let with = columns::with_quantities(&beneath, case)?;
                return self.force_balance_at(&with, phase_rad);
            }
        }
        #[cfg(test)]
        FORCE_BALANCES.with(|n| n.set(n.get() + 1));
        // One check serves every stage of this prediction.
        self.check_effects(case)?;
        let tail = self.tail_matrix_checked(case, phase_rad)?;
        let body = self.body_matrix_checked(case)?;
        let mut fb = ForceBalance::new(body, tail, case.tail_rate_rad_s());
        fb.dofs = self.dofs;
        // The recorded trim error acts on every model (0 for a neutral robot).
        fb.load[0] += case.net_weight_n();
        for e in self.active(case) {
            e.effect.balance(&e.values, case, &mut fb);
        }
        Ok(fb)
    }

    /// Predict one case (tail at phase 0; the axial results do not depend
    /// on the phase, the lateral ones do: see [`time_domain`]).
    pub fn predict(&self, case: &Case) -> Result<Prediction, ModelError> {
        prediction(case, self.velocity_at(case, 0.0)?)
    }

    /// The instantaneous rigid-body velocity with the tail at `phase_rad`.
    pub fn velocity_at(&self, case: &Case, phase_rad: f64) -> Result<Vector6<f64>, ModelError> {
        self.force_balance_at(case, phase_rad)?
            .solve()
            .map_err(|source| ModelError::Solve {
                case: case.id.clone(),
                source,
            })
    }
}

/// Turn a solved velocity into the reported quantities.
pub fn prediction(case: &Case, v: Vector6<f64>) -> Result<Prediction, ModelError> {
    let u_mm_s = v[0] * 1e3;
    let omega_body_hz = -v[3] / (2.0 * PI);
    if !u_mm_s.is_finite() || !omega_body_hz.is_finite() {
        return Err(ModelError::NonFinite {
            case: case.id.clone(),
            u: u_mm_s,
            omega: omega_body_hz,
        });
    }
    Ok(Prediction {
        u_mm_s,
        omega_body_hz,
        u_over_u_wave: u_mm_s / (case.wavelength_mm * case.frequency_hz),
        omega_ratio: omega_body_hz / case.frequency_hz,
        velocity: v,
    })
}

/// The axial entries in an otherwise diagonal matrix: the lateral diagonal
/// is never read by the x-only solve, so it is set to the axial drag merely
/// to keep the matrix well conditioned.
fn axial_only(a: tail::AxialResistance) -> Matrix6<f64> {
    let mut m = Matrix6::identity() * a.drag_n_s_per_m;
    m[(3, 3)] = a.torque_n_m_s;
    m[(0, 3)] = a.thrust_n_s;
    m[(3, 0)] = a.thrust_n_s;
    m
}
