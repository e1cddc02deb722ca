//! The NEC decoder: a state machine fed with receiver edges, O(1) work per
//! edge, that reports a frame only when its command's inverted byte checks
//! out (the address may be a standard or an extended one, `Address`).

use super::{
    Address, Level, BIT_BURST_US, FRAME_GAP_US, LEADER_BURST_US, LEADER_SPACE_US, ONE_SPACE_US,
    REPEAT_SPACE_US, ZERO_SPACE_US,
};

/// Accept `d` within +-25 % of `nominal`: the protocol's usual tolerance,
/// wide enough for cheap remotes' ceramic resonators and receiver
/// distortion, narrow enough that 0/1 and frame/repeat never overlap.
const fn within_25pct(d: u32, nominal: u32) -> bool {
    let tol = nominal / 4;
    d >= nominal - tol && d <= nominal + tol
}

/// Short data bursts get a wider window: TSOP-type receivers stretch or
/// shorten their output pulses by up to ~150 us relative to the optical
/// burst, which is 27 % of 562 us. Bit values are decided from the
/// burst-to-burst period instead, which that distortion does not change.
const fn bit_burst_ok(d: u32) -> bool {
    d >= 340 && d <= 800
}

/// What a completed frame carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NecEvent {
    /// A full frame whose command and inverted command matched and whose
    /// address's first byte is whitelisted. A standard frame whose address
    /// bytes were corrupted reads as another (extended) address, so it is
    /// never the paired remote's unless that remote is this extended one.
    Frame { address: Address, command: u8 },
    /// A repeat frame (key held). Never a command on its own.
    Repeat,
}

/// The set of NEC addresses (first bytes) a decoder reports; frames from
/// other remotes are dropped. A 256-bit map: O(1) lookup, no lifetimes, `const`-buildable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AddressFilter {
    bits: [u32; 8],
}

impl AddressFilter {
    /// Accept no address at all.
    pub const NONE: Self = Self { bits: [0; 8] };
    /// Accept every address (to count other remotes' frames).
    pub const ANY: Self = Self {
        bits: [u32::MAX; 8],
    };

    /// Accept exactly one address.
    pub const fn only(address: u8) -> Self {
        Self::NONE.with(address)
    }

    /// This filter plus `address`.
    pub const fn with(mut self, address: u8) -> Self {
        // `address >> 5` is at most 7, inside the 8-word map.
        self.bits[(address >> 5) as usize] |= 1 << (address & 31);
        self
    }

