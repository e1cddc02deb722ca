//! Pairing the robot with its own remote. Address 0x00 is what many cheap
//! NEC remotes send, and two remotes of one make send one address, so a
//! robot that obeyed an address alone would start whenever someone in the
//! lab pressed On on a remote like its own. A robot obeys one remote: its
//! whole address (16 bits: an extended-NEC remote's own, or a standard
//! one's byte and its inverse, `nec::Address`) and the keys it was taught,
//! learned after power-up and kept in flash; frames from other addresses
//! are ignored and counted (the run log's foreign-frame counts).
//!
//! How to pair: power the robot up and, within the window (5 s), hold the
//! remote's Off key (CH+) for 1 s: one frame carries the address, then the
//! remote sends a repeat frame every 108 ms while the key is held. The
//! hold counts from that frame to a repeat at least 1 s later, with no gap
//! of more than 250 ms (two repeats lost) between; a frame from any other
//! address or key starts it afresh. Off is the key because it is the one
//! whose meaning is safe whoever sends it; holding it is a deliberate act
//! that a stray press does not make. The robot is then paired, with the
//! board's On key.
//!
//! To tell two remotes of one make apart, teach the robot its own On key:
//! within `learn_us` (5 s) of that pairing, hold another key of the same
//! remote for 1 s; it becomes this robot's On (the board's On no longer
//! is). A neighbour whose robot was taught another key can press its On
//! at will: this robot sees a key it does not know. (The first frame of
//! that hold still acts as whatever the key meant before, e.g. a rate key.)
//! After that, or when `learn_us` has passed, the window closes.
//!
//! An unpaired robot (new, or its pairing sector erased) obeys no remote:
//! On, Off and the rate keys do nothing and the motor cannot start (the
//! LED's unpaired pattern says why). Holding Off in the window of a later
//! power-up re-pairs, also with another remote.
//!
//! NEC timing: a frame, then repeats every 108 ms (NEC protocol, as in
//! `nec`). Where the remote is kept: [`sector`].

pub mod sector;

use crate::command::PairedRemote;
use crate::nec::Address;

/// How pairing is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairingConfig {
    /// The window after power-up in which a hold may start.
    pub window_us: u64,
    /// How long the key must be held.
    pub hold_us: u64,
    /// The longest gap between the frames of one hold.
    pub max_gap_us: u64,
    /// The key to hold (a command code): the remote's Off.
    pub key: u8,
    /// The On key of a remote paired without teaching one.
    pub on: u8,
    /// After pairing, how long a hold of another key may start that
    /// teaches the robot its On key.
    pub learn_us: u64,
}

