//! The robot's state as the `INFO` line reports it after the log's fields
//! (firmware version and commit, battery, rate, the last fault, the
//! supervisor's trips and lock-out, pairing), and the rule for the
//! `BOOTSEL` request: the chip may leave for the ROM's bootloader only
//! while the motor is off and its gate is low, since the ROM leaves the
//! PWM pin to its reset state and nothing would supervise a running motor.

use super::readout::Line;
use crate::battery::BatteryLevel;
use crate::controller::{Duty, MotorState};
use crate::rate::SensorFault;

/// Where pairing stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairingState {
    /// A remote is paired (the `paired=` field of the log part says which).
    Paired,
    /// None is: the motor cannot start.
    Unpaired,
    /// The pairing window is open.
    Window,
}

/// What `INFO` says about the robot beside its log.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Status {
    /// The firmware's version (`CARGO_PKG_VERSION`), at most 16 bytes.
    pub firmware: &'static str,
    /// The commit it was built from, at most 12 bytes (`unknown` outside git).
    pub commit: &'static str,
    pub battery_mv: u16,
    pub battery: BatteryLevel,
    /// The measured rate while running.
    pub rate_mhz: Option<u32>,
    pub set_point_mhz: Option<u32>,
    /// The last fault that stopped the motor since power-up.
    pub fault: Option<SensorFault>,
    /// Supervisor trips (jams, overheating) since power-up.
    pub trips: u16,
    /// The supervisor refuses every start until a power cycle.
    pub locked_out: bool,
    pub pairing: PairingState,
}

fn battery_word(level: BatteryLevel) -> &'static [u8] {
    match level {
        BatteryLevel::Ok => b"ok",
        BatteryLevel::Low => b"low",
        BatteryLevel::Cutoff => b"cutoff",
        BatteryLevel::Fault => b"fault",
    }
}

fn fault_word(fault: Option<SensorFault>) -> &'static [u8] {
    match fault {
        None => b"none",
        Some(SensorFault::Stalled) => b"stalled",
        Some(SensorFault::Reversed) => b"reversed",
        Some(SensorFault::Disconnected) => b"disconnected",
        Some(SensorFault::Overspeed) => b"overspeed",
        Some(SensorFault::Jammed) => b"jammed",
        Some(SensorFault::Overheated) => b"overheated",
    }
}

impl Status {
    /// Append ` fw=.. commit=.. battery_mv=.. battery=.. rate_mhz=..
    /// set_mhz=.. fault=.. trips=.. lockout=.. pairing=..`. At most 171
    /// bytes with the field limits above (10-digit rates, 5-digit counts).
    pub(super) fn put(&self, s: &mut Line) {
        let clip = |t: &'static str, n: usize| &t.as_bytes()[..t.len().min(n)];
        s.put(b" fw=");
        s.put(clip(self.firmware, 16));
        s.put(b" commit=");
        s.put(clip(self.commit, 12));
        s.put(b" battery_mv=");
        s.put_decimal(u32::from(self.battery_mv));
        s.put(b" battery=");
        s.put(battery_word(self.battery));
        s.put(b" rate_mhz=");
        put_optional(s, self.rate_mhz);
        s.put(b" set_mhz=");
        put_optional(s, self.set_point_mhz);
        s.put(b" fault=");
        s.put(fault_word(self.fault));
        s.put(b" trips=");
        s.put_decimal(u32::from(self.trips));
        s.put(b" lockout=");
        s.put(if self.locked_out { b"yes" } else { b"no" });
        s.put(b" pairing=");
        s.put(match self.pairing {
            PairingState::Paired => b"paired".as_slice(),
            PairingState::Unpaired => b"unpaired",
            PairingState::Window => b"window",
        });
    }
}

fn put_optional(s: &mut Line, n: Option<u32>) {
    match n {
        Some(n) => s.put_decimal(n),
        None => s.put(b"none"),
    }
}

/// The answer to `BOOTSEL` when it is honoured.
pub const BOOTSEL_ANSWER: &[u8] = b"OK BOOTSEL\n";
/// The answer when it is refused.
pub const BOOTSEL_REFUSED: &[u8] = b"ERR motor on\n";

/// `BOOTSEL` is honoured: the controller is off, the last duty applied is
/// zero and the gate pin reads low. Each alone is not enough: the state
/// says what the controller decided, the duty what the PWM was told, the
/// pin what the MOSFET's gate sees.
pub fn bootsel_allowed(state: MotorState, applied: Duty, gate_high: bool) -> bool {
    state == MotorState::Off && applied == Duty::ZERO && !gate_high
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::run_log::readout::{info_line, RequestReader, LINE_MAX};
    use crate::run_log::{Header, Request};

    const IDLE: Status = Status {
        firmware: "0.1.0",
        commit: "6b8f116",
        battery_mv: 3_950,
        battery: BatteryLevel::Ok,
        rate_mhz: None,
        set_point_mhz: Some(1_000),
        fault: None,
        trips: 0,
        locked_out: false,
        pairing: PairingState::Paired,
    };

    #[test]
    fn bootsel_only_with_the_motor_off_and_the_gate_low() {
        assert!(bootsel_allowed(MotorState::Off, Duty::ZERO, false));
        assert!(!bootsel_allowed(MotorState::Running, Duty::ZERO, false));
        assert!(!bootsel_allowed(MotorState::Off, Duty::percent(1), false));
        assert!(!bootsel_allowed(MotorState::Off, Duty::ZERO, true));
        let mut r = RequestReader::new();
        let got: std::vec::Vec<_> = b"BOOTSEL\r\nBOOTSELX\n"
            .iter()
            .filter_map(|&b| r.push(b))
            .collect();
        assert_eq!(got, [Request::Bootsel, Request::Unknown]);
    }

    #[test]
    fn info_carries_the_status_and_the_longest_line_fits() {
        let header = Header {
            sample_period_ms: 100,
            record_count: 3,
            dropped_records: 0,
            foreign_frames: 2,
            paired_address: Some(0x00),
            flags: 0,
        };
        let line = info_line(&header, Some(&IDLE));
        let text = core::str::from_utf8(&line).unwrap();
        assert!(
            text.starts_with("swimbot-log v2 records=3 period_ms=100 "),
            "{text}"
        );
        assert!(
            text.ends_with(
                " fw=0.1.0 commit=6b8f116 battery_mv=3950 battery=ok rate_mhz=none \
                 set_mhz=1000 fault=none trips=0 lockout=no pairing=paired\n"
            ),
            "{text}"
        );
        let worst = Header {
            sample_period_ms: u16::MAX,
            record_count: u32::MAX,
            dropped_records: u32::MAX,
            foreign_frames: u32::MAX,
            paired_address: Some(0xff),
            flags: 0,
        };
        let status = Status {
            firmware: "0123456789abcdefTOO-LONG",
            commit: "0123456789abTOO-LONG",
            battery_mv: u16::MAX,
            battery: BatteryLevel::Cutoff,
            rate_mhz: Some(u32::MAX),
            set_point_mhz: Some(u32::MAX),
            fault: Some(SensorFault::Disconnected),
            trips: u16::MAX,
            locked_out: true,
            pairing: PairingState::Unpaired,
        };
        let line = info_line(&worst, Some(&status));
        assert_eq!(line.len(), 133 - 1 + 171 + 1, "every field there");
        assert!(line.len() <= LINE_MAX);
        assert!(line.ends_with(b" pairing=unpaired\n"), "a put was dropped");
        assert!(line.windows(9).any(|w| w == b"commit=01"));
    }
}
