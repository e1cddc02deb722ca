//! Where the cell's power goes inside one PWM period: the winding's
//! `R <i²>`, the freewheel diode's `V_d <i_d>` and the back-EMF's `e <i>`.
//!
//! The same piecewise-exponential periodic current as
//! `PwmDrive::cycle_average` (switch on: `i -> (V - e)/R`; diode: `i ->
//! -(V_d + e)/R` until zero; then floating), integrated for `i²` as well:
//! on a segment `i = a + (i_s - a) e^{-t/tau}`,
//! `int i² = a² T + 2 a (i_s - a) tau (1 - e^{-T/tau}) + (i_s - a)² tau/2 (1 - e^{-2T/tau})`.
//! With a source resistance `R_s` (the cell's, in the loop while the
//! switch is on) the on-segments relax with `L/(R + R_s)` towards
//! `(V - e)/(R + R_s)`. Over a period `L di/dt` integrates to zero, so
//! `V <i_supply> = R_s <i_on²> + R <i²> + V_d <i_d> + e <i>` holds exactly;
//! the energy test uses these terms as the electrical losses.

use crate::robot::{Motor, PwmDrive};

/// Per-period means (A, A², W).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodLosses {
    pub supply_current_a: f64,
    pub motor_current_a: f64,
    pub winding_w: f64,
    pub diode_w: f64,
    /// In the source's resistance (the cell's internal loss).
    pub source_w: f64,
}

/// `int_0^T (a + (s - a) e^{-t/tau})^{1,2} dt`.
fn segment(a: f64, s: f64, tau: f64, t: f64) -> (f64, f64) {
    let x = (-t / tau).exp();
    let d = s - a;
    (
        a * t + d * tau * (1.0 - x),
        a * a * t + 2.0 * a * d * tau * (1.0 - x) + d * d * 0.5 * tau * (1.0 - x * x),
    )
}

pub fn period_losses(
    drive: &PwmDrive,
    motor: &Motor,
    duty: f64,
    supply_v: f64,
    speed_rad_s: f64,
) -> PeriodLosses {
    period_losses_through(drive, motor, duty, supply_v, 0.0, speed_rad_s)
}

/// [`period_losses`] from `source_v` behind `source_ohm`
/// (`PwmDrive::cycle_average_through`).
pub fn period_losses_through(
    drive: &PwmDrive,
    motor: &Motor,
    duty: f64,
    source_v: f64,
    source_ohm: f64,
    speed_rad_s: f64,
) -> PeriodLosses {
    let p = &motor.params;
    let (r, tau) = (p.resistance_ohm, p.inductance_h / p.resistance_ohm);
    let tau_on = p.inductance_h / (r + source_ohm);
    let period = 1.0 / drive.carrier_hz;
    let t_on = duty.clamp(0.0, 1.0) * period;
    let t_off = period - t_on;
    let e = motor.back_emf_v(speed_rad_s);
    let a_on = (source_v - e) / (r + source_ohm);
    let a_off = -(drive.diode_drop_v + e) / r;
    let (x_on, x_off) = ((-t_on / tau_on).exp(), (-t_off / tau).exp());
    let i0_ccm = (a_off * (1.0 - x_off) + a_on * (1.0 - x_on) * x_off) / (1.0 - x_on * x_off);
    // At duty 1 the current is the on-asymptote throughout. (`cycle_average`
    // starts it from zero instead, ~9 % low at 25 kHz; the controller's
    // duty stays below 1 above the cut-off, so the sim never meets it.)
    let i0 = if t_off <= 0.0 {
        a_on.max(0.0)
    } else if i0_ccm > 0.0 {
        i0_ccm
    } else {
        0.0
    };
    let (q_on, sq_on) = segment(a_on, i0, tau_on, t_on);
    let i1 = (a_on + (i0 - a_on) * x_on).max(0.0);
    let t_diode = if i0 > 0.0 || a_off >= 0.0 {
        t_off
    } else {
        (tau * (1.0 + i1 / -a_off).ln()).min(t_off)
    };
    let (q_d, sq_d) = segment(a_off, i1, tau, t_diode);
    let q_d = q_d.max(0.0);
    PeriodLosses {
        supply_current_a: q_on / period,
        motor_current_a: (q_on + q_d) / period,
        winding_w: r * (sq_on + sq_d) / period,
        diode_w: drive.diode_drop_v * q_d / period,
        source_w: source_ohm * sq_on / period,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_cycle_average_and_balances_power() {
        let m = Motor::coreless_6mm();
        for &(duty, v, w, rs) in &[
            (0.75, 4.0, 6.0, 0.0),
            (0.3, 3.7, 300.0, 0.0),
            (1.0, 4.2, 10.0, 0.0),
            (0.05, 3.5, 1.0, 0.0),
            (0.75, 4.0, 6.0, 0.6),
            (0.3, 3.7, 300.0, 1.5),
            (1.0, 4.2, 10.0, 0.6),
        ] {
            let c = PwmDrive::BOARD.cycle_average_through(&m, duty, v, rs, w);
            let l = period_losses_through(&PwmDrive::BOARD, &m, duty, v, rs, w);
            assert!((l.supply_current_a - c.supply_current_a).abs() < 1e-12);
            assert!((l.motor_current_a - c.motor_current_a).abs() < 1e-12);
            // The mean current follows the mean motor voltage.
            let from_v = (c.motor_v - m.back_emf_v(w)) / m.params.resistance_ohm;
            assert!((from_v - c.motor_current_a).abs() < 1e-9, "{c:?}");
            let out = l.source_w + l.winding_w + l.diode_w + m.back_emf_v(w) * l.motor_current_a;
            let inp = v * l.supply_current_a;
            assert!(
                (out - inp).abs() < 1e-9 * inp.max(1e-9),
                "{duty} {v} {w}: {inp} vs {out}"
            );
        }
    }
}
