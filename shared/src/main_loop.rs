//! One pass of the robot's main loop: receiver edges -> command (Off wins
//! within a pass), Hall edges -> the tail's rate (`rate::hall`), a battery
//! reading when one is due -> battery status, the rate controller (its
//! on/off state machine and soft start are `controller::Controller`'s) ->
//! PWM duty, the LED pattern, whether the Hall latches are powered, and
//! whether the chip may go dormant. The RP2040 firmware
//! (`firmware/src/run.rs`), the host rig (`tests/src/lib.rs`), the safety
//! property tests (`tests/tests/firmware_safety.rs`) and the whole-robot
//! simulation (`host/src/sim/dynamics.rs`, `swimbot sim`) all run this same
//! pass; only the hardware around it differs. What turns the command and
//! the battery status into a duty is a [`MotorControl`]: the chip's rate
//! control ([`ChipControl`]) by default; the sim's voltage mode in its place.
//!
//! "Motor on", for the battery monitor's release-at-rest rule, means the
//! duty applied since the previous pass is non-zero: that is what loaded
//! the cell during the reading.

use crate::battery::{BatteryConfig, BatteryMonitor, BatteryStatus};
use crate::board;
use crate::command::{Command, KeyMap, Remote};
use crate::controller::{Duty, Event, MotorState};
use crate::led::{self, LedMode};
use crate::nec::Level;
use crate::rate::{HallConfig, RateConfig, RateController, RateEstimator, RateEvent, SensorFault};
use crate::set_point::SetPointKeys;

mod motor_control;
pub use motor_control::{ChipControl, MotorControl};

/// One Hall edge as the interrupt queued it: the timer's low 32 bits and
/// both latches' levels read together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HallEdge {
    pub t_us: u32,
    pub a: bool,
    pub b: bool,
}

/// What one pass decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassOutput {
    /// Apply this duty now.
    pub duty: Duty,
    pub state: MotorState,
    pub event: Option<Event>,
    /// A sensor fault stopped the motor in this pass (log it).
    pub fault: Option<SensorFault>,
    /// An On arrived with no set-point: nothing started (log it).
    pub refused_no_set_point: bool,
    /// Drive the Hall latches' power pin: on whenever the motor may run.
    pub hall_power: bool,
    /// The turn-averaged rate while running (mHz), and what it is driven
    /// towards (the soft-started, slewed set-point).
    pub rate_mhz: Option<u32>,
    pub reference_mhz: u32,
    /// The selected set-point (mHz), if any (the run log's).
    pub set_point_mhz: Option<u32>,
    /// The command decoded in this pass (merged: Off wins).
    pub command: Option<Command>,
    /// A set-point key changed the set-point in this pass: the new one.
    pub set_point_changed: Option<u32>,
    /// Complete frames from other remotes since power-up (ignored).
    pub foreign_frames: u32,
    /// The battery reading taken in this pass (ADC counts), if one was due.
    pub sample: Option<u16>,
    pub battery: BatteryStatus,
    pub led: LedMode,
    pub led_lit: bool,
    /// The cut-off latch changed in this pass: store the new value where
    /// it survives a reset (`reset_memory`).
    pub latch_changed: Option<bool>,
    /// Run the next pass this soon (us) rather than after the usual wake
    /// period: set on the pass that starts the motor, when the soft start's
    /// reference (and with it the duty) first becomes non-zero after
    /// `ramp_us / set-point`, so the first PWM edge does not wait a whole
    /// wake period (the On -> PWM latency, issue 26.3).
    pub next_pass_in_us: Option<u32>,
    /// Motor off and no IR edge for `dormant_after_us`:
    /// the chip may stop its clocks until the next IR edge.
    pub may_go_dormant: bool,
}

/// What a main loop is built from. `BOARD` is the robot's board
/// (`board.rs`); a simulation of another robot changes fields of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MainLoopConfig {
    pub keys: KeyMap,
    pub set_point_keys: SetPointKeys,
    pub battery: BatteryConfig,
    pub rate: RateConfig,
    pub hall: HallConfig,
    /// The set-point after power-up (mHz); `None`: On starts nothing until
    /// a key selects one.
    pub set_point_mhz: Option<u32>,
    /// Battery readings at most this often.
    pub sample_period_us: u64,
    /// Motor off and no IR edge this long: the chip may go dormant.
    pub dormant_after_us: u64,
}

impl MainLoopConfig {
    pub const BOARD: Self = Self {
        keys: board::KEYS,
        set_point_keys: board::SET_POINT_KEYS,
        battery: board::BATTERY,
        rate: board::RATE,
        hall: board::HALL,
        set_point_mhz: Some(board::DEFAULT_RATE_MHZ),
        sample_period_us: board::BATTERY_SAMPLE_PERIOD_US,
        dormant_after_us: board::DORMANT_AFTER_IDLE_US,
    };
}

impl Default for MainLoopConfig {
    fn default() -> Self {
        Self::BOARD
    }
}

/// The main loop's state between passes.
#[derive(Clone, Debug)]
pub struct MainLoop<C = ChipControl> {
    cfg: MainLoopConfig,
    remote: Remote,
    monitor: BatteryMonitor,
    control: C,
    next_sample_us: Option<u64>,
    duty: Duty,
    state: MotorState,
    latched: bool,
    last_activity_us: u64,
}

impl MainLoop {
    /// The board's main loop, with a cut-off latch remembered from before a
    /// reset (`false` after power-on).
    pub fn new(cutoff_latched: bool) -> Self {
        Self::with_config(MainLoopConfig::BOARD, cutoff_latched)
    }

