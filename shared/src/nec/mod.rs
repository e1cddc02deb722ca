//! NEC infrared remote protocol: a decoder fed with the edge timestamps of a
//! TSOP-style receiver (output low while a 38 kHz burst is received).
//!
//! A frame is a 9 ms burst, a 4.5 ms space, 32 bits sent LSB first (address,
//! inverted address, command, inverted command; an extended-NEC remote
//! sends a 16-bit address in place of the address and its inverse, so only
//! the command carries the inversion check there; every bit is a 562.5 us burst
//! followed by a 562.5 us space for 0 or a 1687.5 us space for 1) and a final
//! 562.5 us stop burst. A held key sends repeat frames: 9 ms burst, 2.25 ms
//! space, stop burst. Repeats are reported but carry no command, so a stuck
//! key can never switch the motor on by itself.
//!
//! Hand-written rather than the `infrared` crate: `infrared` is built on
//! embedded-hal 0.2 (the firmware uses 1.0), and its plain `Nec` decoder
//! does not check the inverted address and command bytes, which are the
//! protocol's only integrity check and the main defence against noise
//! turning into a command. The decoder is a small state machine doing O(1)
//! work per edge (no buffer of past edges, no loops), so it can run in the
//! GPIO interrupt or in the main loop alike, and it never panics: durations
//! are wrapping differences of `u32` microsecond timestamps.
//!
//! `decoder` turns receiver edges into frames; `pulses` synthesises the
//! receiver's output for a frame (tests, the simulation, the fuzz target).

mod decoder;
mod pulses;

pub use decoder::{AddressFilter, NecDecoder, NecEvent};

/// A remote's address as sent: the first byte low, the second high. A
/// standard remote sends its 8-bit address and then its inverse; an
/// extended one any other 16 bits. Kept whole, so that two remotes whose
/// first bytes agree are still two (NEC as extended by NEC/Renesas, and as
/// pico-sdk's and IRremote's decoders report it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Address(pub u16);

impl Address {
    /// A standard remote's address `a`: `a`, then `!a`.
    pub const fn standard(a: u8) -> Self {
        Self(a as u16 | ((!a as u16) << 8))
    }

    /// The first byte (the whole address of a standard remote).
    pub const fn low(self) -> u8 {
        self.0 as u8
    }

    /// The second byte is not the first's inverse.
    pub const fn is_extended(self) -> bool {
        (self.0 >> 8) as u8 != !(self.0 as u8)
    }
}
pub use pulses::{
    for_each_edge, frame_pulses_us, raw_frame_pulses_us, FRAME_PULSES, REPEAT_PULSES_US,
};

/// Nominal NEC timings in microseconds (562.5 us rounded down).
pub const LEADER_BURST_US: u32 = 9_000;
pub const LEADER_SPACE_US: u32 = 4_500;
pub const REPEAT_SPACE_US: u32 = 2_250;
pub const BIT_BURST_US: u32 = 562;
pub const ZERO_SPACE_US: u32 = 562;
pub const ONE_SPACE_US: u32 = 1_687;

/// A partial frame older than this is abandoned. The longest legal pause
/// inside a frame is the 9 ms leader burst; 12 ms leaves margin for it while
/// still dropping a frame whose tail was lost well before the next one
/// (NEC frames repeat every 108 ms).
pub const FRAME_GAP_US: u32 = 12_000;

/// The receiver's output level right after an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Level {
    /// Output went low: a burst started (falling edge).
    Low,
    /// Output went high: a burst ended (rising edge).
    High,
}