    pub const fn accepts(&self, address: u8) -> bool {
        self.bits[(address >> 5) as usize] & (1 << (address & 31)) != 0
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum State {
    /// Waiting for the falling edge of a leader burst.
    Idle,
    /// Inside the leader burst.
    LeaderBurst,
    /// Inside the space after the leader: 4.5 ms (frame) or 2.25 ms (repeat).
    LeaderSpace,
    /// Inside the stop burst of a repeat frame.
    RepeatBurst,
    /// Inside a data burst; `bits` holds this many decoded bits.
    BitBurst,
    /// Inside the space after a data burst.
    BitSpace,
    /// Inside the stop burst after all 32 bits.
    StopBurst,
}

/// NEC decoder state. Feed every receiver edge to [`NecDecoder::edge`].
#[derive(Clone, Debug)]
pub struct NecDecoder {
    filter: AddressFilter,
    state: State,
    /// Timestamp of the previous edge (any polarity).
    last_edge_us: u32,
    /// Timestamp of the last falling edge (burst start), for bit periods.
    last_fall_us: u32,
    bits: u32,
    nbits: u8,
}

impl NecDecoder {
    pub const fn new(filter: AddressFilter) -> Self {
        Self {
            filter,
            state: State::Idle,
            last_edge_us: 0,
            last_fall_us: 0,
            bits: 0,
            nbits: 0,
        }
    }

    /// True while no frame is in progress.
    pub fn is_idle(&self) -> bool {
        self.state == State::Idle
    }

    /// Process one receiver edge at `t_us` (free-running 1 MHz counter; it
    /// may wrap). Returns an event when the edge completes a valid frame.
    pub fn edge(&mut self, level: Level, t_us: u32) -> Option<NecEvent> {
        let since_edge = t_us.wrapping_sub(self.last_edge_us);
        self.last_edge_us = t_us;
        if since_edge > FRAME_GAP_US {
            // Also catches a timestamp going backwards (huge wrapped value).
            self.state = State::Idle;
        }
        let since_fall = t_us.wrapping_sub(self.last_fall_us);
        match level {
            Level::Low => {
                self.falling(t_us, since_edge, since_fall);
                None
            }
            Level::High => self.rising(since_fall),
        }
    }

    /// A burst started at `t_us`, after a space of `space_us` and
    /// `period_us` after the previous burst started.
    fn falling(&mut self, t_us: u32, space_us: u32, period_us: u32) {
        self.state = match self.state {
            State::LeaderSpace if within_25pct(space_us, LEADER_SPACE_US) => {
                self.bits = 0;
                self.nbits = 0;
                State::BitBurst
            }
            State::LeaderSpace if within_25pct(space_us, REPEAT_SPACE_US) => State::RepeatBurst,
            State::BitSpace => match self.bit_from_period(period_us) {
                Some(bit) => {
                    self.bits |= u32::from(bit) << (self.nbits & 31);
                    self.nbits = self.nbits.saturating_add(1);
                    if self.nbits >= 32 {
                        State::StopBurst
                    } else {
                        State::BitBurst
                    }
                }
                // Not a valid bit: this burst may be the leader of a new frame.
                None => State::LeaderBurst,
            },
            // Idle, or any out-of-sequence falling edge (a lost rising edge,
            // a bad space): resynchronise on this burst as a possible leader.
            _ => State::LeaderBurst,
        };
        self.last_fall_us = t_us;
    }

    /// A burst of `burst_us` just ended: advance, or emit the event of a
    /// frame whose stop burst this was.
    fn rising(&mut self, burst_us: u32) -> Option<NecEvent> {
        let (next, event) = match self.state {
            State::BitBurst if bit_burst_ok(burst_us) => (State::BitSpace, None),
            State::RepeatBurst if bit_burst_ok(burst_us) => (State::Idle, Some(NecEvent::Repeat)),
            State::StopBurst if bit_burst_ok(burst_us) => (State::Idle, self.frame()),
            // A leader-length burst starts a frame whatever came before, so
            // garbage that happened to look like a frame start cannot make
            // the decoder miss the real frame right behind it.
            _ if within_25pct(burst_us, LEADER_BURST_US) => (State::LeaderSpace, None),
            _ => (State::Idle, None),
        };
        self.state = next;
        event
    }

    /// The frame in `bits`, if its command bytes match and its address's
    /// first byte is whitelisted.
    fn frame(&self) -> Option<NecEvent> {
        let [low, high, command, command_inv] = self.bits.to_le_bytes();
        let intact = command ^ command_inv == 0xFF;
        let address = Address(u16::from_le_bytes([low, high]));
        (intact && self.filter.accepts(low)).then_some(NecEvent::Frame { address, command })
    }

    fn bit_from_period(&self, period_us: u32) -> Option<bool> {
        if within_25pct(period_us, BIT_BURST_US + ZERO_SPACE_US) {
            Some(false)
        } else if within_25pct(period_us, BIT_BURST_US + ONE_SPACE_US) {
            Some(true)
        } else {
            None
        }
    }
}
#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::nec::*;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn decode(dec: &mut NecDecoder, start: u32, pulses: &[u32]) -> Vec<NecEvent> {
        let mut out = Vec::new();
        for_each_edge(start, pulses, |l, t| out.extend(dec.edge(l, t)));
        out
    }

    fn any_addr() -> NecDecoder {
        let mut f = AddressFilter::NONE;
        let mut a = 0u8;
        loop {
            f = f.with(a);
            if a == 255 {
                break;
            }
            a += 1;
        }
        NecDecoder::new(f)
    }

