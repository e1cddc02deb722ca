//! Cross-crate integration tests live in `tests/tests/`; this library holds
//! the helpers they share.
//!
//! [`Rig`] is the firmware's main loop (`firmware/src/run.rs`) rebuilt on
//! the host: the same shared `Remote`, `BatteryMonitor` and `Controller`,
//! ticked every millisecond, with the ADC, the PWM stage, the motor and the
//! cell replaced by the host models of `swimbot::robot`.

use std::collections::VecDeque;
use swimbot::robot::{LiPo, LiPoParams, Motor, MotorState, PwmDrive};
use swimbot_shared::nec::{for_each_edge, frame_pulses_us};
use swimbot_shared::{
    BatteryConfig, BatteryMonitor, BatteryStatus, Command, Controller, ControllerConfig, Duty,
    Event, KeyMap, Level, MotorState as CtlState, Remote,
};

/// The board's remote keys and divider (firmware/src/board.rs).
pub const KEYS: KeyMap = KeyMap {
    address: 0x00,
    on: 0x45,
    off: 0x47,
};
pub const BATTERY: BatteryConfig = BatteryConfig::new(100_000, 82_000, 3_300);

/// Tail drag as a viscous coefficient at the motor shaft (direct drive).
/// Calibrated, not derived: it holds the motor at ~1 Hz at the controller's
/// 3.0 V target, the paper's observed tail rates being 0.57-1.5 Hz
/// (Table II). A resistive-force estimate for tail #1 in 3.5 Pa s oil gives
/// about a fifth of this; the rest is taken to be the shaft seal's drag.
pub const TAIL_DAMPING_N_M_S: f64 = 5.2e-5;

/// Control-loop tick, as the firmware's main loop at worst.
pub const TICK_US: u64 = 1_000;
/// ADC sampling period of the firmware.
pub const ADC_PERIOD_US: u64 = 20_000;

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
    pub supply_v: f64,
    /// Mean motor terminal voltage over the PWM period.
    pub motor_v: f64,
    pub speed_rad_s: f64,
    pub supply_current_a: f64,
}

pub struct Rig {
    pub remote: Remote,
    pub monitor: BatteryMonitor,
    pub controller: Controller,
    pub motor: Motor,
    pub drive: PwmDrive,
    pub supply: Supply,
    pub tail_damping_n_m_s: f64,
    pub motor_state: MotorState,
    pub t_us: u64,
    /// Pending receiver edges, absolute microseconds.
    edges: VecDeque<(Level, u64)>,
    next_adc_us: u64,
    supply_current_a: f64,
    pub events: Vec<(u64, Event)>,
    pub commands: Vec<(u64, Command)>,
    pub last: Option<Sample>,
}

impl Rig {
    pub fn new(supply: Supply) -> Self {
        Self::with_config(supply, ControllerConfig::DEFAULT)
    }

    pub fn with_config(supply: Supply, cfg: ControllerConfig) -> Self {
        Self {
            remote: Remote::new(KEYS),
            monitor: BatteryMonitor::new(BATTERY),
            controller: Controller::new(cfg),
            motor: Motor::coreless_6mm(),
            drive: PwmDrive::BOARD,
            supply,
            tail_damping_n_m_s: TAIL_DAMPING_N_M_S,
            motor_state: MotorState::REST,
            t_us: 0,
            edges: VecDeque::new(),
            next_adc_us: 0,
            supply_current_a: 0.0,
            events: Vec::new(),
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

    /// Advance one tick: IR edges due, ADC sample if due, controller,
    /// PWM stage, motor and supply.
    pub fn tick(&mut self) -> Sample {
        self.t_us += TICK_US;
        let now = self.t_us;
        let mut command = None;
        while let Some(&(level, t)) = self.edges.front() {
            if t > now {
                break;
            }
            self.edges.pop_front();
            // The firmware timestamps with the timer's low 32 bits.
            if let Some(c) = self.remote.edge(level, t as u32) {
                self.commands.push((t, c));
                command = Some(Command::merge(command, c));
            }
        }
        let supply_v = self.supply.terminal_v(now, self.supply_current_a);
        if now >= self.next_adc_us {
            self.next_adc_us = now + ADC_PERIOD_US;
            let counts = BATTERY.mv_to_counts((supply_v * 1_000.0).round().max(0.0) as u32);
            let motor_on = self.last.is_some_and(|s| s.duty != Duty::ZERO);
            self.monitor.sample(counts, now, motor_on);
        }
        let battery = self.monitor.status();
        let out = self.controller.step(now, command, battery);
        if let Some(e) = out.event {
            self.events.push((now, e));
        }
        let means = self.drive.cycle_average(
            &self.motor,
            out.duty.as_f64(),
            supply_v,
            self.motor_state.speed_rad_s,
        );
        let c = self.tail_damping_n_m_s;
        let dt_s = TICK_US as f64 * 1e-6;
        self.motor_state = self.motor.step_implicit(
            self.motor_state,
            means.motor_v,
            c * self.motor_state.speed_rad_s,
            c,
            dt_s,
        );
        self.supply.draw(means.supply_current_a, dt_s);
        self.supply_current_a = means.supply_current_a;
        let s = Sample {
            t_us: now,
            state: out.state,
            duty: out.duty,
            battery,
            supply_v,
            motor_v: means.motor_v,
            speed_rad_s: self.motor_state.speed_rad_s,
            supply_current_a: means.supply_current_a,
        };
        self.last = Some(s);
        s
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
