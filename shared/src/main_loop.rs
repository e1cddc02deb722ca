//! One pass of the robot's main loop: receiver edges -> command (Off wins
//! within a pass), Hall edges -> the tail's rate (`rate::hall`), a battery
//! reading when one is due -> battery status, the rate controller (its
//! on/off state machine and soft start are `controller::Controller`'s) ->
//! PWM duty, the LED pattern, whether the Hall latches are powered, and
//! whether the chip may go dormant. The RP2040 firmware (`firmware/src/run.rs`), the host
//! simulation (`tests/src/lib.rs`) and the safety property tests
//! (`tests/tests/firmware_safety.rs`) all run this same pass; only the
//! hardware around it differs.
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
pub struct MainLoop {
    cfg: MainLoopConfig,
    remote: Remote,
    monitor: BatteryMonitor,
    controller: RateController,
    estimator: RateEstimator,
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
        let mut monitor = BatteryMonitor::new(cfg.battery);
        if cutoff_latched {
            monitor.restore_cutoff_latch();
        }
        let mut controller = RateController::new(cfg.rate);
        controller.set_rate_mhz(cfg.set_point_mhz);
        Self {
            cfg,
            remote: Remote::new(cfg.keys),
            monitor,
            controller,
            estimator: RateEstimator::new(cfg.hall),
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
        let current = self.controller.set_rate();
        let next = self.cfg.set_point_keys.apply(key, current, lo, hi);
        if next.is_some() && next != current {
            self.controller.set_rate_mhz(next);
        }
        next.filter(|n| Some(*n) != current)
    }

    /// The duty applied since the last pass is non-zero.
    pub fn motor_on(&self) -> bool {
        self.duty != Duty::ZERO
    }

    /// The motor's state after the last pass.
    pub fn state(&self) -> MotorState {
        self.state
    }

    pub fn controller(&self) -> &RateController {
        &self.controller
    }

