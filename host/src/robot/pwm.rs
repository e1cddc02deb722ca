//! The PWM motor drive: a low-side MOSFET switching the cell across the
//! motor, with a Schottky freewheel diode across the motor. Three models:
//! - ideal average: motor voltage = duty x supply, supply current = duty x
//!   motor current (continuous-conduction textbook model);
//! - cycle average ([`PwmDrive::cycle_average`]): the exact per-period means
//!   of the RL circuit at constant speed, in closed form. This is what the
//!   controller tests and `swimbot sim` should use;
//! - switched ([`PwmDrive::step_switched`]): integrated through every
//!   carrier period, the reference the two averages are checked against.
//!
//! Why the cycle average: at 25 kHz the 40 us period is ten times the
//! motor's L/R, so the current rises to (V - e)/R within each on-phase and
//! falls to zero in each off-phase (discontinuous conduction). The mean
//! motor current still follows the mean terminal voltage (the per-period
//! mean of L di/dt is zero), so the ideal average gets the torque right to
//! a few per cent (the diode's drop is the difference); but the cell sees
//! nearly the full (V - e)/R while the switch is on, so the ideal model
//! underestimates the supply current, and with it the cell's sag and
//! drain, by ~20 % at this working point.

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

    /// Exact per-period means at periodic steady state, with the speed
    /// (back-EMF) taken as constant over one period: the loaded mechanical
    /// time constant (~0.2 ms) is several periods, and near stall the
    /// back-EMF is millivolts anyway.
    pub fn cycle_average(
        &self,
        motor: &Motor,
        duty: f64,
        supply_v: f64,
        speed_rad_s: f64,
    ) -> CycleMeans {
        self.cycle_average_through(motor, duty, supply_v, 0.0, speed_rad_s)
    }

    /// [`Self::cycle_average`] from a source with resistance: the cell's
    /// open-circuit `source_v` behind its `source_ohm`, in the loop only
    /// while the switch is on. Each on-pulse then sags the terminals by
    /// `source_ohm i` (the ripple the battery input sees) and the motor
    /// gets `source_v - source_ohm i` during the pulse, not the cycle mean.
    pub fn cycle_average_through(
        &self,
        motor: &Motor,
        duty: f64,
        source_v: f64,
        source_ohm: f64,
        speed_rad_s: f64,
    ) -> CycleMeans {
        let p = &motor.params;
        let r = p.resistance_ohm;
        let (tau_on, tau) = (p.inductance_h / (r + source_ohm), p.inductance_h / r);
        let period = 1.0 / self.carrier_hz;
        let t_on = duty.clamp(0.0, 1.0) * period;
        let t_off = period - t_on;
        let e = motor.back_emf_v(speed_rad_s);
        let (x_on, x_off) = ((-t_on / tau_on).exp(), (-t_off / tau).exp());
        // Asymptotes of the current: switch on, and diode conducting.
        let a_on = (source_v - e) / (r + source_ohm);
        let a_off = -(self.diode_drop_v + e) / r;
        // Continuous conduction if the periodic solution stays positive
        // (at duty 1 it is `a_on`: the motor across the cell, no pulses).
        let i0_ccm = (a_off * (1.0 - x_off) + a_on * (1.0 - x_on) * x_off) / (1.0 - x_on * x_off);
        let i0 = i0_ccm.max(0.0);
        let i1 = (a_on + (i0 - a_on) * x_on).max(0.0);
        let on_charge = a_on * t_on + (i0 - a_on) * tau_on * (1.0 - x_on);
        // Diode conduction time: until the current reaches zero, or the
        // whole off-phase in continuous conduction.
        let t_diode = if i0 > 0.0 || a_off >= 0.0 {
            t_off
        } else {
            (tau * (1.0 + i1 / -a_off).ln()).min(t_off)
        };
        let off_charge = a_off * t_diode + (i1 - a_off) * tau * (1.0 - (-t_diode / tau).exp());
        let t_float = t_off - t_diode;
        let motor_v = (source_v * t_on - source_ohm * on_charge - self.diode_drop_v * t_diode
            + e * t_float)
            / period;
        let mid_on_current_a = if t_on > 0.0 {
            (a_on + (i0 - a_on) * (-0.5 * t_on / tau_on).exp()).max(0.0)
        } else {
            0.0
        };
        CycleMeans {
            motor_v,
            motor_current_a: (on_charge + off_charge.max(0.0)) / period,
            supply_current_a: on_charge / period,
            mid_on_current_a,
        }
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

/// Per-period means of the drive, see [`PwmDrive::cycle_average`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleMeans {
    /// Mean voltage across the motor terminals: drive the motor's
    /// equations with this (mean current = (motor_v - back-EMF) / R).
    pub motor_v: f64,
    pub motor_current_a: f64,
    /// Mean current out of the cell.
    pub supply_current_a: f64,
    /// The current through the switch (and the cell) in the middle of the
    /// on-pulse, where the firmware converts the battery voltage
    /// (`firmware/src/battery_adc.rs`); 0 at duty 0.
    pub mid_on_current_a: f64,
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
    fn switched_model_confirms_the_averages_near_stall() {
        // The working point: 3.0 V average from a 4.0 V cell, tail load
        // holding the motor near 1 Hz.
        let motor = Motor::coreless_6mm();
        let damping = 5.2e-5;
        let duty = 0.75;
        let drive = PwmDrive::BOARD;
        let ideal = motor
            .steady_state(PwmDrive::averaged_motor_v(duty, 4.0), 0.0, damping)
            .expect("turns");
        let (i, w, supply) = switched_means(&drive, &motor, duty, 4.0, damping, ideal);

        // Cycle average at the switched model's mean speed: within 1 %.
        let c = drive.cycle_average(&motor, duty, 4.0, w);
        assert!((c.motor_current_a / i - 1.0).abs() < 0.01, "{c:?} vs {i}");
        assert!(
            (c.supply_current_a / supply - 1.0).abs() < 0.01,
            "{c:?} vs {supply}"
        );
        let from_v = (c.motor_v - motor.back_emf_v(w)) / motor.params.resistance_ohm;
        assert!(
            (from_v / c.motor_current_a - 1.0).abs() < 1e-9,
            "mean current follows mean voltage"
        );

        // Ideal average: torque (mean current) within 5 %, the shortfall
        // being the diode drop; supply current underestimated by > 10 %.
        let torque_err = 1.0 - i / ideal.current_a;
        assert!(torque_err > 0.0 && torque_err < 0.05, "{torque_err}");
        let supply_ideal = PwmDrive::averaged_supply_a(duty, ideal.current_a);
        assert!(supply / supply_ideal > 1.1, "{supply} vs {supply_ideal}");

        // With an ideal diode the ideal average's torque is exact to 1 %.
        let no_diode = PwmDrive {
            diode_drop_v: 0.0,
            ..drive
        };
        let (i0, w0, _) = switched_means(&no_diode, &motor, duty, 4.0, damping, ideal);
        assert!(
            (i0 / ideal.current_a - 1.0).abs() < 0.01,
            "{i0} vs {}",
            ideal.current_a
        );
        assert!((w0 / ideal.speed_rad_s - 1.0).abs() < 0.01);
    }

    #[test]
    fn cycle_average_in_continuous_conduction_and_limits() {
        // A slow carrier is irrelevant here; a big inductance makes the
        // current continuous: then the ideal average is exact.
        let mut motor = Motor::coreless_6mm();
        motor.params.inductance_h = 10e-3;
        let no_diode = PwmDrive {
            diode_drop_v: 0.0,
            ..PwmDrive::BOARD
        };
        let c = no_diode.cycle_average(&motor, 0.6, 4.0, 100.0);
        let e = motor.back_emf_v(100.0);
        assert!((c.motor_v - 2.4).abs() < 1e-9, "{c:?}");
        assert!((c.motor_current_a - (2.4 - e) / 7.0).abs() < 1e-6);
        assert!((c.supply_current_a / (0.6 * c.motor_current_a) - 1.0).abs() < 1e-3);
        // Duty 0: nothing flows, the terminals float at the back-EMF.
        let m = Motor::coreless_6mm();
        let z = PwmDrive::BOARD.cycle_average(&m, 0.0, 4.0, 50.0);
        assert_eq!((z.motor_current_a, z.supply_current_a), (0.0, 0.0));
        assert!((z.motor_v - m.back_emf_v(50.0)).abs() < 1e-12);
        // Duty 1: the motor is across the cell.
        let f = PwmDrive::BOARD.cycle_average(&m, 1.0, 4.0, 50.0);
        assert!(
            (f.motor_v - 4.0).abs() < 1e-12
                && (f.supply_current_a - f.motor_current_a).abs() < 1e-9
        );
    }

    #[test]
    fn mid_on_pulse_current_matches_the_switched_model() {
        // Where the firmware converts the battery: the current through the
        // cell half-way through the on-pulse, from the closed form and from
        // integrating every period at constant speed (DCM at 0.4 and 0.75,
        // the pulse settled; and full duty, where it is (V - e)/R).
        let motor = Motor::coreless_6mm();
        let drive = PwmDrive::BOARD;
        let w = 6.0;
        let steps = 4000;
        let dt = 1.0 / drive.carrier_hz / f64::from(steps);
        for duty in [0.4, 0.75, 1.0] {
            let mut s = MotorState {
                current_a: 0.0,
                speed_rad_s: w,
            };
            let mid = (duty * f64::from(steps) / 2.0).round() as u32;
            let mut at_mid = 0.0;
            for period in 0..20 {
                for k in 0..steps {
                    let on = f64::from(k) < duty * f64::from(steps);
                    let (next, _) = drive.step_switched(&motor, s, on, 4.0, 0.0, dt);
                    s = MotorState {
                        speed_rad_s: w,
                        ..next
                    };
                    if period == 19 && k + 1 == mid {
                        at_mid = s.current_a;
                    }
                }
            }
            let c = drive.cycle_average(&motor, duty, 4.0, w);
            assert!(
                (c.mid_on_current_a / at_mid - 1.0).abs() < 2e-3,
                "duty {duty}: {c:?} vs {at_mid}"
            );
            // Switching, the pulse's middle carries more than the mean:
            // the ripple the cell's resistance turns into a voltage.
            assert!(duty == 1.0 || c.mid_on_current_a > 1.2 * c.supply_current_a);
        }
        let full = drive.cycle_average(&motor, 1.0, 4.0, w);
        let steady = (4.0 - motor.back_emf_v(w)) / motor.params.resistance_ohm;
        assert!((full.mid_on_current_a / steady - 1.0).abs() < 1e-9);
        assert!((full.supply_current_a / steady - 1.0).abs() < 1e-9);
        assert_eq!(
            drive.cycle_average(&motor, 0.0, 4.0, w).mid_on_current_a,
            0.0
        );
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
