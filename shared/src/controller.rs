//! The motor controller: the state machine Off -> soft-start ramp ->
//! Running -> Off, with battery-voltage compensation of the PWM duty, a
//! maximum run time, and the battery and fault interlocks.
//!
//! The duty is target motor voltage / measured cell voltage, so the motor
//! sees the same average voltage while the cell sags from 4.2 V towards the
//! cut-off: the paper treats the motor torque as constant through a run,
//! which holds only if the motor voltage does. The soft start ramps the
//! target voltage linearly, which limits the start current (a coreless
//! motor at standstill draws V/R) and with it the cell's start sag.
//!
//! Time is an argument (`now_us`, microseconds from any monotonic 64-bit
//! counter): the firmware passes the RP2040 timer, tests pass simulated
//! time. Going backwards is tolerated (treated as no time elapsed).

use crate::battery::{BatteryLevel, BatteryStatus};
use crate::command::Command;

/// PWM duty as a fraction of the period, in units of 1/65536. Integer
/// arithmetic keeps the Cortex-M0+ (no FPU) free of soft-float code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Duty(u32);

impl Duty {
    pub const ZERO: Duty = Duty(0);
    pub const FULL: Duty = Duty(1 << 16);

    /// `num / den`, clamped to [0, 1]; zero if `den` is zero.
    pub fn from_ratio(num: u32, den: u32) -> Duty {
        if den == 0 {
            return Duty::ZERO;
        }
        let raw = (u64::from(num) << 16) / u64::from(den);
        Duty(u32::try_from(raw).unwrap_or(u32::MAX).min(Self::FULL.0))
    }

    /// Duty in percent (for configuration and logs).
    pub const fn percent(p: u32) -> Duty {
        let p = if p > 100 { 100 } else { p };
        Duty((p << 16) / 100)
    }

    /// Fraction of full scale, 0..=65536.
    pub const fn raw(self) -> u32 {
        self.0
    }

    pub fn as_f64(self) -> f64 {
        f64::from(self.0) / f64::from(Self::FULL.0)
    }

