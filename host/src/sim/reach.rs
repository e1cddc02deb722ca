//! The robot's largest steady motor rate in a run: at full drive the
//! motor's torque line meets the tail's load (docs in `motor/src/dc_motor.rs`
//! and [`super::hydro`]):
//!
//! ```text
//! k (V - k w) / (R + R_cell) = b w + tau_c + tau_0 + c w
//! w_max = (k V / (R + R_cell) - tau_c - tau_0) / (k^2 / (R + R_cell) + b + c)
//! ```
//!
//! with `V` the cell's open-circuit voltage at its starting charge, `R_cell`
//! its internal resistance and `tau_0 + c w` the load [`Hydro`] computes
//! from the swimmer model; or, when it binds first, the rate controller's
//! motor-voltage ceiling (`V` that ceiling, `R_cell` 0: the duty makes up
//! the cell's sag). A set-point above it is never held: the
//! controller saturates at full duty.

use super::hydro::Hydro;
use super::robot::Robot;
use crate::data::Case;
use crate::model::Model;
use crate::workbench::plan::Reach;
use std::f64::consts::TAU;

impl Reach for Robot {
    fn max_rate_hz(&self, model: &Model, case: &Case) -> Option<f64> {
        let h = Hydro::new(model, case).ok()?;
        let m = &self.motor;
        let k = m.torque_constant_n_m_per_a;
        let tau0 = h.motor_torque_n_m(0.0);
        let c = h.motor_torque_n_m(1.0) - tau0;
        let w_at = |v: f64, r: f64| {
            (k * v / r - m.coulomb_friction_n_m - tau0) / (k * k / r + m.viscous_friction_n_m_s + c)
        };
        // Full duty on the cell through its resistance, or the rate
        // controller's motor-voltage ceiling, whichever binds first.
        let cell = w_at(
            self.cell.ocv_v(self.cell.initial_soc),
            m.resistance_ohm + self.cell.internal_resistance_ohm,
        );
        let ceiling_v = f64::from(swimbot_shared::board::RATE.max_motor_mv) / 1e3;
        let w = cell.min(w_at(ceiling_v, m.resistance_ohm));
        (w.is_finite()).then(|| (w / TAU).max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{simulate_with, Options, RateRun, Script};

    /// A set-point far above the bound is held at the bound: the motor's
    /// simulated rate at full drive agrees with the formula.
    #[test]
    fn the_bound_is_the_rate_the_simulated_motor_saturates_at() {
        let robot = crate::sim::default_robot();
        let case = robot.case(0, 1.0);
        let max = robot.max_rate_hz(&robot.model, &case).unwrap();
        assert!(max > 0.3 && max < 10.0, "{max}");
        let rate = RateRun::new(vec![(0, 1.5 * max)]);
        let opts = Options {
            max_time_s: 20.0,
            stop_at_top: false,
            ..Options::default()
        };
        let o = simulate_with(&robot, &Script::on_at_zero(), &opts, Some(&rate)).unwrap();
        let held = o.last.motor_rate_hz;
        assert!(
            (held / max - 1.0).abs() < 0.03,
            "saturated at {held} Hz, the bound says {max} Hz"
        );
    }
}
