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
//! Between its duty and the PWM stands the motor supervisor
//! (`supervisor`), which keeps its own state: it caps the mean voltage at
//! the motor's rating, and stops the motor on a jam or on its heat
//! estimate, whatever the controller asked.
//!
//! "Motor on", for the battery monitor's release-at-rest rule, means the
//! duty applied since the previous pass is non-zero: that is what loaded
//! the cell during the reading.

use crate::battery::{BatteryConfig, BatteryMonitor};
use crate::board;
use crate::command::{Command, KeyMap, PairedRemote, Remote, RemoteEvent};
use crate::controller::{Duty, Event, MotorState};
use crate::led::{self, LedMode};
use crate::nec::Level;
use crate::pairing::{Pairing, PairingConfig};
use crate::rate::{HallConfig, RateConfig, RateController, RateEstimator, RateEvent};
use crate::set_point::SetPointKeys;
use crate::supervisor::{Supervisor, SupervisorConfig};

mod motor_control;
mod output;
mod self_test;
pub use motor_control::{ChipControl, MotorControl};
pub use output::{PassOutput, ERASE_QUIET_US};
pub use self_test::{PreStart, SelfTestFault};

/// One Hall edge as the interrupt queued it: the timer's low 32 bits and
/// both latches' levels read together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HallEdge {
    pub t_us: u32,
    pub a: bool,
    pub b: bool,
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
    /// How the robot is paired with its remote after power-up.
    pub pairing: PairingConfig,
    /// The motor's limits, guarded independently of the controller.
    pub supervisor: SupervisorConfig,
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
        pairing: board::PAIRING,
        supervisor: board::SUPERVISOR,
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
    supervisor: Supervisor,
    next_sample_us: Option<u64>,
    duty: Duty,
    state: MotorState,
    latched: bool,
    last_activity_us: u64,
    last_ir_us: Option<u64>,
    pairing: Pairing,
    usb_connected: bool,
    erase_pending: bool,
    prestart: PreStart,
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
            supervisor: Supervisor::new(cfg.supervisor),
            next_sample_us: None,
            duty: Duty::ZERO,
            state: MotorState::Off,
            latched: cutoff_latched,
            last_activity_us: 0,
            last_ir_us: None,
            pairing: Pairing::new(cfg.pairing),
            usb_connected: false,
            erase_pending: false,
            prestart: PreStart::HEALTHY,
        }
    }

    /// The remote to obey, as kept in flash (`None`: unpaired, none is).
    /// Until this is called it is the key map's remote.
    pub fn set_paired(&mut self, remote: Option<PairedRemote>) {
        self.remote.set_paired(remote);
    }

    /// The chip has just woken from DORMANT (its timer stood still, so the
    /// sample schedule does not know time passed): the next pass reads
    /// the battery, whatever the schedule says. A stored robot's cell is
    /// thus checked on every wake-up, before anything else is decided.
    pub fn woke(&mut self) {
        self.next_sample_us = None;
    }

    /// USB is connected (VBUS present): from the next pass the motor is
    /// held off, and On does nothing, until it is disconnected.
    pub fn set_usb_connected(&mut self, connected: bool) {
        self.usb_connected = connected;
    }

    /// What the pins read now (`self_test`): an On from Off is refused
    /// while the self-test fails. Until this is called, a healthy board.
    pub fn set_prestart(&mut self, pins: PreStart) {
        self.prestart = pins;
    }

    /// A flash erase is pending (the run log's slots, the pairing sector):
    /// from the next pass the chip does not go dormant until it is done.
    /// A pass that would otherwise go dormant (motor off, no USB, no IR
    /// edge for the idle time) allows an erase too once the pairing window
    /// has closed, so the sequence goes on, one erase a pass, and the pass
    /// after its last one may go dormant. An IR edge still stops it (not
    /// quiet), and a pass later it may resume.
    pub fn set_erase_pending(&mut self, pending: bool) {
        self.erase_pending = pending;
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

    pub fn supervisor(&self) -> &Supervisor {
        &self.supervisor
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
        let mut newly_paired = None;
        for (level, t_us) in edges {
            self.last_activity_us = now_us;
            self.last_ir_us = Some(now_us);
            match self.remote.edge_event(level, t_us) {
                Some(RemoteEvent::Key(code)) => {
                    let paired = self.remote.paired();
                    if let Some(p) = paired {
                        self.pairing.frame(now_us, p.address, code);
                    }
                    // The remote checked the (paired) address.
                    if let Some(c) = paired.and_then(|p| p.lookup(code)) {
                        command = Some(Command::merge(command, c));
                    } else if let Some(key) = self.cfg.set_point_keys.lookup(code) {
                        set_point_changed = self.set_key(key);
                    }
                }
                Some(RemoteEvent::Foreign { address, command }) => {
                    self.pairing.frame(now_us, address, command);
                }
                Some(RemoteEvent::Repeat) => {
                    let paired = self.pairing.repeat(now_us);
                    if paired.is_some() && paired != self.remote.paired() {
                        self.remote.set_paired(paired);
                        newly_paired = paired;
                    }
                }
                None => {}
            }
        }
        for e in hall {
            self.control.hall_edge(e);
            self.supervisor.hall_edge(e);
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
        // USB connected: Off every pass (Off wins over any On).
        // An overheated or locked-out motor refuses On; so does a start
        // from Off that fails the self-test.
        let self_test = (command == Some(Command::On) && self.state == MotorState::Off)
            .then(|| self.prestart.check())
            .flatten();
        let applied = if self.usb_connected {
            Some(Command::Off)
        } else if command == Some(Command::On)
            && (self.supervisor.refuses_start() || self_test.is_some())
        {
            None
        } else {
            command
        };
        let mut out = self.control.step(now_us, applied, battery);
        if out.event == Some(RateEvent::Motor(Event::Started)) {
            self.supervisor.started();
        }
        let senses = self.control.senses_rotor();
        let verdict = self
            .supervisor
            .check(now_us, out.duty, u32::from(battery.mv), senses);
        if let Some(f) = verdict.trip {
            // The controller is told Off, so it stops as after any Off.
            let stopped = self.control.step(now_us, Some(Command::Off), battery);
            out.state = stopped.state;
            out.event = Some(RateEvent::Fault(f));
        }
        out.duty = verdict.duty;
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
        let pairing_window = self.pairing.window_open(now_us);
        let faulted = self.control.fault().is_some() || self.supervisor.fault().is_some();
        let led = LedMode::of(out.state, battery, faulted)
            .with_pairing(pairing_window, self.remote.paired().is_some());
        let quiet = self
            .last_ir_us
            .is_none_or(|t| now_us.saturating_sub(t) >= ERASE_QUIET_US);
        PassOutput {
            duty: out.duty,
            state: out.state,
            event,
            fault,
            refused_no_set_point: out.event == Some(RateEvent::NoSetPoint),
            refused_self_test: self_test.filter(|_| !self.usb_connected),
            locked_out: self.supervisor.locked_out(),
            trips: self.supervisor.trips(),
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
            // DORMANT would stop the USB clock under a connected host, and
            // leave an erase half done for a later wake-up (or, if the cell
            // is disconnected first, for the next power-up's first run).
            may_go_dormant: out.state == MotorState::Off
                && !self.usb_connected
                && !self.erase_pending
                && now_us.saturating_sub(self.last_activity_us) >= self.cfg.dormant_after_us,
            paired: self.remote.paired(),
            newly_paired,
            pairing_window,
            usb_connected: self.usb_connected,
            may_erase_flash: out.state == MotorState::Off
                && out.duty == Duty::ZERO
                && !pairing_window
                && !self.usb_connected
                && quiet,
        }
    }
}

#[cfg(test)]
mod erase_tests;
#[cfg(test)]
mod pairing_tests;
#[cfg(test)]
mod tests;
