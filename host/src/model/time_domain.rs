//! The paper's time-domain procedure (section III): integrate the robot's
//! motion over two complete tail revolutions with an adaptive Runge-Kutta
//! method and average. Two independent evaluations of the same mean:
//!
//! * [`integrate`]: Dormand-Prince 5(4) (`ode_solvers`) on
//!   `d(t, x, theta_b)/dphi = (1, U, Omega_b) / phi_dot`, with the tail's
//!   phase relative to the body `phi` as the independent variable so that
//!   the window is exactly two revolutions however fast the body turns
//!   (`phi_dot = omega - Omega_b` for the paper's absolute drive, `omega`
//!   for a motor-relative drive);
//! * [`phase_average`]: the same time average written as a phase integral,
//!   `<U> = ∫ U/phi_dot dphi / ∫ 1/phi_dot dphi`, by the trapezoidal rule on
//!   equispaced phases (spectrally accurate for a smooth periodic integrand).
//!
//! With the paper's x-only degrees of freedom the axial resistances do not
//! depend on the phase and both equal the direct solve; with all six
//! degrees of freedom the lateral coupling of a non-integer number of turns
//! makes the instantaneous velocity vary over a revolution. The body's
//! orientation is not advanced (lateral rotations are averaged, not
//! accumulated), as in the paper's phase averaging.
//!
//! Reference: J. R. Dormand & P. J. Prince, J. Comput. Appl. Math. 6 (1980) 19.

use super::{prediction, Model, ModelError, Prediction};
use crate::data::Case;
use crate::physics::solve::TailDrive;
use nalgebra::Vector6;
use ode_solvers::dopri5::Dopri5;
use ode_solvers::{System, Vector3};
use std::cell::RefCell;
use std::f64::consts::PI;

/// Tail revolutions in the averaging window (the paper's two periods).
pub const REVOLUTIONS: f64 = 2.0;

/// Settings of the time integration.
#[derive(Debug, Clone, Copy)]
pub struct TimeDomainSettings {
    /// Relative tolerance of the adaptive steps (default 1e-10).
    pub rtol: f64,
    /// Absolute tolerance (default 1e-14, in s, m and rad).
    pub atol: f64,
}

impl Default for TimeDomainSettings {
    fn default() -> Self {
        TimeDomainSettings {
            rtol: 1e-10,
            atol: 1e-14,
        }
    }
}

/// Rate at which the tail's phase advances relative to the body.
fn relative_rate(model: &Model, case: &Case, v: &Vector6<f64>) -> f64 {
    match model.force_balance(case).map(|fb| fb.drive) {
        Ok(TailDrive::RelativeToBody) => case.tail_rate_rad_s(),
        _ => case.tail_rate_rad_s() - v[3],
    }
}

/// Helix phase for a relative rotation `phi` of the tail (the centre-line
/// turns by `+phi` about x, which moves the phase by `-chi phi`).
fn phase_of(case: &Case, phi: f64) -> f64 {
    -case.handedness.sign() * phi
}

struct Motion<'a> {
    model: &'a Model,
    case: &'a Case,
    error: RefCell<Option<ModelError>>,
}

/// The stepper owns its system; lending it a reference keeps the error
/// slot readable after the integration.
struct Lent<'a, 'b>(&'a Motion<'b>);

impl System<f64, Vector3<f64>> for Lent<'_, '_> {
    fn system(&self, phi: f64, y: &Vector3<f64>, dy: &mut Vector3<f64>) {
        self.0.rates(phi, y, dy);
    }
}

impl Motion<'_> {
    fn rates(&self, phi: f64, _y: &Vector3<f64>, dy: &mut Vector3<f64>) {
        match self.model.velocity_at(self.case, phase_of(self.case, phi)) {
            Ok(v) => {
                let rate = relative_rate(self.model, self.case, &v);
                *dy = Vector3::new(1.0, v[0], v[3]) / rate;
            }
            Err(e) => {
                self.error.borrow_mut().get_or_insert(e);
                *dy = Vector3::zeros();
            }
        }
    }
}

/// Mean motion over two revolutions by adaptive time integration.
pub fn integrate(
    model: &Model,
    case: &Case,
    settings: TimeDomainSettings,
) -> Result<Prediction, ModelError> {
    let motion = Motion {
        model,
        case,
        error: RefCell::new(None),
    };
    let end = REVOLUTIONS * 2.0 * PI;
    let mut stepper = Dopri5::new(
        Lent(&motion),
        0.0,
        end,
        end,
        Vector3::zeros(),
        settings.rtol,
        settings.atol,
    );
    stepper.set_output(ode_solvers::dop_shared::OutputType::Sparse);
    let outcome = stepper.integrate();
    let y = *stepper.y_out().last().unwrap_or(&Vector3::zeros());
    if let Some(e) = motion.error.take() {
        return Err(e);
    }
    if let Err(e) = outcome {
        return Err(ModelError::NonFinite {
            case: format!("{} (time integration: {e:?})", case.id),
            u: f64::NAN,
            omega: f64::NAN,
        });
    }
    let mut v = Vector6::zeros();
    v[0] = y[1] / y[0];
    v[3] = y[2] / y[0];
    prediction(case, v)
}

/// Mean motion over a revolution by phase quadrature on `n` phases.
pub fn phase_average(model: &Model, case: &Case, n: usize) -> Result<Prediction, ModelError> {
    let n = n.max(1);
    let (mut time, mut x, mut theta) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let phi = 2.0 * PI * i as f64 / n as f64;
        let v = model.velocity_at(case, phase_of(case, phi))?;
        let w = 1.0 / relative_rate(model, case, &v);
        time += w;
        x += v[0] * w;
        theta += v[3] * w;
    }
    let mut v = Vector6::zeros();
    v[0] = x / time;
    v[3] = theta / time;
    prediction(case, v)
}
