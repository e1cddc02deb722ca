//! The whole robot in time: remote edges and the battery input -> the
//! firmware's own main-loop pass (`swimbot_shared::MainLoop`, the code
//! `firmware/src/run.rs` calls: the chip's rate control fed the simulated
//! Hall edges with `--rate-hz`, the host's voltage-mode controller in its
//! place otherwise; [`super::rate`]) -> PWM drive (cycle average)
//! -> motor -> the swimmer's hydrodynamics -> height in the channel; the
//! cell discharges.
//!
//! Per tick `dt` (1 ms by default, one pass a tick):
//! * the battery input, when the pass asks for a reading, sees the previous
//!   tick's load as the firmware's ADC does: by default the terminal
//!   voltage in the middle of the on-pulse, `OCV - R_int i_mid`, where the
//!   firmware converts (`firmware/src/battery_adc.rs`);
//!   [`BatteryReading::CycleMean`] reads `OCV - R_int I_s` instead, what
//!   an RC filter on the divider tap would give;
//! * cell and drive: the cell's `OCV(soc)` behind `R_int`, in the motor's
//!   loop while the switch is on ([`crate::robot::PwmDrive::cycle_average_through`]):
//!   each pulse sags the terminals by `R_int i`; the mean terminal voltage
//!   is `V = OCV - R_int I_s`, `I_s` the mean supply current;
//! * motor (`Motor::step_implicit`): `L di/dt = v - R i - k w`,
//!   `J dw/dt = k i - b w - tau_c sgn(w) - tau_m(w)`, `w` the rate of the
//!   tail relative to the body, `J` rotor + coupler + tail;
//! * hydrodynamics ([`Hydro`]): `tau_m = tau_0 + c w` and `V = [U; Omega_b]`
//!   from eq. 11 with the motor between body and tail (quasi-static: the
//!   Stokes flow has no memory, and the body's own inertia is neglected);
//! * `dh/dt = U`.
//!
//! Energy ledger (J): the cell's `OCV I_s`, against internal, winding,
//! diode, friction and hydrodynamic losses, the external load's work and
//! the stored kinetic and magnetic energy.

use super::drive::period_losses_through;
use super::hydro::Hydro;
pub use super::outcome::{End, Energy, Outcome, Sample};
use super::rate::{Driver, RatePoint, RateRun};
use super::robot::Robot;
use super::script::Script;
use super::SimError;
use crate::robot::motor::FRICTION_SMOOTHING_RAD_S;
use crate::robot::MotorState;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::TAU;
use swimbot_shared::rate::{RateEvent, SensorFault};
use swimbot_shared::run_log::Recorder;
use swimbot_shared::{
    Controller, Event, MainLoop, MainLoopConfig, MotorControl, MotorState as State, StopReason,
};

/// What to simulate beyond the robot and the script.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Index of the tail in the robot's list.
    pub tail: usize,
    /// Give up after this much robot time (s).
    pub max_time_s: f64,
    /// Keep one sample every this many seconds.
    pub sample_every_s: f64,
    /// End when the nose reaches the channel's top.
    pub stop_at_top: bool,
    /// What the battery input converts.
    pub battery_reading: BatteryReading,
}

/// Where in the PWM period the battery is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BatteryReading {
    /// In the middle of the on-pulse: the loaded voltage the motor sees,
    /// what the firmware does.
    #[default]
    MidOnPulse,
    /// The cycle mean, as behind an RC filter on the divider tap (corner
    /// well below the carrier).
    CycleMean,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tail: 0,
            max_time_s: 1800.0,
            sample_every_s: 0.1,
            stop_at_top: true,
            battery_reading: BatteryReading::MidOnPulse,
        }
    }
}

/// Spacing of the rate trace: fine enough for settling times, a tenth of
/// the memory of every tick.
pub const RATE_TRACE_EVERY_US: u64 = 10_000;

/// The robot in voltage mode (the firmware today).
pub fn simulate(robot: &Robot, script: &Script, opts: &Options) -> Result<Outcome, SimError> {
    simulate_with(robot, script, opts, None)
}

