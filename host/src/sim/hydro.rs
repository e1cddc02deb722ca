//! The swimmer model seen from the motor. With a motor between body and
//! tail (`TailDrive::RelativeToBody`), eq. 11 becomes the torque-free
//! balance `(B_b + B_t + B_x) V = -B_t omega e4 + F`, whose solution
//! `V = [U; Omega_b]` is affine in the motor's relative rate `omega`
//! (linear, plus any rate-independent load `F` such as buoyancy). The tail
//! turns at `omega + Omega_b` and the fluid's torque on it about x is
//! `-(B_t (V + omega e4))[3]`: the motor supplies its negative,
//! `tau_m = tau_0 + c omega`.
//!
//! So the balance is solved at two rates, once per tail, and reused at
//! every time step (a third rate checks that the chosen effects really are
//! affine in the rate). Power: dotting the balance with `V` gives
//! `omega tau_m = P_h - F . V`, `P_h = V_t . B_t V_t + V . (B_b + B_x) V`,
//! `V_t = V + omega e4`: the shaft power is the hydrodynamic dissipation
//! minus the work of the external load, which the energy test checks.

use crate::data::Case;
use crate::model::{Model, ModelError};
use crate::physics::solve::TailDrive;
use nalgebra::{Matrix6, Vector6};
use std::f64::consts::TAU;

/// Eq. 11 with a motor, precomputed for one tail.
#[derive(Debug, Clone, PartialEq)]
pub struct Hydro {
    /// `V` at zero motor rate (m/s, rad/s): only external loads drive it.
    pub v0: Vector6<f64>,
    /// `dV / d omega` (m/s and rad/s per rad/s).
    pub dv: Vector6<f64>,
    /// Motor load torque at zero rate (N m) and per unit rate (N m s).
    pub tau0_n_m: f64,
    pub damping_n_m_s: f64,
    tail: Matrix6<f64>,
    body: Matrix6<f64>,
    f0: Vector6<f64>,
    df: Vector6<f64>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HydroError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("case `{case}`: the model's balance is not affine in the tail rate (relative mismatch {mismatch:.1e}); `sim` needs effects linear in the rate")]
    NotAffine { case: String, mismatch: f64 },
}

/// Tail matrix, body + extra matrix, external load and `V` of one balance.
type Solved = (Matrix6<f64>, Matrix6<f64>, Vector6<f64>, Vector6<f64>);

/// The balance at motor rate `omega`: matrices, load and solution.
fn balance(model: &Model, case: &Case, omega: f64) -> Result<Solved, ModelError> {
    let case = Case {
        frequency_hz: omega / TAU,
        ..case.clone()
    };
    let mut fb = model.force_balance(&case)?;
    fb.drive = TailDrive::RelativeToBody;
    fb.tail_rate_rad_s = omega;
    let v = fb.solve().map_err(|source| ModelError::Solve {
        case: case.id.clone(),
        source,
    })?;
    Ok((fb.tail, fb.body + fb.extra, fb.load, v))
}

impl Hydro {
    pub fn new(model: &Model, case: &Case) -> Result<Hydro, HydroError> {
        let (_, _, f0, v0) = balance(model, case, 0.0)?;
        let (tail, body, f1, v1) = balance(model, case, 1.0)?;
        let (_, _, _, v2) = balance(model, case, 2.0)?;
        let dv = v1 - v0;
        let mismatch = (v2 - (v0 + 2.0 * dv)).amax() / v2.amax().max(f64::MIN_POSITIVE);
        if mismatch > 1e-9 {
            return Err(HydroError::NotAffine {
                case: case.id.clone(),
                mismatch,
            });
        }
        let torque = |v: &Vector6<f64>, omega: f64| {
            let mut vt = *v;
            vt[3] += omega;
            (tail * vt)[3]
        };
        let tau0_n_m = torque(&v0, 0.0);
        Ok(Hydro {
            v0,
            dv,
            tau0_n_m,
            damping_n_m_s: torque(&v1, 1.0) - tau0_n_m,
            tail,
            body,
            f0,
            df: f1 - f0,
        })
    }

    /// `[U; Omega_b]` (m/s, rad/s; `Omega_b` signed about x) at motor rate `omega`.
    pub fn velocity(&self, omega: f64) -> Vector6<f64> {
        self.v0 + self.dv * omega
    }

    /// Torque the motor must supply at rate `omega` (N m).
    pub fn motor_torque_n_m(&self, omega: f64) -> f64 {
        self.tau0_n_m + self.damping_n_m_s * omega
    }

    /// Hydrodynamic dissipation `P_h` of body and tail (W), from the
    /// matrices directly rather than from the torque (the energy test
    /// compares the two).
    pub fn dissipation_w(&self, omega: f64) -> f64 {
        let v = self.velocity(omega);
        let mut vt = v;
        vt[3] += omega;
        vt.dot(&(self.tail * vt)) + v.dot(&(self.body * v))
    }

    /// Power of the external load `F . V` (W), e.g. buoyancy lifting the robot.
    pub fn external_power_w(&self, omega: f64) -> f64 {
        (self.f0 + self.df * omega).dot(&self.velocity(omega))
    }
}