    #[test]
    fn decodes_a_frame_and_checks_the_filter() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let ev = decode(&mut dec, 1_000, &frame_pulses_us(0x00, 0x45));
        assert_eq!(
            ev,
            [NecEvent::Frame {
                address: Address::standard(0),
                command: 0x45
            }]
        );
        assert!(dec.is_idle());
        let ev = decode(&mut dec, 200_000, &frame_pulses_us(0x01, 0x45));
        assert!(ev.is_empty(), "address 1 is not whitelisted");
    }

    #[test]
    fn frame_across_timer_wrap() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let ev = decode(&mut dec, u32::MAX - 30_000, &frame_pulses_us(0x00, 0x47));
        assert_eq!(
            ev,
            [NecEvent::Frame {
                address: Address::standard(0),
                command: 0x47
            }]
        );
    }

    #[test]
    fn repeat_frames_are_events_not_frames() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        assert_eq!(decode(&mut dec, 5, &REPEAT_PULSES_US), [NecEvent::Repeat]);
    }

    #[test]
    fn inverted_bytes_are_checked() {
        let mut dec = any_addr();
        // Address byte and its inverse disagree: an extended address, not
        // the standard remote's.
        let extended = u32::from_le_bytes([0x00, 0xFE, 0x45, 0xBA]);
        assert_eq!(
            decode(&mut dec, 0, &raw_frame_pulses_us(extended)),
            [NecEvent::Frame {
                address: Address(0xFE00),
                command: 0x45
            }]
        );
        assert!(Address(0xFE00).is_extended() && !Address::standard(0).is_extended());
        assert_ne!(Address(0xFE00), Address::standard(0));
        let bad_cmd = u32::from_le_bytes([0x00, 0xFF, 0x45, 0x45]);
        assert!(decode(&mut dec, 200_000, &raw_frame_pulses_us(bad_cmd)).is_empty());
        let good = u32::from_le_bytes([0x12, 0xED, 0x45, 0xBA]);
        assert_eq!(
            decode(&mut dec, 400_000, &raw_frame_pulses_us(good)),
            [NecEvent::Frame {
                address: Address::standard(0x12),
                command: 0x45
            }]
        );
    }

    #[test]
    fn a_hole_inside_a_frame_drops_it() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let mut p = frame_pulses_us(0x00, 0x45);
        // A 13 ms burst where a data burst belongs (receiver saturated).
        p[20] = FRAME_GAP_US + 1_000;
        let mut events = Vec::new();
        let end = for_each_edge(0, &p, |l, t| events.extend(dec.edge(l, t)));
        assert!(events.is_empty());
        let ev = decode(&mut dec, end + 20_000, &frame_pulses_us(0x00, 0x47));
        assert_eq!(
            ev,
            [NecEvent::Frame {
                address: Address::standard(0),
                command: 0x47
            }]
        );
    }

    #[test]
    fn truncated_frame_then_silence_then_frame() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let p = frame_pulses_us(0x00, 0x45);
        let end = for_each_edge(0, &p[..40], |l, t| assert!(dec.edge(l, t).is_none()));
        assert!(!dec.is_idle());
        let ev = decode(
            &mut dec,
            end + FRAME_GAP_US + 1,
            &frame_pulses_us(0x00, 0x47),
        );
        assert_eq!(
            ev,
            [NecEvent::Frame {
                address: Address::standard(0),
                command: 0x47
            }]
        );
    }

    #[test]
    fn resynchronises_on_a_leader_right_after_garbage() {
        // Noise bursts followed immediately (no gap) by a real frame.
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let mut pulses = Vec::from([300u32, 700, 1_200, 400, 9_000, 2_000]);
        pulses.extend_from_slice(&frame_pulses_us(0x00, 0x45));
        let ev = decode(&mut dec, 77, &pulses);
        assert_eq!(
            ev,
            [NecEvent::Frame {
                address: Address::standard(0),
                command: 0x45
            }]
        );
    }

    #[test]
    fn tolerance_edges() {
        let mut dec = NecDecoder::new(AddressFilter::only(0x00));
        let scale = |p: &[u32; FRAME_PULSES], num: u32, den: u32| p.map(|d| d * num / den);
        let p = frame_pulses_us(0x00, 0x45);
        assert_eq!(decode(&mut dec, 0, &scale(&p, 120, 100)).len(), 1, "+20 %");
        assert_eq!(
            decode(&mut dec, 500_000, &scale(&p, 80, 100)).len(),
            1,
            "-20 %"
        );
        assert!(
            decode(&mut dec, 1_000_000, &scale(&p, 135, 100)).is_empty(),
            "+35 %"
        );
        assert!(
            decode(&mut dec, 1_500_000, &scale(&p, 65, 100)).is_empty(),
            "-35 %"
        );
    }

    #[test]
    fn address_filter() {
        let f = AddressFilter::only(0x00).with(0xFF).with(0x20);
        assert!(f.accepts(0x00) && f.accepts(0xFF) && f.accepts(0x20));
        assert!(!f.accepts(0x01) && !f.accepts(0x1F) && !f.accepts(0x21));
        assert!(!AddressFilter::NONE.accepts(0));
    }

    proptest! {
        #[test]
        fn every_valid_frame_decodes(addr: u8, cmd: u8, start: u32, jitter in proptest::collection::vec(-60i32..60, FRAME_PULSES)) {
            let mut dec = any_addr();
            let mut p = frame_pulses_us(addr, cmd);
            for (d, j) in p.iter_mut().zip(&jitter) {
                *d = d.saturating_add_signed(*j);
            }
            prop_assert_eq!(decode(&mut dec, start, &p), [NecEvent::Frame { address: Address::standard(addr), command: cmd }]);
        }

        /// A flipped command bit never decodes; a flipped address bit
        /// decodes as another address, never as the sender's.
        #[test]
        fn one_flipped_bit_never_decodes_as_the_sent_frame(addr: u8, cmd: u8, bit in 0usize..32) {
            let mut dec = any_addr();
            let payload = u32::from_le_bytes([addr, !addr, cmd, !cmd]) ^ (1 << bit);
            let got = decode(&mut dec, 0, &raw_frame_pulses_us(payload));
            if bit >= 16 {
                prop_assert!(got.is_empty());
            } else {
                prop_assert_eq!(got.len(), 1);
                let NecEvent::Frame { address, command } = got[0] else {
                    return Err(TestCaseError::fail("not a frame"));
                };
                prop_assert_eq!(command, cmd);
                prop_assert_ne!(address, Address::standard(addr));
            }
        }

        #[test]
        fn random_edges_never_panic_and_rarely_decode(
            edges in proptest::collection::vec((any::<bool>(), 0u32..20_000), 0..300),
        ) {
            let mut dec = NecDecoder::new(AddressFilter::only(0x00));
            let mut t = 0u32;
            for (high, d) in edges {
                t = t.wrapping_add(d);
                let level = if high { Level::High } else { Level::Low };
                // A frame needs 68 edges inside 25 % windows; random edges
                // essentially never get there.
                let frame = matches!(dec.edge(level, t), Some(NecEvent::Frame { .. }));
                prop_assert!(!frame, "random edges decoded as a frame");
            }
        }
    }
}