/// The robot, rate-controlled when `rate` is given.
pub fn simulate_with(
    robot: &Robot,
    script: &Script,
    opts: &Options,
    rate: Option<&RateRun>,
) -> Result<Outcome, SimError> {
    let tail = robot.tails.get(opts.tail).ok_or_else(|| {
        SimError::Input(format!(
            "tail index {} out of range (the robot has {})",
            opts.tail,
            robot.tails.len()
        ))
    })?;
    let hydro = Hydro::new(&robot.model, &robot.case(opts.tail, 1.0))?;
    let motor = robot.motor_with(opts.tail);
    let mp = motor.params;
    let cell = &robot.cell;
    let capacity_c = cell.capacity_mah * 3.6;
    let mut charge_c = cell.initial_soc * capacity_c;
    let (tick_us, dt) = (robot.tick_us, robot.tick_us as f64 * 1e-6);
    let board = MainLoopConfig {
        keys: robot.keys,
        battery: robot.battery,
        sample_period_us: robot.adc_period_us,
        ..MainLoopConfig::BOARD
    };
    let driver = Driver::new(Controller::new(robot.controller), rate);
    let mut main_loop = MainLoop::with_control(board, driver, false);
    // The Hall edges of the last tick, queued for the next pass as the
    // chip's interrupt queues them.
    let mut hall_queue = Vec::new();
    let mut rate_faults = Vec::new();
    // ADC noise only where asked for (rate runs): voltage-mode runs stay
    // exactly what they were.
    let adc_sd = rate.map_or(0.0, |r| r.noise.adc_noise_lsb.abs());
    let adc_noise = Normal::new(0.0, adc_sd).ok().filter(|_| adc_sd > 0.0);
    let mut rng = rand::rngs::StdRng::seed_from_u64(rate.map_or(0, |r| r.noise.seed ^ 0xadc));
    let mut rate_trace = Vec::new();
    let mut next_trace_us = 0u64;
    let edges = script.edges(&robot.keys);
    let mut next_edge = 0;
    let script_end_us = edges.last().map_or(0, |e| e.1);
    let channel_mm = robot.setup.channel_length_mm;
    let start_height_mm = robot.start_height_mm(opts.tail);
    let sample_every_us = ((opts.sample_every_s * 1e6) as u64).max(tick_us);
    let max_us = (opts.max_time_s * 1e6) as u64;

    let (mut t_us, mut next_sample_us) = (0u64, 0u64);
    let (mut s, mut height_mm, mut supply_a, mut mid_on_a) =
        (MotorState::REST, start_height_mm, 0.0f64, 0.0f64);
    let mut energy = Energy::default();
    let stored = |s: &MotorState| {
        0.5 * motor.inertia_kg_m2() * s.speed_rad_s.powi(2)
            + 0.5 * mp.inductance_h * s.current_a.powi(2)
    };
    let (mut events, mut commands, mut samples) = (Vec::new(), Vec::new(), Vec::new());
    let (mut running_s, mut sum_u, mut sum_f, mut sum_om) = (0.0, 0.0, 0.0, 0.0);
    let mut top_reached_s = None;
    let mut last_stop = None;
    let mut last_stop_s = f64::NEG_INFINITY;
    let mut ticks = 0u64;
    let mut battery_readings = Vec::new();
    let mut recorder = Recorder::new(swimbot_shared::board::LOG_PERIOD_US);
    let mut log_records = Vec::new();
    let sample_now =
        |t_us: u64, duty: f64, v: (f64, f64), i_s: f64, s: &MotorState, h: f64, q: f64, state| {
            let vel = hydro.velocity(s.speed_rad_s);
            Sample {
                t_s: t_us as f64 * 1e-6,
                duty,
                battery_v: v.0,
                loaded_v: v.1,
                current_a: i_s,
                motor_current_a: s.current_a,
                motor_rate_hz: s.speed_rad_s / TAU,
                tail_rate_hz: (s.speed_rad_s + vel[3]) / TAU,
                body_rate_hz: vel[3] / TAU,
                u_mm_s: vel[0] * 1e3,
                height_mm: h,
                soc: q / capacity_c,
                state,
            }
        };
    let mut last: Sample;
    let end = loop {
        t_us += tick_us;
        ticks += 1;
        let first_edge = next_edge;
        while edges.get(next_edge).is_some_and(|e| e.1 <= t_us) {
            next_edge += 1;
        }
        // The firmware timestamps with the timer's low 32 bits.
        let tick_edges = edges[first_edge..next_edge]
            .iter()
            .map(|&(level, t)| (level, t as u32));
        let ocv = cell.ocv_v(charge_c / capacity_c);
        let read_adc = || {
            let i_a = match opts.battery_reading {
                BatteryReading::MidOnPulse => mid_on_a,
                BatteryReading::CycleMean => supply_a,
            };
            let v = ocv - cell.internal_resistance_ohm * i_a;
            let counts = robot
                .battery
                .mv_to_counts((v * 1e3).round().max(0.0) as u32);
            match adc_noise {
                Some(n) => {
                    (f64::from(counts) + n.sample(&mut rng).round()).clamp(0.0, 4095.0) as u16
                }
                None => counts,
            }
        };
        let out = main_loop.pass(t_us, tick_edges, hall_queue.drain(..), read_adc);
        log_records.extend(recorder.observe(t_us, &out));
        let t_s = t_us as f64 * 1e-6;
        if let Some(f) = out.fault {
            rate_faults.push((t_s, RateEvent::Fault(f)));
        }
        if out.refused_no_set_point {
            rate_faults.push((t_s, RateEvent::NoSetPoint));
        }
        if let Some(counts) = out.sample {
            battery_readings.push((t_us, counts));
        }
        if let Some(c) = out.command {
            commands.push((t_us as f64 * 1e-6, c));
        }
        if let Some(e) = out.event {
            if let Event::Stopped(r) = e {
                last_stop = Some(r);
                last_stop_s = t_us as f64 * 1e-6;
            }
            events.push((t_us as f64 * 1e-6, e));
        }
        let d = out.duty.as_f64();
        let r_int = cell.internal_resistance_ohm;
        let means = robot
            .drive
            .cycle_average_through(&motor, d, ocv, r_int, s.speed_rad_s);
        supply_a = means.supply_current_a;
        mid_on_a = means.mid_on_current_a;
        let v = ocv - r_int * supply_a;
        let losses = period_losses_through(&robot.drive, &motor, d, ocv, r_int, s.speed_rad_s);
        let stored_before = stored(&s);
        let w_old = s.speed_rad_s;
        s = motor.step_implicit(
            s,
            means.motor_v,
            hydro.motor_torque_n_m(w_old),
            hydro.damping_n_m_s,
            dt,
        );
        let w = s.speed_rad_s;
        hall_queue = main_loop
            .control_mut()
            .turned(0.5 * (w_old + w) * dt, t_us, dt);
        charge_c = (charge_c - supply_a * dt).clamp(0.0, capacity_c);
        let vel = hydro.velocity(w);
        height_mm += vel[0] * 1e3 * dt;

        energy.cell_j += ocv * supply_a * dt;
        energy.internal_j += losses.source_w * dt;
        energy.winding_j += losses.winding_w * dt;
        energy.diode_j += losses.diode_w * dt;
        let friction_n_m = mp.viscous_friction_n_m_s * w
            + mp.coulomb_friction_n_m * (w / FRICTION_SMOOTHING_RAD_S).tanh();
        energy.friction_j += friction_n_m * w * dt;
        energy.hydro_j += hydro.dissipation_w(w) * dt;
        energy.external_j += hydro.external_power_w(w) * dt;
        energy.stored_j += stored(&s) - stored_before;

        if out.state == State::Running {
            running_s += dt;
            sum_u += vel[0] * 1e3 * dt;
            sum_f += (w + vel[3]) / TAU * dt;
            sum_om += -vel[3] / TAU * dt;
        }
        let loaded_v = ocv - cell.internal_resistance_ohm * mid_on_a;
        last = sample_now(
            t_us,
            d,
            (v, loaded_v),
            supply_a,
            &s,
            height_mm,
            charge_c,
            out.state,
        );
        if let (Some(run), true) = (rate, t_us >= next_trace_us) {
            next_trace_us += RATE_TRACE_EVERY_US;
            rate_trace.push(RatePoint {
                t_s: last.t_s,
                set_hz: run.set_hz_at(t_us).unwrap_or(0.0),
                reference_hz: f64::from(out.reference_mhz) / 1e3,
                measured_hz: main_loop
                    .control()
                    .rate_mhz()
                    .map_or(f64::NAN, |r| f64::from(r) / 1e3),
                motor_rate_hz: last.motor_rate_hz,
                duty: d,
                battery_v: v,
                running: out.state == State::Running,
            });
        }
        if t_us >= next_sample_us {
            next_sample_us += sample_every_us;
            samples.push(last);
        }
        if height_mm >= channel_mm && top_reached_s.is_none() {
            top_reached_s = Some(t_us as f64 * 1e-6);
            if opts.stop_at_top {
                break End::TopReached;
            }
        }
        let at_rest = out.state == State::Off
            && w.abs() < 1e-3
            && next_edge == edges.len()
            && t_us > script_end_us + 2_000_000;
        if at_rest {
            if let Some(f) = last_fault_after(&rate_faults, last_stop_s) {
                break End::SensorFault(f);
            }
            break last_stop
                .filter(|r| *r != StopReason::Command)
                .map_or(End::Idle, End::Stopped);
        }
        if t_us >= max_us {
            break End::TimeLimit;
        }
    };
    if samples.last().map(|x| x.t_s) != Some(last.t_s) {
        samples.push(last);
    }
    // 0 when the motor never ran (`running_s == 0`): the summary says so
    // instead of printing a mean over nothing.
    let mean = |x: f64| if running_s > 0.0 { x / running_s } else { 0.0 };
    Ok(Outcome {
        tail_id: tail.id.clone(),
        hydro,
        samples,
        last,
        events,
        commands,
        end,
        top_reached_s,
        start_height_mm,
        channel_length_mm: channel_mm,
        running_s,
        mean_u_mm_s: mean(sum_u),
        mean_f_hz: mean(sum_f),
        mean_omega_b_hz: mean(sum_om),
        energy,
        ticks,
        rate_faults,
        rate_trace,
        battery_readings,
        log_records,
    })
}

/// The last sensor fault, if it came after `after_s`.
fn last_fault_after(faults: &[(f64, RateEvent)], after_s: f64) -> Option<SensorFault> {
    faults.iter().rev().find_map(|&(t, e)| match e {
        RateEvent::Fault(f) if t >= after_s => Some(f),
        _ => None,
    })
}
