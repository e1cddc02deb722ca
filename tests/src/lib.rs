//! Cross-crate integration tests live in `tests/tests/`; this library holds
//! the helpers they share.
//!
//! [`Rig`] runs the firmware's main-loop pass (`swimbot_shared::MainLoop`,
//! the very code `firmware/src/run.rs` calls) every millisecond, with the
//! ADC, the PWM stage, the motor and the cell replaced by the host models
//! of `swimbot::robot`. The ADC sees the cell's ripple: the reading is the
//! terminal voltage at the instant of the conversion, which the firmware
//! takes in the middle of the on-pulse (`firmware/src/battery_adc.rs`).
//! The Hall latches are modelled on the rotor's angle: the quadrature
//! levels of the board's ring (`board::HALL`) at exact crossing times,
//! with the timer's 1 us floor, while the main loop powers them.

use std::collections::VecDeque;
use swimbot::robot::{LiPo, LiPoParams, Motor, MotorState, PwmDrive};
pub use swimbot_shared::board::{BATTERY, KEYS};
use swimbot_shared::nec::{for_each_edge, frame_pulses_us};
use swimbot_shared::rate::SensorFault;
use swimbot_shared::{
    board, BatteryStatus, Command, Duty, Event, HallEdge, Level, MainLoop, MotorState as CtlState,
};

/// Tail drag as a viscous coefficient at the motor shaft (direct drive).
/// Calibrated, not derived: it holds the motor at ~1 Hz at the controller's
/// 3.0 V target, the paper's observed tail rates being 0.57-1.5 Hz
/// (Table II). A resistive-force estimate for tail #1 in 3.5 Pa s oil gives
/// about a fifth of this; the rest is taken to be the shaft seal's drag.
pub const TAIL_DAMPING_N_M_S: f64 = 5.2e-5;

/// Control-loop tick, as the firmware's main loop at worst.
pub const TICK_US: u64 = board::WAKE_PERIOD_US as u64;

/// When, within the PWM period, the battery conversion happens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AdcPhase {
    /// The firmware: the middle of the on-pulse (at once when not switching).
    MidOnPulse,
    /// At this fraction of the period, whatever the duty (0 = the start of
    /// the on-pulse): what a free-running conversion hits at random.
    Fixed(f64),
    /// The cycle-mean terminal voltage: an RC-filtered tap.
    CycleMean,
}

/// What powers the drive.
#[derive(Clone, Debug)]
pub enum Supply {
    /// The Li-Po model: open-circuit voltage by charge, internal resistance.
    Cell(LiPo),
    /// A stiff source whose voltage ramps linearly (for compensation tests).
    Ramp {
        from_v: f64,
        to_v: f64,
        start_us: u64,
        duration_us: u64,
    },
}

impl Supply {
    pub fn full_cell() -> Self {
        Supply::Cell(LiPo::full(LiPoParams::CELL_70MAH))
    }

    /// Internal resistance (zero for the stiff source).
    fn resistance_ohm(&self) -> f64 {
        match self {
            Supply::Cell(c) => c.params.internal_resistance_ohm,
            Supply::Ramp { .. } => 0.0,
        }
    }

    fn terminal_v(&self, t_us: u64, current_a: f64) -> f64 {
        match self {
            Supply::Cell(c) => c.terminal_v(current_a),
            Supply::Ramp {
                from_v,
                to_v,
                start_us,
                duration_us,
            } => {
                let x =
                    (t_us.saturating_sub(*start_us) as f64 / (*duration_us).max(1) as f64).min(1.0);
                from_v + (to_v - from_v) * x
            }
        }
    }

    fn draw(&mut self, current_a: f64, dt_s: f64) {
        if let Supply::Cell(c) = self {
            c.draw(current_a, dt_s);
        }
    }
}

/// One millisecond of the simulated robot, for the tests to inspect.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub t_us: u64,
    pub state: CtlState,
    pub duty: Duty,
    pub battery: BatteryStatus,
    /// Cycle-mean terminal voltage of the supply.
    pub supply_v: f64,
    /// Terminal voltage during the on-pulse (what the motor sees).
    pub supply_on_v: f64,
    /// Mean motor terminal voltage over the PWM period.
    pub motor_v: f64,
    pub speed_rad_s: f64,
    pub supply_current_a: f64,
}

