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
use crate::robot::{Motor, MotorState};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::TAU;
use swimbot_shared::rate::{RateEvent, SensorFault};
use swimbot_shared::run_log::Recorder;
use swimbot_shared::{
    Controller, Event, HallEdge, Level, MainLoop, MainLoopConfig, MotorControl,
    MotorState as State, PassOutput, StopReason,
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
    let mut sim = Simulation::new(robot, script, opts, rate)?;
    let end = loop {
        if let Some(end) = sim.step() {
            break end;
        }
    };
    Ok(sim.finish(end))
}

/// A run in progress: the robot's state at the current tick and what the
/// run has recorded so far. [`Simulation::step`] advances one tick (one
/// pass of the firmware's main loop); [`Simulation::finish`] gives the
/// [`Outcome`].
pub struct Simulation<'a> {
    robot: &'a Robot,
    opts: &'a Options,
    rate: Option<&'a RateRun>,
    tail_id: String,
    hydro: Hydro,
    motor: Motor,
    main_loop: MainLoop<Driver>,
    /// The Hall edges of the last tick, queued for the next pass as the
    /// chip's interrupt queues them.
    hall_queue: Vec<HallEdge>,
    adc: AdcNoise,
    /// The remote's edges (timer microseconds) and the next one to send.
    edges: Vec<(Level, u64)>,
    next_edge: usize,
    clock: Clock,
    now: Physical,
    energy: Energy,
    running: RunningMeans,
    record: Record,
}

/// Time: the tick, and when the next sample and trace point are due.
struct Clock {
    t_us: u64,
    tick_us: u64,
    dt_s: f64,
    ticks: u64,
    next_sample_us: u64,
    sample_every_us: u64,
    next_trace_us: u64,
    max_us: u64,
    script_end_us: u64,
}

/// The physical state carried from tick to tick.
struct Physical {
    motor: MotorState,
    height_mm: f64,
    charge_c: f64,
    /// Mean supply current and the current in the middle of the on-pulse
    /// over the last tick: what the next battery reading sees.
    supply_a: f64,
    mid_on_a: f64,
}

/// Time-weighted sums over the ticks the motor ran.
#[derive(Default)]
struct RunningMeans {
    running_s: f64,
    sum_u: f64,
    sum_f: f64,
    sum_om: f64,
}

/// The battery input's noise: ADC noise only where asked for (rate runs),
/// so that voltage-mode runs stay exactly what they were.
struct AdcNoise {
    normal: Option<Normal<f64>>,
    rng: rand::rngs::StdRng,
}

/// What the run keeps.
struct Record {
    events: Vec<(f64, Event)>,
    commands: Vec<(f64, swimbot_shared::Command)>,
    samples: Vec<Sample>,
    last: Option<Sample>,
    rate_faults: Vec<(f64, RateEvent)>,
    rate_trace: Vec<RatePoint>,
    battery_readings: Vec<(u64, u16)>,
    recorder: Recorder,
    log_records: Vec<swimbot_shared::run_log::Record>,
    top_reached_s: Option<f64>,
    last_stop: Option<StopReason>,
    last_stop_s: f64,
}

