//! The PWM motor drive: a low-side MOSFET switching the cell across the
//! motor, with a Schottky freewheel diode across the motor. Two models:
//! the averaged one the controller tests and `swimbot sim` use (motor
//! voltage = duty x supply), and a switched one, integrated through every
//! carrier period, that checks the average.
//!
//! At 25 kHz the 40 us period is ten times the motor's L/R, so the current
//! ripple is large and it falls to zero in each off-phase (discontinuous
//! conduction). The average still holds to a few per cent: the
//! per-period mean of `L di/dt` is zero, so the mean current follows the
//! mean terminal voltage, which differs from duty x supply only by the
//! diode's drop while it conducts and the back-EMF while nothing conducts
//! (small near stall, where this motor runs).

use super::motor::{Motor, MotorState};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PwmDrive {
    pub carrier_hz: f64,
    /// Forward drop of the freewheel diode (Schottky, ~0.3 V at 0.5 A).
    pub diode_drop_v: f64,
}

impl PwmDrive {
    /// The board: 25 kHz carrier, Schottky freewheel diode.
    pub const BOARD: PwmDrive = PwmDrive {
        carrier_hz: 25_000.0,
        diode_drop_v: 0.3,
    };

    /// Averaged model: the motor's mean terminal voltage.
    pub fn averaged_motor_v(duty: f64, supply_v: f64) -> f64 {
        duty.clamp(0.0, 1.0) * supply_v
    }

    /// Averaged model: the mean current drawn from the supply (the motor
    /// current flows through the cell only while the switch is on).
    pub fn averaged_supply_a(duty: f64, motor_current_a: f64) -> f64 {
        duty.clamp(0.0, 1.0) * motor_current_a.max(0.0)
    }

    /// Switched model: is the MOSFET on at `t_s` (edge-aligned PWM, on at
    /// the start of each period, like the RP2040's free-running slice)?
    pub fn switch_on(&self, t_s: f64, duty: f64) -> bool {
        (t_s * self.carrier_hz).fract() < duty.clamp(0.0, 1.0)
    }

    /// Switched model: one integration step of the motor. With the switch
    /// off, current freewheels through the diode until it reaches zero;
    /// then the diode blocks and the terminals float at the back-EMF.
    /// Returns the new state and the mean current drawn from the supply.
    pub fn step_switched(
        &self,
        motor: &Motor,
        s: MotorState,
        on: bool,
        supply_v: f64,
        load_torque_n_m: f64,
        dt_s: f64,
    ) -> (MotorState, f64) {
        if on {
            let next = motor.step_rk4(s, supply_v, load_torque_n_m, dt_s);
            return (next, 0.5 * (s.current_a + next.current_a));
        }
        let blocked = s.current_a <= 0.0;
        let volts = if blocked {
            motor.back_emf_v(s.speed_rad_s)
        } else {
            -self.diode_drop_v
        };
        let mut next = motor.step_rk4(s, volts, load_torque_n_m, dt_s);
        // The diode cannot conduct backwards.
        next.current_a = next.current_a.max(0.0);
        (next, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mean motor current, speed and supply current of the switched model
    /// over `periods` carrier periods after settling from `start`.
    fn switched_means(
        drive: &PwmDrive,
        motor: &Motor,
        duty: f64,
        supply_v: f64,
        damping: f64,
        start: MotorState,
    ) -> (f64, f64, f64) {
        let steps_per_period = 400;
        let dt = 1.0 / drive.carrier_hz / steps_per_period as f64;
        let mut s = start;
        let (mut i_sum, mut w_sum, mut supply_sum, mut n) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..(steps_per_period * 300) {
            let t = k as f64 * dt;
            let (next, supply_a) = drive.step_switched(
                motor,
                s,
                drive.switch_on(t, duty),
                supply_v,
                damping * s.speed_rad_s,
                dt,
            );
            s = next;
            if k >= steps_per_period * 200 {
                i_sum += s.current_a;
                w_sum += s.speed_rad_s;
                supply_sum += supply_a;
                n += 1.0;
            }
        }
        (i_sum / n, w_sum / n, supply_sum / n)
    }

    #[test]
    fn switched_model_confirms_the_average_near_stall() {
        // The working point: 3.0 V average from a 4.0 V cell, tail load
        // holding the motor near 1 Hz.
        let motor = Motor::coreless_6mm();
        let damping = 5.2e-5;
        let duty = 0.75;
        let avg = motor
            .steady_state(PwmDrive::averaged_motor_v(duty, 4.0), 0.0, damping)
            .expect("turns");
        let ideal = PwmDrive {
            diode_drop_v: 0.0,
            ..PwmDrive::BOARD
        };
        let (i, w, supply) = switched_means(&ideal, &motor, duty, 4.0, damping, avg);
        assert!(
            (i / avg.current_a - 1.0).abs() < 0.01,
            "ideal diode: {i} vs {}",
            avg.current_a
        );
        assert!(
            (w / avg.speed_rad_s - 1.0).abs() < 0.01,
            "{w} vs {}",
            avg.speed_rad_s
        );
        // With the discontinuous current the supply current is the on-phase
        // mean, not duty x mean: within 10 % of the averaged estimate.
        let supply_avg = PwmDrive::averaged_supply_a(duty, avg.current_a);
        assert!(
            (supply / supply_avg - 1.0).abs() < 0.1,
            "{supply} vs {supply_avg}"
        );

        // A real Schottky costs a few per cent of torque, bounded by
        // V_f x (conduction time ~ L/R ln(1 + V/V_f)) / period.
        let (i_d, _, _) = switched_means(&PwmDrive::BOARD, &motor, duty, 4.0, damping, avg);
        let loss = 1.0 - i_d / avg.current_a;
        let p = &motor.params;
        let t_cond =
            p.inductance_h / p.resistance_ohm * (1.0 + 4.0 / PwmDrive::BOARD.diode_drop_v).ln();
        let bound = PwmDrive::BOARD.diode_drop_v * t_cond * PwmDrive::BOARD.carrier_hz / 3.0;
        assert!(
            loss > 0.0 && loss < bound * 1.2,
            "loss {loss}, bound {bound}"
        );
        assert!(loss < 0.05, "averaged model within 5 %: {loss}");
    }

    #[test]
    fn switch_timing() {
        let d = PwmDrive::BOARD;
        let period = 1.0 / d.carrier_hz;
        let on: usize = (0..1000)
            .filter(|k| d.switch_on(*k as f64 * period / 1000.0, 0.3))
            .count();
        assert!((299..=301).contains(&on), "{on}");
        assert!(!d.switch_on(0.0, 0.0));
        assert!(d.switch_on(period * 0.999, 1.0));
    }
}