pub struct Rig {
    pub main_loop: MainLoop,
    pub adc_phase: AdcPhase,
    pub motor: Motor,
    pub drive: PwmDrive,
    pub supply: Supply,
    pub tail_damping_n_m_s: f64,
    pub motor_state: MotorState,
    pub t_us: u64,
    /// Pending receiver edges, absolute microseconds.
    edges: VecDeque<(Level, u64)>,
    supply_current_a: f64,
    pub events: Vec<(u64, Event)>,
    pub faults: Vec<(u64, SensorFault)>,
    /// The rotor's angle in turns (for the Hall edges), the edges generated
    /// but not yet seen by a pass, and whether the latches are powered.
    pub angle_turns: f64,
    hall: VecDeque<HallEdge>,
    hall_powered: bool,
    /// The rotor turns but the latches see nothing: a stall as the sensor
    /// sees it (a seized coupler, both wires off).
    pub hall_disconnected: bool,
    pub commands: Vec<(u64, Command)>,
    pub last: Option<Sample>,
}

impl Rig {
    pub fn new(supply: Supply) -> Self {
        Self {
            main_loop: MainLoop::new(false),
            adc_phase: AdcPhase::MidOnPulse,
            motor: Motor::coreless_6mm(),
            drive: PwmDrive::BOARD,
            supply,
            tail_damping_n_m_s: TAIL_DAMPING_N_M_S,
            motor_state: MotorState::REST,
            t_us: 0,
            edges: VecDeque::new(),
            supply_current_a: 0.0,
            events: Vec::new(),
            faults: Vec::new(),
            angle_turns: 0.0,
            hall: VecDeque::new(),
            hall_powered: false,
            hall_disconnected: false,
            commands: Vec::new(),
            last: None,
        }
    }

    /// Queue receiver output (burst/space durations, starting with a burst)
    /// beginning `delay_us` from now. Returns when the last edge happens.
    pub fn send_pulses(&mut self, delay_us: u64, pulses_us: &[u32]) -> u64 {
        let start = self.edges.back().map_or(self.t_us, |e| e.1.max(self.t_us)) + delay_us;
        let mut end = start;
        for_each_edge(0, pulses_us, |level, t| {
            end = start + u64::from(t);
            self.edges.push_back((level, end));
        });
        end
    }

    /// Queue one remote key press (one NEC frame).
    pub fn press(&mut self, command: u8) -> u64 {
        self.send_pulses(1_000, &frame_pulses_us(KEYS.address, command))
    }

    /// Advance one tick: the receiver edges due, one main-loop pass (with
    /// an ADC reading of the rippling cell if one is due), the PWM stage,
    /// the motor and the supply.
    pub fn tick(&mut self) -> Sample {
        self.t_us += TICK_US;
        let now = self.t_us;
        let mut due = Vec::new();
        while let Some(&(level, t)) = self.edges.front() {
            if t > now {
                break;
            }
            self.edges.pop_front();
            // The firmware timestamps with the timer's low 32 bits.
            due.push((level, t as u32));
        }
        let supply_v = self.supply.terminal_v(now, self.supply_current_a);
        let r_ohm = self.supply.resistance_ohm();
        let open_v = supply_v + r_ohm * self.supply_current_a;
        let reading_v = self.adc_reading_v(open_v, supply_v);
        let hall: Vec<HallEdge> = self.hall.drain(..).collect();
        let out = self.main_loop.pass(now, due, hall, || {
            BATTERY.mv_to_counts((reading_v * 1_000.0).round().max(0.0) as u32)
        });
        self.hall_powered = out.hall_power;
        if let Some(f) = out.fault {
            self.faults.push((now, f));
        }
        if let Some(c) = out.command {
            self.commands.push((now, c));
        }
        if let Some(e) = out.event {
            self.events.push((now, e));
        }
        let duty = out.duty.as_f64();
        let supply_on_v = self.on_pulse_v(open_v, duty);
        let means =
            self.drive
                .cycle_average(&self.motor, duty, supply_on_v, self.motor_state.speed_rad_s);
        let c = self.tail_damping_n_m_s;
        let dt_s = TICK_US as f64 * 1e-6;
        self.motor_state = self.motor.step_implicit(
            self.motor_state,
            means.motor_v,
            c * self.motor_state.speed_rad_s,
            c,
            dt_s,
        );
        self.turn(now, dt_s);
        self.supply.draw(means.supply_current_a, dt_s);
        self.supply_current_a = means.supply_current_a;
        let s = Sample {
            t_us: now,
            state: out.state,
            duty: out.duty,
            battery: out.battery,
            supply_v,
            supply_on_v,
            motor_v: means.motor_v,
            speed_rad_s: self.motor_state.speed_rad_s,
            supply_current_a: means.supply_current_a,
        };
        self.last = Some(s);
        s
    }