impl<'a> Simulation<'a> {
    /// The robot at rest at its start height, before the first tick.
    pub fn new(
        robot: &'a Robot,
        script: &Script,
        opts: &'a Options,
        rate: Option<&'a RateRun>,
    ) -> Result<Self, SimError> {
        let tail = robot.tails.get(opts.tail).ok_or_else(|| {
            SimError::Input(format!(
                "tail index {} out of range (the robot has {})",
                opts.tail,
                robot.tails.len()
            ))
        })?;
        let hydro = Hydro::new(&robot.model, &robot.case(opts.tail, 1.0))?;
        let board = MainLoopConfig {
            keys: robot.keys,
            battery: robot.battery,
            sample_period_us: robot.adc_period_us,
            ..MainLoopConfig::BOARD
        };
        let driver = Driver::new(Controller::new(robot.controller), rate);
        let adc_sd = rate.map_or(0.0, |r| r.noise.adc_noise_lsb.abs());
        let edges = script.edges(&robot.keys);
        let tick_us = robot.tick_us;
        let cell = &robot.cell;
        Ok(Simulation {
            robot,
            opts,
            rate,
            tail_id: tail.id.clone(),
            hydro,
            motor: robot.motor_with(opts.tail),
            main_loop: MainLoop::with_control(board, driver, false),
            hall_queue: Vec::new(),
            adc: AdcNoise {
                normal: Normal::new(0.0, adc_sd).ok().filter(|_| adc_sd > 0.0),
                rng: rand::rngs::StdRng::seed_from_u64(rate.map_or(0, |r| r.noise.seed ^ 0xadc)),
            },
            next_edge: 0,
            clock: Clock {
                t_us: 0,
                tick_us,
                dt_s: tick_us as f64 * 1e-6,
                ticks: 0,
                next_sample_us: 0,
                sample_every_us: ((opts.sample_every_s * 1e6) as u64).max(tick_us),
                next_trace_us: 0,
                max_us: (opts.max_time_s * 1e6) as u64,
                script_end_us: edges.last().map_or(0, |e| e.1),
            },
            edges,
            now: Physical {
                motor: MotorState::REST,
                height_mm: robot.start_height_mm(opts.tail),
                charge_c: cell.initial_soc * cell.capacity_mah * 3.6,
                supply_a: 0.0,
                mid_on_a: 0.0,
            },
            energy: Energy::default(),
            running: RunningMeans::default(),
            record: Record {
                events: Vec::new(),
                commands: Vec::new(),
                samples: Vec::new(),
                last: None,
                rate_faults: Vec::new(),
                rate_trace: Vec::new(),
                battery_readings: Vec::new(),
                recorder: Recorder::new(swimbot_shared::board::LOG_PERIOD_US),
                log_records: Vec::new(),
                top_reached_s: None,
                last_stop: None,
                last_stop_s: f64::NEG_INFINITY,
            },
        })
    }

    fn capacity_c(&self) -> f64 {
        self.robot.cell.capacity_mah * 3.6
    }

    /// One tick: the firmware's pass, then the drive, the motor and the
    /// swimmer over `dt`; `Some` when the run ends at this tick.
    pub fn step(&mut self) -> Option<End> {
        self.clock.t_us += self.clock.tick_us;
        self.clock.ticks += 1;
        // The cell's open-circuit voltage at the tick's start: what the
        // pass reads and the drive sees for the whole tick.
        let ocv = self.robot.cell.ocv_v(self.now.charge_c / self.capacity_c());
        let out = self.pass(ocv);
        let d = out.duty.as_f64();
        let (v, w, vel) = self.advance(ocv, d);
        if out.state == State::Running {
            let dt = self.clock.dt_s;
            self.running.running_s += dt;
            self.running.sum_u += vel[0] * 1e3 * dt;
            self.running.sum_f += (w + vel[3]) / TAU * dt;
            self.running.sum_om += -vel[3] / TAU * dt;
        }
        let loaded_v = ocv - self.robot.cell.internal_resistance_ohm * self.now.mid_on_a;
        self.observe(&out, d, (v, loaded_v));
        self.end(&out, w)
    }

    /// The firmware's main-loop pass at this tick: the remote's edges, the
    /// Hall edges of the last tick and the battery input; its outputs
    /// recorded.
    fn pass(&mut self, ocv: f64) -> PassOutput {
        let t_us = self.clock.t_us;
        let first_edge = self.next_edge;
        while self.edges.get(self.next_edge).is_some_and(|e| e.1 <= t_us) {
            self.next_edge += 1;
        }
        // The firmware timestamps with the timer's low 32 bits.
        let tick_edges = self.edges[first_edge..self.next_edge]
            .iter()
            .map(|&(level, t)| (level, t as u32));
        let (robot, opts, now, adc) = (self.robot, self.opts, &self.now, &mut self.adc);
        let read_adc = || {
            let i_a = match opts.battery_reading {
                BatteryReading::MidOnPulse => now.mid_on_a,
                BatteryReading::CycleMean => now.supply_a,
            };
            let v = ocv - robot.cell.internal_resistance_ohm * i_a;
            let counts = robot
                .battery
                .mv_to_counts((v * 1e3).round().max(0.0) as u32);
            match adc.normal {
                Some(n) => {
                    (f64::from(counts) + n.sample(&mut adc.rng).round()).clamp(0.0, 4095.0) as u16
                }
                None => counts,
            }
        };
        let out = self
            .main_loop
            .pass(t_us, tick_edges, self.hall_queue.drain(..), read_adc);
        self.record.outputs(t_us, &out);
        out
    }

