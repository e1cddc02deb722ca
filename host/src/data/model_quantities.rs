//! The model's own per-case quantities as case quantities: the tail's load
//! torque and thrust, the body's drag, the power the tail takes, the
//! predicted U and Omega_b, and the Reynolds numbers the body and the tail
//! see, all of one model (the one `diagnose` starts from).
//!
//! They are not recorded: a caller that owns a model computes them once per
//! dataset ([`crate::model::columns`]) and attaches them to each case
//! ([`Derived`]); the quantities here only read the attached values, so a
//! law in one of them costs no model solve when it is evaluated. On a case
//! with nothing attached they are NaN: the search leaves a feature that is
//! not finite on every case out, and a user effect whose formula reads one
//! is refused by its check ("must be finite") rather than run on NaN.
//!
//! Equations (the paper's eqs. 3, 10 and 11, in the swimmer frame, x the
//! channel's axis, `omega_t` the tail's rate in the lab frame:
//! `omega = 2 pi f` for the paper's drive, `omega + Omega_b` for a drive
//! relative to the body):
//!
//! - load torque `tau_t = B_t[wx,x] U + B_t[wx,wx] omega_t`: the torque the
//!   fluid puts on the turning tail, which the motor must supply (eq. 3);
//! - thrust `F_t = -B_t[x,wx] omega_t`: the tail's propulsive force at
//!   `U = 0` (eq. 3);
//! - body drag `F_b = D_x U` (eq. 10);
//! - tail power `P_t = [U, omega_t] B_t [U, omega_t]^T`: the rate of work
//!   the tail does on the fluid (eq. 3, positive as `B_t` is);
//! - `U` and `Omega_b` from the force balance (eq. 11);
//! - `Re_b = rho U D_b / mu` and `Re_t = rho sqrt((omega_t B_o)^2 + U^2) D_t / mu`
//!   (the wire's speed through the oil on its diameter).
//!
//! Reference: J. Lighthill, *Mathematical Biofluiddynamics* (1975), ch. 3.

use super::quantities::Quantity;

/// Every model quantity's id starts with it.
pub const PREFIX: &str = "model_";

/// How many model quantities a case can carry.
pub const N_MODEL: usize = 8;

/// Values the tool computed for a case from a model, in the order of
/// [`MODEL_QUANTITIES`]; `None` until a caller attaches them. `key`
/// identifies the model they came from within one run
/// ([`crate::model::columns::key`]), so that a law fitted on top of
/// another model is never fed the quantities of the wrong one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Derived {
    pub model: Option<[f64; N_MODEL]>,
    pub key: u64,
}

impl Derived {
    /// The `i`-th model quantity, NaN when none is attached.
    pub fn model(&self, i: usize) -> f64 {
        self.model.map_or(f64::NAN, |m| m[i])
    }
}

/// Slots of [`Derived::model`], named.
pub mod slot {
    pub const TAIL_TORQUE: usize = 0;
    pub const THRUST: usize = 1;
    pub const BODY_DRAG: usize = 2;
    pub const TAIL_POWER: usize = 3;
    pub const U: usize = 4;
    pub const OMEGA_BODY: usize = 5;
    pub const BODY_REYNOLDS: usize = 6;
    pub const TAIL_REYNOLDS: usize = 7;
}

/// The model's quantities, each reading its slot of [`Derived`].
pub const MODEL_QUANTITIES: &[Quantity; N_MODEL] = &[
    Quantity {
        id: "model_tail_torque_n_m",
        name: "tau_t = B_t[wx,x] U + B_t[wx,wx] omega",
        unit: "N m",
        doc: "the model's load torque on the turning tail, which the motor supplies (eq. 3 at the U of eq. 11)",
        value: |c| c.derived.model(slot::TAIL_TORQUE),
    },
    Quantity {
        id: "model_thrust_n",
        name: "F_t = -B_t[x,wx] omega",
        unit: "N",
        doc: "the model's tail thrust: the tail's axial force at U = 0 (eq. 3)",
        value: |c| c.derived.model(slot::THRUST),
    },
    Quantity {
        id: "model_body_drag_n",
        name: "F_b = D_x U",
        unit: "N",
        doc: "the model's axial drag on the body at its predicted U (eq. 10)",
        value: |c| c.derived.model(slot::BODY_DRAG),
    },
    Quantity {
        id: "model_tail_power_w",
        name: "P_t = [U, omega] B_t [U, omega]^T",
        unit: "W",
        doc: "the model's power the tail puts into the oil (eq. 3 at the U of eq. 11)",
        value: |c| c.derived.model(slot::TAIL_POWER),
    },
    Quantity {
        id: "model_u_mm_s",
        name: "U (model)",
        unit: "mm/s",
        doc: "the model's predicted swimming speed (eq. 11)",
        value: |c| c.derived.model(slot::U),
    },
    Quantity {
        id: "model_omega_body_hz",
        name: "Omega_b (model)",
        unit: "Hz",
        doc: "the model's predicted body counter-rotation rate (eq. 11)",
        value: |c| c.derived.model(slot::OMEGA_BODY),
    },
    Quantity {
        id: "model_body_reynolds",
        name: "Re_b = rho U D_b/mu",
        unit: "1",
        doc: "the body's Reynolds number at the model's U",
        value: |c| c.derived.model(slot::BODY_REYNOLDS),
    },
    Quantity {
        id: "model_tail_reynolds",
        name: "Re_t = rho sqrt((omega B_o)^2 + U^2) D_t/mu",
        unit: "1",
        doc: "the wire's Reynolds number at its speed through the oil, with the model's U",
        value: |c| c.derived.model(slot::TAIL_REYNOLDS),
    },
];

/// Whether `q` is one of the model's quantities (it reads attached values).
pub fn is_model_quantity(q: &Quantity) -> bool {
    q.id.starts_with(PREFIX) && MODEL_QUANTITIES.iter().any(|m| m.id == q.id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_attached_values_every_model_quantity_is_nan() {
        let case = &crate::data::paper().cases[0];
        assert!(MODEL_QUANTITIES.iter().all(|q| q.of(case).is_nan()));
        let mut with = case.clone();
        let mut v = [0.0; N_MODEL];
        for (i, x) in v.iter_mut().enumerate() {
            *x = i as f64 + 0.5;
        }
        with.derived.model = Some(v);
        for (i, q) in MODEL_QUANTITIES.iter().enumerate() {
            assert_eq!(q.of(&with), i as f64 + 0.5, "{}", q.id);
            assert!(q.id.starts_with("model_") && is_model_quantity(q));
        }
    }
}