    pub fn with_config(cfg: MainLoopConfig, cutoff_latched: bool) -> Self {
        let control = ChipControl::new(cfg.rate, cfg.hall);
        MainLoop::with_control(cfg, control, cutoff_latched)
    }

    pub fn controller(&self) -> &RateController {
        &self.control.controller
    }

    pub fn estimator(&self) -> &RateEstimator {
        &self.control.estimator
    }
}

impl<C: MotorControl> MainLoop<C> {
    /// A main loop around another controller (`cfg.rate` and `cfg.hall`
    /// unused; `cfg.set_point_mhz` handed to it).
    pub fn with_control(cfg: MainLoopConfig, mut control: C, cutoff_latched: bool) -> Self {
        let mut monitor = BatteryMonitor::new(cfg.battery);
        if cutoff_latched {
            monitor.restore_cutoff_latch();
        }
        control.set_rate_mhz(cfg.set_point_mhz);
        Self {
            cfg,
            remote: Remote::new(cfg.keys),
            monitor,
            control,
            next_sample_us: None,
            duty: Duty::ZERO,
            state: MotorState::Off,
            latched: cutoff_latched,
            last_activity_us: 0,
        }
    }

    /// Apply a set-point key: only the set-point changes, never the state.
    fn set_key(&mut self, key: crate::set_point::SetPointKey) -> Option<u32> {
        let (lo, hi) = (self.cfg.rate.min_rate_mhz, self.cfg.rate.max_rate_mhz);
        let current = self.control.set_rate();
        let next = self.cfg.set_point_keys.apply(key, current, lo, hi);
        if next.is_some() && next != current {
            self.control.set_rate_mhz(next);
        }
        // A controller without a set-point took nothing: nothing changed.
        self.control.set_rate().filter(|n| Some(*n) != current)
    }

    /// The duty applied since the last pass is non-zero.
    pub fn motor_on(&self) -> bool {
        self.duty != Duty::ZERO
    }

    /// The motor's state after the last pass.
    pub fn state(&self) -> MotorState {
        self.state
    }

    pub fn control(&self) -> &C {
        &self.control
    }

    pub fn control_mut(&mut self) -> &mut C {
        &mut self.control
    }

    pub fn monitor(&self) -> &BatteryMonitor {
        &self.monitor
    }

    /// One pass at `now_us`: feed `edges` (receiver level and the timer's
    /// low 32 bits, oldest first) and `hall` (oldest first), call
    /// `read_adc` if a battery reading is due (at most every
    /// `sample_period_us`; the first pass always reads), and decide the
    /// outputs.
    pub fn pass(
        &mut self,
        now_us: u64,
        edges: impl IntoIterator<Item = (Level, u32)>,
        hall: impl IntoIterator<Item = HallEdge>,
        read_adc: impl FnOnce() -> u16,
    ) -> PassOutput {
        let mut command = None;
        let mut set_point_changed = None;
        for (level, t_us) in edges {
            self.last_activity_us = now_us;
            let Some(code) = self.remote.edge_code(level, t_us) else {
                continue;
            };
            if let Some(c) = self.cfg.keys.lookup(self.cfg.keys.address, code) {
                command = Some(Command::merge(command, c));
            } else if let Some(key) = self.cfg.set_point_keys.lookup(code) {
                set_point_changed = self.set_key(key);
            }
        }
        for e in hall {
            self.control.hall_edge(e);
        }
        let mut sample = None;
        if self.next_sample_us.is_none_or(|due| now_us >= due) {
            // Catch up without bursts if a pass was ever late.
            self.next_sample_us = Some(now_us.saturating_add(self.cfg.sample_period_us));
            let counts = read_adc();
            self.monitor.sample(counts, now_us, self.motor_on());
            sample = Some(counts);
        }
        let battery = self.monitor.status();
        let out = self.control.step(now_us, command, battery);
        self.duty = out.duty;
        self.state = out.state;
        let (event, fault) = match out.event {
            Some(RateEvent::Motor(e)) => (Some(e), None),
            Some(RateEvent::Fault(f)) => (None, Some(f)),
            Some(RateEvent::NoSetPoint) | None => (None, None),
        };
        let running = out.state != MotorState::Off;
        if running {
            self.last_activity_us = now_us;
        }
        let latched = self.monitor.cutoff_latched();
        let latch_changed = (latched != self.latched).then_some(latched);
        self.latched = latched;
        let led = LedMode::of(out.state, battery, self.control.fault().is_some());
        PassOutput {
            duty: out.duty,
            state: out.state,
            event,
            fault,
            refused_no_set_point: out.event == Some(RateEvent::NoSetPoint),
            hall_power: running,
            rate_mhz: running.then(|| self.control.rate_mhz()).flatten(),
            reference_mhz: out.reference_mhz,
            set_point_mhz: self.control.set_rate(),
            command,
            set_point_changed,
            foreign_frames: self.remote.foreign_frames(),
            next_pass_in_us: (event == Some(Event::Started))
                .then(|| self.control.set_rate())
                .flatten()
                .map(|set| self.cfg.rate.motor.ramp_us.div_ceil(set.max(1))),
            sample,
            battery,
            led,
            led_lit: led::is_lit(led, now_us),
            latch_changed,
            may_go_dormant: out.state == MotorState::Off
                && now_us.saturating_sub(self.last_activity_us) >= self.cfg.dormant_after_us,
        }
    }
}

#[cfg(test)]
mod tests;