    /// Drive, motor and swimmer over one tick at duty `d`: returns the mean
    /// terminal voltage, the motor's new rate (rad/s) and the swimmer's
    /// velocity.
    fn advance(&mut self, ocv: f64, d: f64) -> (f64, f64, nalgebra::Vector6<f64>) {
        let (robot, motor, hydro, dt) = (self.robot, &self.motor, &self.hydro, self.clock.dt_s);
        let now = &mut self.now;
        let r_int = robot.cell.internal_resistance_ohm;
        let w_old = now.motor.speed_rad_s;
        let means = robot
            .drive
            .cycle_average_through(motor, d, ocv, r_int, w_old);
        now.supply_a = means.supply_current_a;
        now.mid_on_a = means.mid_on_current_a;
        let v = ocv - r_int * now.supply_a;
        let losses = period_losses_through(&robot.drive, motor, d, ocv, r_int, w_old);
        let stored = |s: &MotorState| {
            0.5 * motor.inertia_kg_m2() * s.speed_rad_s.powi(2)
                + 0.5 * motor.params.inductance_h * s.current_a.powi(2)
        };
        let stored_before = stored(&now.motor);
        now.motor = motor.step_implicit(
            now.motor,
            means.motor_v,
            hydro.motor_torque_n_m(w_old),
            hydro.damping_n_m_s,
            dt,
        );
        let w = now.motor.speed_rad_s;
        self.hall_queue =
            self.main_loop
                .control_mut()
                .turned(0.5 * (w_old + w) * dt, self.clock.t_us, dt);
        now.charge_c = (now.charge_c - now.supply_a * dt).clamp(0.0, robot.cell.capacity_mah * 3.6);
        let vel = hydro.velocity(w);
        now.height_mm += vel[0] * 1e3 * dt;

        let e = &mut self.energy;
        e.cell_j += ocv * now.supply_a * dt;
        e.internal_j += losses.source_w * dt;
        e.winding_j += losses.winding_w * dt;
        e.diode_j += losses.diode_w * dt;
        e.friction_j += motor.friction_n_m(w) * w * dt;
        e.hydro_j += hydro.dissipation_w(w) * dt;
        e.external_j += hydro.external_power_w(w) * dt;
        e.stored_j += stored(&now.motor) - stored_before;
        (v, w, vel)
    }

    /// The sample of this tick, kept when one is due, and the rate trace;
    /// `(v, loaded_v)` the mean and the on-pulse terminal voltages.
    fn observe(&mut self, out: &PassOutput, d: f64, (v, loaded_v): (f64, f64)) {
        let t_us = self.clock.t_us;
        let now = &self.now;
        let vel = self.hydro.velocity(now.motor.speed_rad_s);
        let last = Sample {
            t_s: t_us as f64 * 1e-6,
            duty: d,
            battery_v: v,
            loaded_v,
            current_a: now.supply_a,
            motor_current_a: now.motor.current_a,
            motor_rate_hz: now.motor.speed_rad_s / TAU,
            tail_rate_hz: (now.motor.speed_rad_s + vel[3]) / TAU,
            body_rate_hz: vel[3] / TAU,
            u_mm_s: vel[0] * 1e3,
            height_mm: now.height_mm,
            soc: now.charge_c / self.capacity_c(),
            state: out.state,
        };
        if let (Some(run), true) = (self.rate, t_us >= self.clock.next_trace_us) {
            self.clock.next_trace_us += RATE_TRACE_EVERY_US;
            self.record.rate_trace.push(RatePoint {
                t_s: last.t_s,
                set_hz: run.set_hz_at(t_us).unwrap_or(0.0),
                reference_hz: f64::from(out.reference_mhz) / 1e3,
                measured_hz: self
                    .main_loop
                    .control()
                    .rate_mhz()
                    .map_or(f64::NAN, |r| f64::from(r) / 1e3),
                motor_rate_hz: last.motor_rate_hz,
                duty: d,
                battery_v: v,
                running: out.state == State::Running,
            });
        }
        if t_us >= self.clock.next_sample_us {
            self.clock.next_sample_us += self.clock.sample_every_us;
            self.record.samples.push(last);
        }
        self.record.last = Some(last);
    }