    pub fn estimator(&self) -> &RateEstimator {
        &self.estimator
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
            self.estimator.edge(e.t_us, e.a, e.b);
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
        let out = self
            .controller
            .step(now_us, command, battery, &mut self.estimator);
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
        let led = LedMode::of(out.state, battery, self.controller.fault().is_some());
        PassOutput {
            duty: out.duty,
            state: out.state,
            event,
            fault,
            refused_no_set_point: out.event == Some(RateEvent::NoSetPoint),
            hall_power: running,
            rate_mhz: running
                .then(|| self.estimator.estimate().map(|r| r.rate_mhz))
                .flatten(),
            reference_mhz: out.reference_mhz,
            command,
            set_point_changed,
            foreign_frames: self.remote.foreign_frames(),
            next_pass_in_us: (event == Some(Event::Started))
                .then(|| self.controller.set_rate())
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
mod tests {
    use super::*;
    use crate::battery::BatteryLevel;
    use crate::nec::{for_each_edge, frame_pulses_us};
    use crate::rate::SensorFault;

    fn counts(mv: u32) -> u16 {
        board::BATTERY.mv_to_counts(mv)
    }

    /// Passes every millisecond up to `until_us`, at `mv`, no edges.
    fn idle(m: &mut MainLoop, from_us: u64, until_us: u64, mv: u32) -> PassOutput {
        let mut last = m.pass(from_us, [], [], || counts(mv));
        let mut t = from_us;
        while t < until_us {
            t += 1_000;
            last = m.pass(t, [], [], || counts(mv));
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
        let o = m.pass(0, [], [], || counts(3_900));
        assert_eq!(o.sample, Some(counts(3_900)));
        assert_eq!(m.pass(19_999, [], [], || unreachable!()).sample, None);
        assert!(m.pass(20_000, [], [], || counts(3_900)).sample.is_some());
        idle(&mut m, 20_000, 290_000, 3_900);
        let o = m.pass(400_000, on_frame(), [], || counts(3_900));
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
        assert!(m.pass(0, [], [], || counts(3_900)).sample.is_some());
        assert!(m.pass(4_999, [], [], || counts(3_900)).sample.is_none());
        assert!(m.pass(5_000, [], [], || counts(3_900)).sample.is_some());
    }

    #[test]
    fn a_remembered_cutoff_refuses_on_and_reports_its_release() {
        let mut m = MainLoop::new(true);
        idle(&mut m, 0, 300_000, 3_600);
        let o = m.pass(400_000, on_frame(), [], || counts(3_600));
        assert_eq!(o.battery.level, BatteryLevel::Cutoff);
        assert_eq!(o.duty, Duty::ZERO);
        let o = idle(&mut m, 400_000, 420_000, 4_100);
        assert_eq!(o.latch_changed, None, "the average still reads low");
        let mut released = None;
        let mut t = 420_000;
        while released.is_none() && t < 1_000_000 {
            t += 1_000;
            released = m.pass(t, [], [], || counts(4_100)).latch_changed;
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
        let o = m.pass(quiet + 1_000, [(Level::Low, 5)], [], || counts(3_900));
        assert!(!o.may_go_dormant);
    }

    #[test]
    fn a_stalled_motor_is_stopped_shown_and_needs_a_new_on() {
        let mut m = MainLoop::new(false);
        idle(&mut m, 0, 290_000, 3_900);
        let o = m.pass(400_000, on_frame(), [], || counts(3_900));
        assert_eq!(o.event, Some(Event::Started));
        assert!(o.hall_power, "the latches are powered with the start");
        // The duty is zero on the starting pass; the next pass comes when
        // the ramp's reference first is non-zero, and its duty is.
        assert_eq!(o.duty, Duty::ZERO);
        let soon = o.next_pass_in_us.expect("an early pass after the start");
        assert!(soon < board::WAKE_PERIOD_US);
        let o = m.pass(400_000 + u64::from(soon), [], [], || counts(3_900));
        assert!(o.duty > Duty::ZERO && o.next_pass_in_us.is_none());
        // No Hall edge: driven past the soft start for the stall time.
        let stall_us = u64::from(board::RATE.stall_us);
        let ramp_us = u64::from(board::RATE.motor.ramp_us);
        let before = idle(&mut m, 400_000, 400_000 + ramp_us + stall_us, 3_900);
        assert!(before.duty > Duty::ZERO && before.fault.is_none());
        let o = m.pass(400_000 + ramp_us + stall_us + 1_000, [], [], || {
            counts(3_900)
        });
        assert_eq!(o.fault, Some(SensorFault::Stalled));
        assert_eq!(
            (o.duty, o.state, o.hall_power),
            (Duty::ZERO, MotorState::Off, false)
        );
        assert_eq!(o.led, LedMode::Fault);
        let later = idle(&mut m, 6_000_000, 8_000_000, 3_900);
        assert_eq!((later.duty, later.led), (Duty::ZERO, LedMode::Fault));
    }

    #[test]
    fn quadrature_edges_become_the_rate() {
        let mut m = MainLoop::new(false);
        idle(&mut m, 0, 290_000, 3_900);
        m.pass(400_000, on_frame(), [], || counts(3_900));
        // 0.5 Hz: 16 edges a turn, one every 125 ms, Gray order A leads B.
        let gray = [(false, false), (false, true), (true, true), (true, false)];
        let mut out = None;
        for k in 0..40u32 {
            let t = 500_000 + u64::from(k) * 125_000;
            let (a, b) = gray[k as usize % 4];
            let e = HallEdge {
                t_us: t as u32,
                a,
                b,
            };
            out = Some(m.pass(t, [], [e], || counts(3_900)));
        }
        let o = out.unwrap_or_else(|| unreachable!());
        assert_eq!(o.rate_mhz, Some(500));
        assert_eq!(o.fault, None);
        assert!(o.reference_mhz > 0 && o.reference_mhz <= board::DEFAULT_RATE_MHZ);
    }

    fn frame(address: u8, command: u8, at_us: u32) -> heapless::Vec<(Level, u32), 80> {
        let mut v = heapless::Vec::new();
        for_each_edge(at_us, &frame_pulses_us(address, command), |l, t| {
            let _ = v.push((l, t));
        });
        v
    }

    #[test]
    fn rate_keys_change_only_the_set_point_and_other_remotes_are_counted() {
        use crate::nec::REPEAT_PULSES_US;
        let keys = board::SET_POINT_KEYS;
        let mut m = MainLoop::new(false);
        idle(&mut m, 0, 290_000, 3_900);
        let o = m.pass(
            400_000,
            frame(board::NEC_ADDRESS, keys.presets[0].0, 300_000),
            [],
            || counts(3_900),
        );
        assert_eq!(o.set_point_changed, Some(keys.presets[0].1));
        assert_eq!(
            (o.state, o.duty),
            (MotorState::Off, Duty::ZERO),
            "a key never starts"
        );
        let o = m.pass(
            500_000,
            frame(board::NEC_ADDRESS, keys.faster, 400_000),
            [],
            || counts(3_900),
        );
        assert_eq!(o.set_point_changed, Some(keys.presets[0].1 + keys.step_mhz));
        // A held key's repeat frames step nothing.
        let mut rep = heapless::Vec::<(Level, u32), 8>::new();
        for_each_edge(520_000, &REPEAT_PULSES_US, |l, t| {
            let _ = rep.push((l, t));
        });
        assert_eq!(
            m.pass(600_000, rep, [], || counts(3_900)).set_point_changed,
            None
        );
        assert_eq!(
            m.controller().set_rate(),
            Some(keys.presets[0].1 + keys.step_mhz)
        );
        // Another remote's On: ignored, counted.
        let o = m.pass(800_000, frame(0x5a, board::NEC_CMD_ON, 700_000), [], || {
            counts(3_900)
        });
        assert_eq!(
            (o.command, o.state, o.foreign_frames),
            (None, MotorState::Off, 1)
        );
    }
}
