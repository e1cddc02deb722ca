//! Status LED patterns, a pure function of the robot's state and the time,
//! so the firmware just writes `is_lit(mode, now)` to the pin each loop and
//! the patterns are testable on the host.
//!
//! Each pattern is distinct at a glance through the glass casing and under
//! the camera (30 fps, so no pulse is shorter than ~3 frames):
//! - Off: a 100 ms blip every 2 s (alive, idle);
//! - Running: steady on;
//! - LowBattery: two 100 ms blips every second;
//! - Fault: fast 5 Hz blinking (a broken battery reading, or a rate-sensor
//!   fault that stopped the motor, shown until the next On);
//! - Pairing: 1 Hz, half lit (the pairing window after power-up is open;
//!   it stops when a remote is paired);
//! - Unpaired: a 500 ms flash every 2 s (no remote is obeyed: On does
//!   nothing until a remote is paired).

use crate::battery::{BatteryLevel, BatteryStatus};
use crate::controller::MotorState;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LedMode {
    Off,
    Running,
    LowBattery,
    Fault,
    Pairing,
    Unpaired,
}

impl LedMode {
    /// The mode to show: a fault (of the battery reading, or of the rate
    /// sensor that stopped the motor, until the next On) outranks a low
    /// battery, which outranks the motor state (a low cell while running
    /// must be visible).
    pub fn of(motor: MotorState, battery: BatteryStatus, sensor_fault: bool) -> LedMode {
        match (battery.level, motor) {
            (BatteryLevel::Fault, _) => LedMode::Fault,
            _ if sensor_fault => LedMode::Fault,
            (BatteryLevel::Cutoff | BatteryLevel::Low, _) => LedMode::LowBattery,
            (BatteryLevel::Ok, MotorState::Off) => LedMode::Off,
            (BatteryLevel::Ok, MotorState::Ramping | MotorState::Running) => LedMode::Running,
        }
    }
}

impl LedMode {
    /// The idle pattern gives way to the pairing window's, or to the
    /// unpaired one; a fault, a low cell and a running motor outrank both.
    pub fn with_pairing(self, window_open: bool, paired: bool) -> LedMode {
        match self {
            LedMode::Off if window_open => LedMode::Pairing,
            LedMode::Off if !paired => LedMode::Unpaired,
            mode => mode,
        }
    }
}

/// Is the LED lit at `now_us` in `mode`?
pub fn is_lit(mode: LedMode, now_us: u64) -> bool {
    let ms = now_us / 1_000;
    match mode {
        LedMode::Off => ms % 2_000 < 100,
        LedMode::Running => true,
        LedMode::LowBattery => {
            let phase = ms % 1_000;
            phase < 100 || (200..300).contains(&phase)
        }
        LedMode::Fault => ms % 200 < 100,
        LedMode::Pairing => ms % 1_000 < 500,
        LedMode::Unpaired => ms % 2_000 < 500,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lit milliseconds and rising edges over `period_ms` starting at `t0_ms`.
    fn profile(mode: LedMode, t0_ms: u64, period_ms: u64) -> (u64, u32) {
        let mut lit = 0;
        let mut rises = 0;
        let mut prev = is_lit(mode, (t0_ms - 1) * 1_000);
        for ms in t0_ms..t0_ms + period_ms {
            let on = is_lit(mode, ms * 1_000);
            lit += u64::from(on);
            rises += u32::from(on && !prev);
            prev = on;
        }
        (lit, rises)
    }

    #[test]
    fn patterns_are_distinct() {
        let t0 = 123_457;
        assert_eq!(profile(LedMode::Off, t0, 2_000), (100, 1));
        assert_eq!(profile(LedMode::Running, t0, 2_000), (2_000, 0));
        assert_eq!(profile(LedMode::LowBattery, t0, 2_000), (400, 4));
        assert_eq!(profile(LedMode::Fault, t0, 2_000), (1_000, 10));
        assert_eq!(profile(LedMode::Pairing, t0, 2_000), (1_000, 2));
        assert_eq!(profile(LedMode::Unpaired, t0, 2_000), (500, 1));
    }

    #[test]
    fn pairing_patterns_only_replace_idle() {
        assert_eq!(LedMode::Off.with_pairing(true, true), LedMode::Pairing);
        assert_eq!(LedMode::Off.with_pairing(false, false), LedMode::Unpaired);
        assert_eq!(LedMode::Off.with_pairing(false, true), LedMode::Off);
        for m in [LedMode::Running, LedMode::LowBattery, LedMode::Fault] {
            assert_eq!(m.with_pairing(true, false), m);
        }
    }

    #[test]
    fn priority() {
        let s = |level| BatteryStatus { mv: 3_700, level };
        assert_eq!(
            LedMode::of(MotorState::Running, s(BatteryLevel::Ok), false),
            LedMode::Running
        );
        assert_eq!(
            LedMode::of(MotorState::Ramping, s(BatteryLevel::Ok), false),
            LedMode::Running
        );
        assert_eq!(
            LedMode::of(MotorState::Off, s(BatteryLevel::Ok), false),
            LedMode::Off
        );
        assert_eq!(
            LedMode::of(MotorState::Running, s(BatteryLevel::Low), false),
            LedMode::LowBattery
        );
        assert_eq!(
            LedMode::of(MotorState::Off, s(BatteryLevel::Cutoff), false),
            LedMode::LowBattery
        );
        assert_eq!(
            LedMode::of(MotorState::Off, s(BatteryLevel::Low), true),
            LedMode::Fault,
            "a sensor fault that stopped the motor outranks a low cell"
        );
        assert_eq!(
            LedMode::of(MotorState::Off, s(BatteryLevel::Fault), false),
            LedMode::Fault
        );
    }
}