    /// Whether the run ends at this tick, and how.
    fn end(&mut self, out: &PassOutput, w: f64) -> Option<End> {
        let t_us = self.clock.t_us;
        if self.now.height_mm >= self.robot.setup.channel_length_mm
            && self.record.top_reached_s.is_none()
        {
            self.record.top_reached_s = Some(t_us as f64 * 1e-6);
            if self.opts.stop_at_top {
                return Some(End::TopReached);
            }
        }
        let at_rest = out.state == State::Off
            && w.abs() < 1e-3
            && self.next_edge == self.edges.len()
            && t_us > self.clock.script_end_us + 2_000_000;
        if at_rest {
            if let Some(f) = last_fault_after(&self.record.rate_faults, self.record.last_stop_s) {
                return Some(End::SensorFault(f));
            }
            return Some(
                self.record
                    .last_stop
                    .filter(|r| *r != StopReason::Command)
                    .map_or(End::Idle, End::Stopped),
            );
        }
        (t_us >= self.clock.max_us).then_some(End::TimeLimit)
    }

    /// The run's outcome, ended by `end`.
    pub fn finish(self, end: End) -> Outcome {
        let mut record = self.record;
        let last = record.last.expect("finish after at least one step");
        if record.samples.last().map(|x| x.t_s) != Some(last.t_s) {
            record.samples.push(last);
        }
        let r = self.running;
        // 0 when the motor never ran (`running_s == 0`): the summary says so
        // instead of printing a mean over nothing.
        let mean = |x: f64| {
            if r.running_s > 0.0 {
                x / r.running_s
            } else {
                0.0
            }
        };
        Outcome {
            tail_id: self.tail_id,
            hydro: self.hydro,
            samples: record.samples,
            last,
            events: record.events,
            commands: record.commands,
            end,
            top_reached_s: record.top_reached_s,
            start_height_mm: self.robot.start_height_mm(self.opts.tail),
            channel_length_mm: self.robot.setup.channel_length_mm,
            running_s: r.running_s,
            mean_u_mm_s: mean(r.sum_u),
            mean_f_hz: mean(r.sum_f),
            mean_omega_b_hz: mean(r.sum_om),
            energy: self.energy,
            ticks: self.clock.ticks,
            rate_faults: record.rate_faults,
            rate_trace: record.rate_trace,
            battery_readings: record.battery_readings,
            log_records: record.log_records,
        }
    }
}

impl Record {
    /// What one pass reported: faults, battery readings, commands, events.
    fn outputs(&mut self, t_us: u64, out: &PassOutput) {
        self.log_records.extend(self.recorder.observe(t_us, out));
        let t_s = t_us as f64 * 1e-6;
        if let Some(f) = out.fault {
            self.rate_faults.push((t_s, RateEvent::Fault(f)));
        }
        if out.refused_no_set_point {
            self.rate_faults.push((t_s, RateEvent::NoSetPoint));
        }
        if let Some(counts) = out.sample {
            self.battery_readings.push((t_us, counts));
        }
        if let Some(c) = out.command {
            self.commands.push((t_s, c));
        }
        if let Some(e) = out.event {
            if let Event::Stopped(r) = e {
                self.last_stop = Some(r);
                self.last_stop_s = t_s;
            }
            self.events.push((t_s, e));
        }
    }
}

/// The last sensor fault, if it came after `after_s`.
fn last_fault_after(faults: &[(f64, RateEvent)], after_s: f64) -> Option<SensorFault> {
    faults.iter().rev().find_map(|&(t, e)| match e {
        RateEvent::Fault(f) if t >= after_s => Some(f),
        _ => None,
    })
}
