//! One pass of the robot's main loop: receiver edges -> command (Off wins
//! within a pass), a battery reading when one is due -> battery status,
//! the controller -> PWM duty, the LED pattern, and whether the chip may
//! go dormant. The RP2040 firmware (`firmware/src/run.rs`), the host rig
//! (`tests/src/lib.rs`), the safety property tests
//! (`tests/tests/firmware_safety.rs`) and the whole-robot simulation
//! (`host/src/sim/dynamics.rs`, `swimbot sim`) all run this same pass; only
//! the hardware around it differs.
//!
//! What turns the command and the battery status into a duty is a
//! [`MotorControl`]: the voltage-mode [`Controller`] on the board today,
//! or a rate controller (`swimbot sim --rate-hz`). The decisions around it
//! (command merge, when to read the cell, the monitor, the latch, the LED,
//! dormancy) are the pass's, whichever controller it carries.
//!
//! "Motor on", for the battery monitor's release-at-rest rule, means the
//! duty applied since the previous pass is non-zero: that is what loaded
//! the cell during the reading.

use crate::battery::{BatteryConfig, BatteryMonitor, BatteryStatus};
use crate::board;
use crate::command::{Command, KeyMap, Remote};
use crate::controller::{Controller, ControllerConfig, Duty, Event, MotorState, Output};
use crate::led::{self, LedMode};
use crate::nec::Level;

/// The motor's controller inside a pass: a command (if one arrived) and the
/// battery status in, the duty and state out.
pub trait MotorControl {
    fn step(&mut self, now_us: u64, command: Option<Command>, battery: BatteryStatus) -> Output;
}

impl MotorControl for Controller {
    fn step(&mut self, now_us: u64, command: Option<Command>, battery: BatteryStatus) -> Output {
        Controller::step(self, now_us, command, battery)
    }
}

/// What one pass decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassOutput {
    /// Apply this duty now.
    pub duty: Duty,
    pub state: MotorState,
    pub event: Option<Event>,
    /// The command decoded in this pass (merged: Off wins).
    pub command: Option<Command>,
    /// The battery reading taken in this pass (ADC counts), if one was due.
    pub sample: Option<u16>,
    pub battery: BatteryStatus,
    pub led: LedMode,
    pub led_lit: bool,
    /// The cut-off latch changed in this pass: store the new value where
    /// it survives a reset (`reset_memory`).
    pub latch_changed: Option<bool>,
    /// Motor off and no IR edge for `dormant_after_us`:
    /// the chip may stop its clocks until the next IR edge.
    pub may_go_dormant: bool,
}

/// What a main loop is built from. `BOARD` is the robot's board
/// (`board.rs`); a simulation of another robot changes fields of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MainLoopConfig {
    pub keys: KeyMap,
    pub battery: BatteryConfig,
    /// The voltage-mode controller's settings (used by
    /// [`MainLoop::with_config`]; a loop built with
    /// [`MainLoop::with_controller`] carries its own).
    pub controller: ControllerConfig,
    /// Battery readings at most this often.
    pub sample_period_us: u64,
    /// Motor off and no IR edge this long: the chip may go dormant.
    pub dormant_after_us: u64,
}

impl MainLoopConfig {
    pub const BOARD: Self = Self {
        keys: board::KEYS,
        battery: board::BATTERY,
        controller: board::CONTROLLER,
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
pub struct MainLoop<C = Controller> {
    cfg: MainLoopConfig,
    remote: Remote,
    monitor: BatteryMonitor,
    controller: C,
    next_sample_us: Option<u64>,
    duty: Duty,
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
        MainLoop::with_controller(cfg, Controller::new(cfg.controller), cutoff_latched)
    }
}

impl<C: MotorControl> MainLoop<C> {
    /// A main loop around another controller (`cfg.controller` unused).
    pub fn with_controller(cfg: MainLoopConfig, controller: C, cutoff_latched: bool) -> Self {
        let mut monitor = BatteryMonitor::new(cfg.battery);
        if cutoff_latched {
            monitor.restore_cutoff_latch();
        }
        Self {
            cfg,
            remote: Remote::new(cfg.keys),
            monitor,
            controller,
            next_sample_us: None,
            duty: Duty::ZERO,
            latched: cutoff_latched,
            last_activity_us: 0,
        }
    }

    /// The duty applied since the last pass is non-zero.
    pub fn motor_on(&self) -> bool {
        self.duty != Duty::ZERO
    }

    pub fn controller(&self) -> &C {
        &self.controller
    }

    /// The controller, for what lies outside the pass (a rate sensor's
    /// edges, queued between passes as the firmware's interrupt does).
    pub fn controller_mut(&mut self) -> &mut C {
        &mut self.controller
    }

    pub fn monitor(&self) -> &BatteryMonitor {
        &self.monitor
    }