    /// Advance the rotor's angle over the tick that began at `t0_us` and
    /// queue a Hall edge at each crossing of a quadrature step: levels in
    /// the Gray order 00, 01, 11, 10 forwards (A leads B).
    fn turn(&mut self, t0_us: u64, dt_s: f64) {
        let per_turn = board::HALL.edges_per_turn() as f64;
        let turns_per_s = self.motor_state.speed_rad_s / std::f64::consts::TAU;
        let from = self.angle_turns * per_turn;
        self.angle_turns += turns_per_s * dt_s;
        let to = self.angle_turns * per_turn;
        if !self.hall_powered || self.hall_disconnected || turns_per_s == 0.0 {
            return;
        }
        let rate_steps_per_us = (to - from) / (dt_s * 1e6);
        let (lo, hi) = (from.min(to), from.max(to));
        let mut k = lo.floor() + 1.0;
        let mut crossings = Vec::new();
        while k <= hi {
            crossings.push(k);
            k += 1.0;
        }
        if to < from {
            crossings.reverse();
        }
        for k in crossings {
            let t_us = t0_us as f64 + (k - from) / rate_steps_per_us;
            // Entering step k (going forwards) or k - 1 (backwards).
            let step = if to > from { k } else { k - 1.0 } as i64;
            let (a, b) = [(false, false), (false, true), (true, true), (true, false)]
                [step.rem_euclid(4) as usize];
            self.hall.push_back(HallEdge {
                t_us: t_us.floor() as u64 as u32,
                a,
                b,
            });
        }
    }

    /// Terminal voltage during the on-pulse at `duty`: the open-circuit
    /// voltage less the drop of the mean on-phase current (the cell
    /// supplies current only while the switch is on).
    fn on_pulse_v(&self, open_v: f64, duty: f64) -> f64 {
        let r_ohm = self.supply.resistance_ohm();
        if duty <= 0.0 || r_ohm == 0.0 {
            return open_v;
        }
        let p = &self.motor.params;
        let e = self.motor.back_emf_v(self.motor_state.speed_rad_s);
        // Discontinuous conduction: the on-current rises from zero towards
        // (V_oc - e) / (R_motor + R_cell) with the loop's time constant.
        let r = p.resistance_ohm + r_ohm;
        let tau_s = p.inductance_h / r;
        let t_on_s = duty.min(1.0) / self.drive.carrier_hz;
        let mean_rise = 1.0 - tau_s / t_on_s * (1.0 - (-t_on_s / tau_s).exp());
        open_v - r_ohm * (open_v - e).max(0.0) / r * mean_rise
    }

    /// The terminal voltage the ADC converts, at the firmware's phase.
    fn adc_reading_v(&self, open_v: f64, mean_v: f64) -> f64 {
        let duty = self.last.map_or(0.0, |s| s.duty.as_f64());
        let r_ohm = self.supply.resistance_ohm();
        let period_s = 1.0 / self.drive.carrier_hz;
        let at_s = match self.adc_phase {
            AdcPhase::CycleMean => return mean_v,
            AdcPhase::MidOnPulse if duty > 0.0 && duty < 1.0 => duty / 2.0 * period_s,
            AdcPhase::MidOnPulse => 0.5 * period_s,
            AdcPhase::Fixed(x) => x.clamp(0.0, 1.0) * period_s,
        };
        let t_on_s = duty.clamp(0.0, 1.0) * period_s;
        if at_s >= t_on_s || r_ohm == 0.0 {
            return open_v; // switch off: no current from the cell
        }
        let p = &self.motor.params;
        let e = self.motor.back_emf_v(self.motor_state.speed_rad_s);
        let r = p.resistance_ohm + r_ohm;
        let rise = 1.0 - (-at_s * r / p.inductance_h).exp();
        open_v - r_ohm * (open_v - e).max(0.0) / r * rise
    }

    /// Tick for `duration_us`, returning every sample.
    pub fn run_for(&mut self, duration_us: u64) -> Vec<Sample> {
        let end = self.t_us + duration_us;
        let mut out = Vec::new();
        while self.t_us < end {
            out.push(self.tick());
        }
        out
    }

    /// Tick until `pred` holds (or `limit_us` passes); the matching sample.
    pub fn run_until(
        &mut self,
        limit_us: u64,
        mut pred: impl FnMut(&Sample) -> bool,
    ) -> Option<Sample> {
        let end = self.t_us + limit_us;
        while self.t_us < end {
            let s = self.tick();
            if pred(&s) {
                return Some(s);
            }
        }
        None
    }

    pub fn started_at(&self) -> Option<u64> {
        self.events
            .iter()
            .rev()
            .find(|e| e.1 == Event::Started)
            .map(|e| e.0)
    }
}
