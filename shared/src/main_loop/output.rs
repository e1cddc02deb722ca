//! What one main-loop pass decided ([`PassOutput`]): the outputs the
//! firmware applies (duty, Hall power, LED, the latch's copy, the next
//! wake-up, dormancy, whether flash may be erased now, a new pairing to
//! store) and what it logs (events, faults, rates, counts).

use crate::battery::BatteryStatus;
use crate::command::Command;
use crate::controller::{Duty, Event, MotorState};
use crate::led::LedMode;
use crate::rate::SensorFault;

/// No IR edge for this long before a flash erase may stall the chip: an
/// NEC frame lasts 68 ms and a held key repeats every 108 ms, so 250 ms
/// of quiet means nobody is pressing a key right now.
pub const ERASE_QUIET_US: u64 = 250_000;

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
    /// An On from Off was refused by the pre-start self-test.
    pub refused_self_test: Option<super::SelfTestFault>,
    /// The supervisor has locked the motor out until the next power-up.
    pub locked_out: bool,
    /// Supervisor trips since power-up.
    pub trips: u16,
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
    /// wake period (the On -> PWM latency).
    pub next_pass_in_us: Option<u32>,
    /// Motor off, USB not connected, no flash erase pending
    /// (`MainLoop::set_erase_pending`) and no IR edge for
    /// `dormant_after_us`: the chip may stop its clocks until the next IR
    /// edge (or VBUS).
    pub may_go_dormant: bool,
    /// The remote obeyed (`None`: unpaired, no remote is).
    pub paired: Option<crate::command::PairedRemote>,
    /// A hold in the pairing window paired this address in this pass
    /// (another than before): store it in flash.
    pub newly_paired: Option<crate::command::PairedRemote>,
    /// The pairing window is open.
    pub pairing_window: bool,
    /// USB is connected: the motor is held off and On refused.
    pub usb_connected: bool,
    /// A flash erase (which stalls the chip for up to 2 s, interrupts
    /// masked) may run now: the motor is off with the gate low, the
    /// pairing window is closed, USB is not connected (its host would
    /// time out), and no IR edge came for [`ERASE_QUIET_US`]. Never while
    /// the motor can run.
    pub may_erase_flash: bool,
}