    /// One pass at `now_us`: feed `edges` (receiver level and the timer's
    /// low 32 bits, oldest first), call `read_adc` if a battery reading is
    /// due (at most every `sample_period_us`; the first pass
    /// always reads), and decide the outputs.
    pub fn pass(
        &mut self,
        now_us: u64,
        edges: impl IntoIterator<Item = (Level, u32)>,
        read_adc: impl FnOnce() -> u16,
    ) -> PassOutput {
        let mut command = None;
        for (level, t_us) in edges {
            self.last_activity_us = now_us;
            if let Some(c) = self.remote.edge(level, t_us) {
                command = Some(Command::merge(command, c));
            }
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
        let out = self.controller.step(now_us, command, battery);
        self.duty = out.duty;
        if out.state != MotorState::Off {
            self.last_activity_us = now_us;
        }
        let latched = self.monitor.cutoff_latched();
        let latch_changed = (latched != self.latched).then_some(latched);
        self.latched = latched;
        let led = LedMode::of(out.state, battery);
        PassOutput {
            duty: out.duty,
            state: out.state,
            event: out.event,
            command,
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
mod tests {
    use super::*;
    use crate::battery::BatteryLevel;
    use crate::nec::{for_each_edge, frame_pulses_us};

    fn counts(mv: u32) -> u16 {
        board::BATTERY.mv_to_counts(mv)
    }

    /// Passes every millisecond up to `until_us`, at `mv`, no edges.
    fn idle<C: MotorControl>(
        m: &mut MainLoop<C>,
        from_us: u64,
        until_us: u64,
        mv: u32,
    ) -> PassOutput {
        let mut last = m.pass(from_us, [], || counts(mv));
        let mut t = from_us;
        while t < until_us {
            t += 1_000;
            last = m.pass(t, [], || counts(mv));
        }
        last
    }

    fn on_frame() -> heapless::Vec<(Level, u32), 80> {
        let mut v = heapless::Vec::new();
        for_each_edge(
            300_000,
            &frame_pulses_us(board::NEC_ADDRESS, board::NEC_CMD_ON),
            |l, t| {
                let _ = v.push((l, t));
            },
        );
        v
    }

    #[test]
    fn samples_on_schedule_and_starts_on_a_frame() {
        let mut m = MainLoop::new(false);
        let o = m.pass(0, [], || counts(3_900));
        assert_eq!(o.sample, Some(counts(3_900)));
        assert_eq!(m.pass(19_999, [], || unreachable!()).sample, None);
        assert!(m.pass(20_000, [], || counts(3_900)).sample.is_some());
        idle(&mut m, 20_000, 290_000, 3_900);
        let o = m.pass(400_000, on_frame(), || counts(3_900));
        assert_eq!(o.command, Some(Command::On));
        assert_eq!(o.event, Some(Event::Started));
        let o = idle(&mut m, 400_000, 800_000, 3_900);
        assert_eq!(o.state, MotorState::Running);
        assert!(m.motor_on());
    }

    #[test]
    fn another_robot_samples_on_its_own_period() {
        let cfg = MainLoopConfig {
            sample_period_us: 5_000,
            ..MainLoopConfig::BOARD
        };
        let mut m = MainLoop::with_config(cfg, false);
        assert!(m.pass(0, [], || counts(3_900)).sample.is_some());
        assert!(m.pass(4_999, [], || counts(3_900)).sample.is_none());
        assert!(m.pass(5_000, [], || counts(3_900)).sample.is_some());
    }

    #[test]
    fn a_remembered_cutoff_refuses_on_and_reports_its_release() {
        let mut m = MainLoop::new(true);
        idle(&mut m, 0, 300_000, 3_600);
        let o = m.pass(400_000, on_frame(), || counts(3_600));
        assert_eq!(o.battery.level, BatteryLevel::Cutoff);
        assert_eq!(o.duty, Duty::ZERO);
        let o = idle(&mut m, 400_000, 420_000, 4_100);
        assert_eq!(o.latch_changed, None, "the average still reads low");
        let mut released = None;
        let mut t = 420_000;
        while released.is_none() && t < 1_000_000 {
            t += 1_000;
            released = m.pass(t, [], || counts(4_100)).latch_changed;
        }
        assert_eq!(released, Some(false));
    }

    #[test]
    fn dormant_only_after_a_quiet_idle_stretch() {
        let mut m = MainLoop::new(false);
        let quiet = board::DORMANT_AFTER_IDLE_US;
        assert!(!idle(&mut m, 0, quiet - 1_000, 3_900).may_go_dormant);
        assert!(idle(&mut m, quiet - 1_000, quiet, 3_900).may_go_dormant);
        // An edge (even noise) restarts the count.
        let o = m.pass(quiet + 1_000, [(Level::Low, 5)], || counts(3_900));
        assert!(!o.may_go_dormant);
    }

    /// A controller that wants the motor on at a fixed duty whenever the
    /// battery allows, to see the pass's decisions around any controller.
    #[derive(Clone, Debug)]
    struct Fixed(Duty);

    impl MotorControl for Fixed {
        fn step(&mut self, _: u64, _: Option<Command>, battery: BatteryStatus) -> Output {
            let on = battery.allows_motor();
            Output {
                duty: if on { self.0 } else { Duty::ZERO },
                state: if on {
                    MotorState::Running
                } else {
                    MotorState::Off
                },
                event: None,
            }
        }
    }

    #[test]
    fn another_controller_gets_the_same_sampling_latch_and_led() {
        let mut m =
            MainLoop::with_controller(MainLoopConfig::BOARD, Fixed(Duty::percent(50)), false);
        let o = m.pass(0, [], || counts(3_900));
        assert_eq!(
            (o.duty, o.led),
            (Duty::percent(50), LedMode::of(o.state, o.battery))
        );
        assert!(
            m.motor_on(),
            "its duty is what the next reading was loaded by"
        );
        // A cell under the cut-off for the debounce: the pass latches it and
        // the controller is handed a status that stops the motor.
        let o = idle(&mut m, 0, 1_300_000, 3_100);
        assert_eq!(o.battery.level, BatteryLevel::Cutoff);
        assert_eq!(o.duty, Duty::ZERO);
        assert_eq!(m.controller().0, Duty::percent(50));
    }
}