impl PairingConfig {
    /// 5 s window, 1 s hold of `off`, at most 250 ms between frames; On is
    /// `on` unless another key is taught within 5 s of pairing.
    pub const fn hold(off: u8, on: u8) -> Self {
        Self {
            window_us: 5_000_000,
            hold_us: 1_000_000,
            max_gap_us: 250_000,
            key: off,
            on,
            learn_us: 5_000_000,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Hold {
    address: Address,
    key: u8,
    since_us: u64,
    last_us: u64,
}

/// The pairing window's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pairing {
    cfg: PairingConfig,
    hold: Option<Hold>,
    /// Paired in this window, and until when its On key may be taught.
    paired: Option<(PairedRemote, u64)>,
    done: bool,
}

impl Pairing {
    pub const fn new(cfg: PairingConfig) -> Self {
        Self {
            cfg,
            hold: None,
            paired: None,
            done: false,
        }
    }

    /// The window is open: after power-up and not yet paired in it, or
    /// paired and still able to learn the On key.
    pub fn window_open(&self, now_us: u64) -> bool {
        match self.paired {
            _ if self.done => false,
            Some((_, until)) => now_us < until,
            None => now_us < self.cfg.window_us,
        }
    }

    /// A complete frame at `now_us`: may start a hold.
    pub fn frame(&mut self, now_us: u64, address: Address, command: u8) {
        let starts = self.window_open(now_us)
            && match self.paired {
                // Teaching On: another key of the same remote.
                Some((p, _)) => p.address == address && command != p.off,
                None => command == self.cfg.key,
            };
        self.hold = starts.then_some(Hold {
            address,
            key: command,
            since_us: now_us,
            last_us: now_us,
        });
    }

    /// A repeat frame at `now_us`: the remote as now paired, if a hold
    /// completed (the first pairing, or its On key taught).
    pub fn repeat(&mut self, now_us: u64) -> Option<PairedRemote> {
        let h = self.hold.as_mut()?;
        if now_us.saturating_sub(h.last_us) > self.cfg.max_gap_us {
            self.hold = None;
            return None;
        }
        h.last_us = now_us;
        if now_us.saturating_sub(h.since_us) < self.cfg.hold_us {
            return None;
        }
        let h = *h;
        self.hold = None;
        let remote = match self.paired {
            Some((p, _)) => {
                self.done = true;
                PairedRemote { on: h.key, ..p }
            }
            None => {
                let p = PairedRemote {
                    address: h.address,
                    on: self.cfg.on,
                    off: h.key,
                };
                self.paired = Some((p, now_us.saturating_add(self.cfg.learn_us)));
                p
            }
        };
        Some(remote)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const CFG: PairingConfig = PairingConfig::hold(0x47, 0x45);

    /// A frame at `t0` and repeats every 108 ms for `held_us`.
    fn hold(p: &mut Pairing, t0: u64, address: u8, key: u8, held_us: u64) -> Option<u8> {
        hold_remote(p, t0, Address::standard(address), key, held_us).map(|r| r.address.low())
    }

    fn hold_remote(
        p: &mut Pairing,
        t0: u64,
        address: Address,
        key: u8,
        held_us: u64,
    ) -> Option<PairedRemote> {
        p.frame(t0, address, key);
        let mut t = t0 + 108_000;
        let mut got = None;
        while t <= t0 + held_us {
            got = got.or(p.repeat(t));
            t += 108_000;
        }
        got
    }

    #[test]
    fn a_one_second_hold_in_the_window_pairs() {
        let mut p = Pairing::new(CFG);
        assert_eq!(hold(&mut p, 2_000_000, 0x5a, 0x47, 1_100_000), Some(0x5a));
        // Another remote's Off, still in the window: not a second pairing.
        assert_eq!(hold(&mut p, 3_500_000, 0x00, 0x47, 2_000_000), None);
        assert!(p.window_open(8_000_000), "learning On until 5 s after");
        assert!(!p.window_open(8_200_000), "then closed");
    }

    #[test]
    fn short_holds_other_keys_gaps_and_late_holds_do_not() {
        let mut p = Pairing::new(CFG);
        assert_eq!(hold(&mut p, 100_000, 0x5a, 0x47, 900_000), None, "0.9 s");
        assert_eq!(hold(&mut p, 1_200_000, 0x5a, 0x45, 2_000_000), None, "On");
        assert_eq!(hold(&mut p, 5_000_000, 0x5a, 0x47, 2_000_000), None, "late");
        // A gap of three lost repeats breaks the hold.
        let mut p = Pairing::new(CFG);
        p.frame(0, Address::standard(0x5a), 0x47);
        assert_eq!(p.repeat(108_000), None);
        assert_eq!(p.repeat(108_000 + 4 * 108_000), None);
        assert_eq!(p.repeat(1_200_000), None);
        // A repeat alone (no frame) is nobody's.
        let mut p = Pairing::new(CFG);
        assert_eq!(p.repeat(1_500_000), None);
    }

    #[test]
    fn another_frame_restarts_the_hold() {
        let mut p = Pairing::new(CFG);
        p.frame(0, Address::standard(0x5a), 0x47);
        p.repeat(108_000);
        p.frame(200_000, Address::standard(0x11), 0x47);
        assert_eq!(p.repeat(1_100_000), None, "gap from the new frame");
        assert_eq!(hold(&mut p, 1_500_000, 0x11, 0x47, 1_100_000), Some(0x11));
    }

    #[test]
    fn a_taught_on_key_replaces_the_boards_and_only_from_that_remote() {
        let mine = Address(0x1280); // extended: 0x80 then 0x12
        let mut p = Pairing::new(CFG);
        let paired = hold_remote(&mut p, 500_000, mine, 0x47, 1_100_000).unwrap();
        assert_eq!((paired.address, paired.on, paired.off), (mine, 0x45, 0x47));
        // Another remote's hold cannot teach it; nor can Off itself.
        let other = Address::standard(0x80);
        assert_eq!(hold_remote(&mut p, 2_000_000, other, 0x16, 1_100_000), None);
        assert_eq!(hold_remote(&mut p, 3_200_000, mine, 0x47, 1_100_000), None);
        let taught = hold_remote(&mut p, 4_400_000, mine, 0x16, 1_100_000).unwrap();
        assert_eq!((taught.address, taught.on, taught.off), (mine, 0x16, 0x47));
        assert!(!p.window_open(5_600_000), "taught: closed");
        assert_eq!(hold_remote(&mut p, 5_700_000, mine, 0x0c, 1_100_000), None);
    }

    proptest! {
        /// Whatever arrives, pairing happens only after a frame of the key
        /// inside the window and at least the hold time later.
        #[test]
        fn pairs_only_after_a_whole_hold(events in proptest::collection::vec((0u64..400_000, any::<bool>(), any::<u8>(), prop_oneof![Just(0x47u8), any::<u8>()]), 0..60)) {
            let mut p = Pairing::new(CFG);
            let mut t = 0;
            let mut last_frame = None;
            let mut paired: Option<PairedRemote> = None;
            for (dt, is_frame, address, command) in events {
                t += dt;
                if is_frame {
                    p.frame(t, Address::standard(address), command);
                    last_frame = Some((t, address, command));
                } else if let Some(r) = p.repeat(t) {
                    let (t0, address, command) = last_frame.expect("a frame started it");
                    prop_assert!(t - t0 >= CFG.hold_us);
                    prop_assert_eq!(r.address, Address::standard(address));
                    match paired {
                        // The first: Off held inside the window.
                        None => {
                            prop_assert!(command == 0x47 && t0 < CFG.window_us);
                            prop_assert_eq!((r.on, r.off), (0x45, 0x47));
                        }
                        // Then only the same remote's other key, taught as On.
                        Some(first) => {
                            prop_assert_eq!(first.address, r.address);
                            prop_assert!(command != 0x47);
                            prop_assert_eq!((r.on, r.off), (command, 0x47));
                        }
                    }
                    paired = Some(r);
                }
            }
        }
    }
}