    /// Compare value for a PWM counter that counts 0..=`top`: the output is
    /// high for `counts` of the `top + 1` ticks, so `top + 1` means always on.
    pub fn counts(self, top: u16) -> u16 {
        let period = u64::from(top) + 1;
        let c = (period * u64::from(self.0) + (1 << 15)) >> 16;
        u16::try_from(c.min(period)).unwrap_or(u16::MAX)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ControllerConfig {
    /// Soft-start ramp length; 0 starts at full target voltage.
    pub ramp_us: u32,
    /// Average voltage the motor should see once running. 3.0 V sits below
    /// the lowest loaded cell voltage the monitor allows (3.3 V cut-off), so
    /// compensation holds over the whole usable discharge.
    pub target_motor_mv: u16,
    /// Upper duty clamp.
    pub max_duty: Duty,
    /// Safety stop after this long running (a lost Off frame must not
    /// drain the cell flat: the paper's runs last about 10 minutes).
    pub max_run_us: u64,
}

impl ControllerConfig {
    pub const DEFAULT: Self = Self {
        ramp_us: 250_000,
        target_motor_mv: 3_000,
        max_duty: Duty::FULL,
        max_run_us: 600_000_000,
    };
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MotorState {
    Off,
    Ramping,
    Running,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StopReason {
    Command,
    MaxRunTime,
    LowBattery,
    BatteryFault,
}

/// A state change, for the firmware's log and the tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event {
    Started,
    RampDone,
    Stopped(StopReason),
    /// An On command arrived while the battery forbids running.
    StartRefused(StopReason),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Output {
    pub duty: Duty,
    pub state: MotorState,
    pub event: Option<Event>,
}

#[derive(Clone, Debug)]
pub struct Controller {
    cfg: ControllerConfig,
    state: MotorState,
    started_us: u64,
}

impl Controller {
    pub const fn new(cfg: ControllerConfig) -> Self {
        Self {
            cfg,
            state: MotorState::Off,
            started_us: 0,
        }
    }

    pub fn state(&self) -> MotorState {
        self.state
    }

    pub fn config(&self) -> &ControllerConfig {
        &self.cfg
    }

    /// One control step: apply `command` (if any), the interlocks and the
    /// timers, and return the duty to apply now. Call it every main-loop
    /// pass and whenever a command arrives; at most one event per call
    /// (a refused or stopping command takes precedence over timers).
    pub fn step(
        &mut self,
        now_us: u64,
        command: Option<Command>,
        battery: BatteryStatus,
    ) -> Output {
        let event = self.transition(now_us, command, battery);
        Output {
            duty: self.duty(now_us, battery),
            state: self.state,
            event,
        }
    }

    fn transition(
        &mut self,
        now_us: u64,
        command: Option<Command>,
        battery: BatteryStatus,
    ) -> Option<Event> {
        let running = self.state != MotorState::Off;
        let interlock = match battery.level {
            BatteryLevel::Cutoff => Some(StopReason::LowBattery),
            BatteryLevel::Fault => Some(StopReason::BatteryFault),
            BatteryLevel::Ok | BatteryLevel::Low => None,
        };
        if command == Some(Command::Off) {
            self.state = MotorState::Off;
            return running.then_some(Event::Stopped(StopReason::Command));
        }
        if let Some(reason) = interlock {
            self.state = MotorState::Off;
            return if running {
                Some(Event::Stopped(reason))
            } else if command == Some(Command::On) {
                Some(Event::StartRefused(reason))
            } else {
                None
            };
        }
        let elapsed_us = now_us.saturating_sub(self.started_us);
        match self.state {
            MotorState::Off if command == Some(Command::On) => {
                self.state = MotorState::Ramping;
                self.started_us = now_us;
                Some(Event::Started)
            }
            MotorState::Off => None,
            // On while running does not extend the run: the time limit is a
            // safety net, not a keep-alive.
            _ if elapsed_us >= self.cfg.max_run_us => {
                self.state = MotorState::Off;
                Some(Event::Stopped(StopReason::MaxRunTime))
            }
            MotorState::Ramping if elapsed_us >= u64::from(self.cfg.ramp_us) => {
                self.state = MotorState::Running;
                Some(Event::RampDone)
            }
            MotorState::Ramping | MotorState::Running => None,
        }
    }

    fn duty(&self, now_us: u64, battery: BatteryStatus) -> Duty {
        let target_mv = u64::from(self.cfg.target_motor_mv);
        let motor_mv = match self.state {
            MotorState::Off => return Duty::ZERO,
            MotorState::Running => target_mv,
            MotorState::Ramping => {
                let ramp_us = u64::from(self.cfg.ramp_us);
                let elapsed_us = now_us.saturating_sub(self.started_us).min(ramp_us);
                (target_mv * elapsed_us)
                    .checked_div(ramp_us)
                    .unwrap_or(target_mv)
            }
        };
        let motor_mv = u32::try_from(motor_mv).unwrap_or(u32::MAX);
        Duty::from_ratio(motor_mv, u32::from(battery.mv)).min(self.cfg.max_duty)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn bat(mv: u16, level: BatteryLevel) -> BatteryStatus {
        BatteryStatus { mv, level }
    }
    const OK: BatteryStatus = BatteryStatus {
        mv: 4_000,
        level: BatteryLevel::Ok,
    };

    #[test]
    fn duty_helpers() {
        assert_eq!(Duty::from_ratio(1, 2).raw(), 1 << 15);
        assert_eq!(Duty::from_ratio(5, 2), Duty::FULL);
        assert_eq!(Duty::from_ratio(5, 0), Duty::ZERO);
        assert_eq!(Duty::FULL.counts(4_999), 5_000);
        assert_eq!(Duty::from_ratio(1, 2).counts(4_999), 2_500);
        assert_eq!(Duty::ZERO.counts(u16::MAX), 0);
        assert_eq!(Duty::percent(250), Duty::FULL);
    }

    #[test]
    fn ramp_then_run_then_off() {
        let mut c = Controller::new(ControllerConfig::DEFAULT);
        let o = c.step(1_000, Some(Command::On), OK);
        assert_eq!(
            (o.state, o.event),
            (MotorState::Ramping, Some(Event::Started))
        );
        assert_eq!(o.duty, Duty::ZERO);
        let half = c.step(1_000 + 125_000, None, OK);
        // Half of 3.0 V over 4.0 V.
        assert_eq!(half.duty, Duty::from_ratio(1_500, 4_000));
        let o = c.step(1_000 + 250_000, None, OK);
        assert_eq!(
            (o.state, o.event),
            (MotorState::Running, Some(Event::RampDone))
        );
        assert_eq!(o.duty, Duty::from_ratio(3_000, 4_000));
        let o = c.step(2_000_000, Some(Command::Off), OK);
        assert_eq!(o.event, Some(Event::Stopped(StopReason::Command)));
        assert_eq!(o.duty, Duty::ZERO);
        assert_eq!(c.step(2_000_001, Some(Command::Off), OK).event, None);
    }

    #[test]
    fn compensates_and_clamps() {
        let mut c = Controller::new(ControllerConfig {
            ramp_us: 0,
            max_duty: Duty::percent(90),
            ..ControllerConfig::DEFAULT
        });
        c.step(0, Some(Command::On), OK);
        let d42 = c.step(10, None, bat(4_200, BatteryLevel::Ok)).duty;
        let d35 = c.step(20, None, bat(3_500, BatteryLevel::Low)).duty;
        // The motor's average voltage, duty * cell, stays at 3.0 V.
        let v42 = d42.as_f64() * 4.2;
        let v35 = d35.as_f64() * 3.5;
        assert!(
            (v42 - 3.0).abs() < 1e-3 && (v35 - 3.0).abs() < 1e-3,
            "{v42} {v35}"
        );
        assert_eq!(
            c.step(30, None, bat(3_000, BatteryLevel::Low)).duty,
            Duty::percent(90)
        );
    }

    #[test]
    fn max_run_time_stops_and_on_does_not_extend_it() {
        let cfg = ControllerConfig::DEFAULT;
        let mut c = Controller::new(cfg);
        c.step(0, Some(Command::On), OK);
        c.step(300_000_000, Some(Command::On), OK);
        assert_eq!(
            c.step(cfg.max_run_us - 1, None, OK).state,
            MotorState::Running
        );
        let o = c.step(cfg.max_run_us, None, OK);
        assert_eq!(o.event, Some(Event::Stopped(StopReason::MaxRunTime)));
        assert_eq!(o.duty, Duty::ZERO);
        // A new On starts a new run.
        assert_eq!(
            c.step(cfg.max_run_us + 1, Some(Command::On), OK).event,
            Some(Event::Started)
        );
    }

    #[test]
    fn battery_interlocks() {
        let mut c = Controller::new(ControllerConfig::DEFAULT);
        let cut = bat(3_200, BatteryLevel::Cutoff);
        let o = c.step(0, Some(Command::On), cut);
        assert_eq!(o.event, Some(Event::StartRefused(StopReason::LowBattery)));
        assert_eq!((o.state, o.duty), (MotorState::Off, Duty::ZERO));
        c.step(10, Some(Command::On), OK);
        let o = c.step(20, None, cut);
        assert_eq!(o.event, Some(Event::Stopped(StopReason::LowBattery)));
        assert_eq!(o.duty, Duty::ZERO);
        c.step(30, Some(Command::On), OK);
        let o = c.step(40, None, bat(0, BatteryLevel::Fault));
        assert_eq!(o.event, Some(Event::Stopped(StopReason::BatteryFault)));
    }

    fn any_command() -> impl Strategy<Value = Option<Command>> {
        prop_oneof![
            Just(None),
            Just(Some(Command::On)),
            Just(Some(Command::Off))
        ]
    }
    fn any_level() -> impl Strategy<Value = BatteryLevel> {
        prop_oneof![
            Just(BatteryLevel::Ok),
            Just(BatteryLevel::Low),
            Just(BatteryLevel::Cutoff),
            Just(BatteryLevel::Fault)
        ]
    }

    proptest! {
        /// Over any sequence of inputs: Off always yields zero duty and the
        /// Off state; a forbidding battery always yields zero duty; duty
        /// never exceeds the clamp; the motor is never on past max run time.
        #[test]
        fn invariants(
            steps in proptest::collection::vec((0u64..2_000_000, any_command(), any::<u16>(), any_level()), 1..300),
            ramp_us in 0u32..1_000_000,
            max_pct in 0u32..=100,
        ) {
            let cfg = ControllerConfig { ramp_us, max_duty: Duty::percent(max_pct), max_run_us: 30_000_000, ..ControllerConfig::DEFAULT };
            let mut c = Controller::new(cfg);
            let mut t = 0u64;
            let mut started: Option<u64> = None;
            for (dt, cmd, mv, level) in steps {
                t += dt;
                let b = bat(mv, level);
                let o = c.step(t, cmd, b);
                if o.event == Some(Event::Started) { started = Some(t); }
                prop_assert!(o.duty <= cfg.max_duty);
                if cmd == Some(Command::Off) || !b.allows_motor() {
                    prop_assert_eq!(o.state, MotorState::Off);
                    prop_assert_eq!(o.duty, Duty::ZERO);
                }
                if o.state == MotorState::Off {
                    prop_assert_eq!(o.duty, Duty::ZERO);
                } else {
                    let s = started.unwrap_or(0);
                    prop_assert!(t - s < cfg.max_run_us);
                    if o.state == MotorState::Running {
                        // Running means the ramp is over.
                        prop_assert!(t - s >= u64::from(ramp_us));
                    }
                }
            }
        }
    }
}
