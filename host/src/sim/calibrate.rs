//! `swimbot sim --fit-motor`: one DC motor for all cases. The paper could
//! not measure its motor; it observed the tail rate `f` per tail (Table II)
//! and assumed the motor torque constant. At steady state the motor's
//! torque line equals the tail's hydrodynamic load from the swimmer model
//! ([`Hydro`], eq. 11 with the motor between body and tail):
//!
//! `T_s - s w_i = tau_0,i + c_i w_i`,  `w_i = (2 pi f_i - Omega_0,i) / (1 + dOmega/dw)`
//!
//! with `T_s` the effective stall torque (`k V / R - tau_c`) and `s` the
//! torque-speed slope (`k² / R + b`). This is linear in `(T_s, s)`: solved
//! by linear least squares on the relative misfit of the motor rate,
//! `(T_s - tau_0,i - (c_i + s) w_i) / ((c_i + s) w_i)`, reweighted until `s`
//! settles. A constant torque (`s = 0`, the paper's
//! assumption) is the one-parameter special case. Each fit then predicts
//! `f` and `Omega_b` per case; so does the robot file's motor, to show
//! whether a plausible motor reproduces the observed rates with the
//! model's load.

use super::hydro::Hydro;
use super::motor_profile::{self, Assumed, Calibration, Observed};
use super::robot::Robot;
use super::SimError;
use crate::data::{Case, Dataset};
use crate::format::fmt_sig;
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// One case under one motor: predicted tail rate (lab) and body counter-rotation (Hz).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Rates {
    pub f_hz: f64,
    pub omega_b_hz: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct CaseFit {
    pub id: String,
    pub f_obs_hz: f64,
    pub omega_b_obs_hz: Option<f64>,
    /// Torque the motor must give at the observed f (N m).
    pub torque_needed_n_m: f64,
    /// Tail load per unit motor rate (N m s).
    pub damping_n_m_s: f64,
    pub line: Rates,
    pub constant: Rates,
    pub robot_motor: Rates,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct MotorFit {
    pub stall_torque_n_m: f64,
    pub slope_n_m_s: f64,
    pub no_load_rad_s: f64,
    /// `k` from the stall torque and from the slope, with the robot's
    /// `R`, target voltage and friction: one motor needs them equal.
    pub k_from_stall_n_m_per_a: f64,
    pub k_from_slope_n_m_per_a: Option<f64>,
    pub constant_torque_n_m: f64,
    /// The robot file's motor at the controller's target voltage.
    pub robot_stall_n_m: f64,
    pub robot_slope_n_m_s: f64,
    pub cases: Vec<CaseFit>,
    /// The motor `(k, b)` with profile intervals ([`motor_profile`]).
    pub calibration: Option<Calibration>,
}

/// Confidence level of the calibration's intervals.
pub const LEVEL: f64 = 0.95;

/// Per-case pieces of the steady balance.
struct Load {
    hydro: Hydro,
    w_obs: f64,
    tau: f64,
}

impl Load {
    fn rates(&self, stall: f64, slope: f64) -> Rates {
        let h = &self.hydro;
        let w = ((stall - h.tau0_n_m) / (h.damping_n_m_s + slope)).max(0.0);
        let body = h.v0[3] + h.dv[3] * w;
        Rates {
            f_hz: (w + body) / TAU,
            omega_b_hz: -body / TAU,
        }
    }
}

pub fn fit_motor(robot: &Robot, data: &Dataset) -> Result<MotorFit, SimError> {
    let loads = data
        .cases
        .iter()
        .map(|case: &Case| {
            let hydro = Hydro::new(&robot.model, case)?;
            let w_obs = (case.tail_rate_rad_s() - hydro.v0[3]) / (1.0 + hydro.dv[3]);
            let tau = hydro.motor_torque_n_m(w_obs);
            Ok(Load { hydro, w_obs, tau })
        })
        .collect::<Result<Vec<_>, SimError>>()?;
    if loads.len() < 2 {
        return Err(SimError::Input(
            "--fit-motor needs at least two cases".into(),
        ));
    }
    // Relative f misfit: (T_s - tau_0 - (c + s) w) / ((c + s) w) is linear in
    // (T_s, s) once the weight's s is frozen, so iterate the reweighting
    // (converges in a few passes: the weights depend weakly on s).
    let (mut stall, mut slope) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for l in &loads {
            let wt = ((l.hydro.damping_n_m_s + slope.max(0.0)) * l.w_obs).powi(-2);
            let y = l.hydro.tau0_n_m + l.hydro.damping_n_m_s * l.w_obs;
            a11 += wt;
            a12 -= wt * l.w_obs;
            a22 += wt * l.w_obs * l.w_obs;
            b1 += wt * y;
            b2 -= wt * l.w_obs * y;
        }
        let det = a11 * a22 - a12 * a12;
        if det.abs() <= 1e-300 || det.is_nan() {
            return Err(SimError::Input(
                "--fit-motor: all cases have the same motor rate; the slope is not identifiable"
                    .into(),
            ));
        }
        let next = ((b1 * a22 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det);
        let done = (next.1 - slope).abs() <= 1e-12 * next.1.abs();
        (stall, slope) = next;
        if done {
            break;
        }
    }
    let (mut sw, mut swt) = (0.0, 0.0);
    for l in &loads {
        let wt = 1.0 / (l.tau * l.tau);
        sw += wt;
        swt += wt * l.tau;
    }
    let constant = swt / sw;
    let m = &robot.motor;
    let volts = f64::from(robot.controller.target_motor_mv) * 1e-3;
    let k = m.torque_constant_n_m_per_a;
    let robot_stall = k * volts / m.resistance_ohm - m.coulomb_friction_n_m;
    let robot_slope = k * k / m.resistance_ohm + m.viscous_friction_n_m_s;
    let k_slope = slope - m.viscous_friction_n_m_s;
    let cases = data
        .cases
        .iter()
        .zip(&loads)
        .map(|(c, l)| CaseFit {
            id: c.id.clone(),
            f_obs_hz: c.frequency_hz,
            omega_b_obs_hz: c.omega_body_hz.map(|m| m.mean),
            torque_needed_n_m: l.tau,
            damping_n_m_s: l.hydro.damping_n_m_s,
            line: l.rates(stall, slope),
            constant: l.rates(constant, 0.0),
            robot_motor: l.rates(robot_stall, robot_slope),
        })
        .collect();
    let observed: Vec<Observed> = loads
        .iter()
        .zip(&data.cases)
        .map(|(l, c)| Observed {
            hydro: l.hydro.clone(),
            f_obs_hz: c.frequency_hz,
        })
        .collect();
    let assumed = Assumed {
        resistance_ohm: m.resistance_ohm,
        volts,
        coulomb_n_m: m.coulomb_friction_n_m,
    };
    Ok(MotorFit {
        calibration: motor_profile::calibrate(&observed, assumed, LEVEL),
        stall_torque_n_m: stall,
        slope_n_m_s: slope,
        no_load_rad_s: stall / slope,
        k_from_stall_n_m_per_a: (stall + m.coulomb_friction_n_m) * m.resistance_ohm / volts,
        k_from_slope_n_m_per_a: (k_slope > 0.0).then(|| (k_slope * m.resistance_ohm).sqrt()),
        constant_torque_n_m: constant,
        robot_stall_n_m: robot_stall,
        robot_slope_n_m_s: robot_slope,
        cases,
    })
}

fn rel(pred: f64, obs: f64) -> f64 {
    pred / obs - 1.0
}

/// RMS relative error of `f` under one of the motors.
pub fn rms_f_error(fit: &MotorFit, pick: fn(&CaseFit) -> Rates) -> f64 {
    let n = fit.cases.len() as f64;
    (fit.cases
        .iter()
        .map(|c| rel(pick(c).f_hz, c.f_obs_hz).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

pub fn report(robot: &Robot, data: &Dataset, fit: &MotorFit) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "model: {}   data: {}", robot.model.describe(), data.name);
    let _ = writeln!(
        s,
        "observed f taken as the tail's lab-frame rate; load = the model's tail torque at that f\n"
    );
    let _ = writeln!(
        s,
        "{:<8} {:>6} {:>10} {:>10} | {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} {:>7}",
        "case",
        "f obs",
        "tau need",
        "c",
        "f line",
        "err",
        "f const",
        "err",
        "f robot",
        "err",
        "Ω obs",
        "Ω line",
        "err"
    );
    for c in &fit.cases {
        let om_err = c.omega_b_obs_hz.map_or("-".into(), |o| {
            format!("{:+.1}%", 100.0 * rel(c.line.omega_b_hz, o))
        });
        let _ = writeln!(
            s,
            "{:<8} {:>6} {:>10} {:>10} | {:>7} {:>+6.1}% | {:>7} {:>+6.1}% | {:>7} {:>+6.0}% | {:>7} {:>7} {:>7}",
            c.id,
            fmt_sig(c.f_obs_hz, 3),
            fmt_sig(c.torque_needed_n_m, 3),
            fmt_sig(c.damping_n_m_s, 3),
            fmt_sig(c.line.f_hz, 3),
            100.0 * rel(c.line.f_hz, c.f_obs_hz),
            fmt_sig(c.constant.f_hz, 3),
            100.0 * rel(c.constant.f_hz, c.f_obs_hz),
            fmt_sig(c.robot_motor.f_hz, 3),
            100.0 * rel(c.robot_motor.f_hz, c.f_obs_hz),
            c.omega_b_obs_hz.map_or("-".into(), |o| fmt_sig(o, 3)),
            fmt_sig(c.line.omega_b_hz, 3),
            om_err
        );
    }
    let _ = writeln!(s, "\n(tau need: N m at the observed f; c: load per motor rate, N m s; Ω: body counter-rotation, Hz)");
    let _ = writeln!(
        s,
        "torque-speed line (one motor): stall {} N m, slope {} N m s, no-load {} rad/s; RMS f error {:.1} %",
        fmt_sig(fit.stall_torque_n_m, 4),
        fmt_sig(fit.slope_n_m_s, 4),
        fmt_sig(fit.no_load_rad_s, 4),
        100.0 * rms_f_error(fit, |c| c.line)
    );
    let _ = writeln!(
        s,
        "  as a motor (robot's R, {} V, friction): k = {} N m/A from the stall torque, {} from the slope{}",
        fmt_sig(f64::from(robot.controller.target_motor_mv) * 1e-3, 3),
        fmt_sig(fit.k_from_stall_n_m_per_a, 3),
        fit.k_from_slope_n_m_per_a.map_or("none (slope below the friction b)".into(), |k| fmt_sig(k, 3)),
        if fit.slope_n_m_s <= 0.0 { "; slope <= 0: torque rising with speed, no DC motor does that" } else { "" }
    );
    let k = fit.k_from_stall_n_m_per_a;
    let _ = writeln!(
        s,
        "  or: k = {} N m/A and a speed-proportional drag b = s - k²/R = {} N m s (bearing/seal), the robot file has b = {}",
        fmt_sig(k, 3),
        fmt_sig(fit.slope_n_m_s - k * k / robot.motor.resistance_ohm, 3),
        fmt_sig(robot.motor.viscous_friction_n_m_s, 3)
    );
    let _ = writeln!(
        s,
        "constant torque (the paper's assumption): {} N m; RMS f error {:.1} %",
        fmt_sig(fit.constant_torque_n_m, 4),
        100.0 * rms_f_error(fit, |c| c.constant)
    );
    let _ = writeln!(
        s,
        "the robot file's motor at the target voltage (stall {} N m, slope {} N m s): RMS f error {:.0} %",
        fmt_sig(fit.robot_stall_n_m, 4),
        fmt_sig(fit.robot_slope_n_m_s, 4),
        100.0 * rms_f_error(fit, |c| c.robot_motor)
    );
    if let Some(c) = &fit.calibration {
        calibration_report(&mut s, c);
    }
    s
}

fn interval_text(iv: &motor_profile::Interval) -> String {
    let lo = if iv.lo_at_bound {
        "0 (bound)".to_string()
    } else {
        fmt_sig(iv.lo, 3)
    };
    let hi = iv.hi.map_or("unbounded".into(), |h| fmt_sig(h, 3));
    format!("{} [{lo}, {hi}]", fmt_sig(iv.best, 3))
}

fn calibration_report(s: &mut String, c: &Calibration) {
    let a = &c.assumed;
    let _ = writeln!(
        s,
        "\ncalibrated motor (least squares in f, b >= 0; R = {} ohm, V = {} V, Coulomb friction {} N m assumed):",
        fmt_sig(a.resistance_ohm, 3),
        fmt_sig(a.volts, 3),
        fmt_sig(a.coulomb_n_m, 3)
    );
    let _ = writeln!(
        s,
        "  k = {} N m/A, b = {} N m s ({:.0} % profile intervals); RMS f error {:.1} %",
        interval_text(&c.k_n_m_per_a),
        interval_text(&c.b_n_m_s),
        100.0 * c.level,
        100.0 * c.rms_f
    );
    let _ = writeln!(
        s,
        "  k with Coulomb friction 0 / twice the assumed: {} / {} N m/A (rates at one voltage cannot separate them)",
        fmt_sig(c.k_if_coulomb_0_and_2x.0, 3),
        fmt_sig(c.k_if_coulomb_0_and_2x.1, 3)
    );
}
