//! NEC frames as receiver output: the burst/space durations of a frame or a
//! repeat, and the edges they make.

use super::{
    Level, BIT_BURST_US, LEADER_BURST_US, LEADER_SPACE_US, ONE_SPACE_US, REPEAT_SPACE_US,
    ZERO_SPACE_US,
};

/// Number of alternating burst/space durations in one NEC frame:
/// leader burst and space, 32 bits of burst and space, stop burst.
pub const FRAME_PULSES: usize = 67;

/// The burst/space durations (starting with a burst) of a frame with
/// `address` and `command` and their inverted bytes. Used by tests, the
/// simulation and the fuzz target to synthesise receiver output.
pub fn frame_pulses_us(address: u8, command: u8) -> [u32; FRAME_PULSES] {
    raw_frame_pulses_us(u32::from_le_bytes([address, !address, command, !command]))
}

/// Durations of a frame carrying any 32-bit payload, LSB first (for tests
/// of frames with wrong inverted bytes).
pub fn raw_frame_pulses_us(payload: u32) -> [u32; FRAME_PULSES] {
    let mut out = [BIT_BURST_US; FRAME_PULSES];
    out[0] = LEADER_BURST_US;
    out[1] = LEADER_SPACE_US;
    for (i, space) in out[2..66].iter_mut().skip(1).step_by(2).enumerate() {
        *space = if payload >> i & 1 == 1 {
            ONE_SPACE_US
        } else {
            ZERO_SPACE_US
        };
    }
    out
}

/// Durations of a repeat frame.
pub const REPEAT_PULSES_US: [u32; 3] = [LEADER_BURST_US, REPEAT_SPACE_US, BIT_BURST_US];

/// Turn burst/space durations (starting with a burst at `start_us`) into
/// edges, calling `f` for each: the first edge is falling.
pub fn for_each_edge(start_us: u32, pulses_us: &[u32], mut f: impl FnMut(Level, u32)) -> u32 {
    let mut t = start_us;
    let mut level = Level::Low;
    f(level, t);
    for &d in pulses_us {
        t = t.wrapping_add(d);
        level = match level {
            Level::Low => Level::High,
            Level::High => Level::Low,
        };
        f(level, t);
    }
    t
}
