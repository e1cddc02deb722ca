//! Pairing the robot with its own remote. Address 0x00
//! is what many cheap NEC remotes send, so a robot that obeyed any of them
//! would start whenever someone in the lab pressed On on another robot's
//! remote. A robot obeys one address, learned in a pairing window after
//! power-up and kept in flash; frames from other addresses are ignored and
//! counted (the run log's foreign-frame counts).
//!
//! How to pair: power the robot up and, within the window (5 s), hold the
//! remote's Off key (CH+) for 1 s: one frame carries the address, then the
//! remote sends a repeat frame every 108 ms while the key is held. The
//! hold counts from that frame to a repeat at least 1 s later, with no gap
//! of more than 250 ms (two repeats lost) between; a frame from any other
//! address or key starts it afresh. Off is the key because it is the one
//! whose meaning is safe whoever sends it; holding it is a deliberate act
//! that a stray press does not make. After pairing the window closes.
//!
//! An unpaired robot (new, or its pairing sector erased) obeys no remote:
//! On, Off and the rate keys do nothing and the motor cannot start (the
//! LED's unpaired pattern says why). Holding Off in the window of a later
//! power-up re-pairs, also with another remote.
//!
//! NEC timing: a frame, then repeats every 108 ms (NEC protocol, as in
//! `nec`). Where the address is kept: [`sector`].

pub mod sector;

/// How pairing is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairingConfig {
    /// The window after power-up in which a hold may start.
    pub window_us: u64,
    /// How long the key must be held.
    pub hold_us: u64,
    /// The longest gap between the frames of one hold.
    pub max_gap_us: u64,
    /// The key to hold (a command code).
    pub key: u8,
}

impl PairingConfig {
    /// 5 s window, 1 s hold of `key`, at most 250 ms between frames.
    pub const fn hold(key: u8) -> Self {
        Self {
            window_us: 5_000_000,
            hold_us: 1_000_000,
            max_gap_us: 250_000,
            key,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Hold {
    address: u8,
    since_us: u64,
    last_us: u64,
}

/// The pairing window's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pairing {
    cfg: PairingConfig,
    hold: Option<Hold>,
    done: bool,
}

impl Pairing {
    pub const fn new(cfg: PairingConfig) -> Self {
        Self {
            cfg,
            hold: None,
            done: false,
        }
    }

    /// The window is open (after power-up, not yet paired in it).
    pub fn window_open(&self, now_us: u64) -> bool {
        !self.done && now_us < self.cfg.window_us
    }

    /// A complete frame at `now_us`: may start a hold.
    pub fn frame(&mut self, now_us: u64, address: u8, command: u8) {
        self.hold = (self.window_open(now_us) && command == self.cfg.key).then_some(Hold {
            address,
            since_us: now_us,
            last_us: now_us,
        });
    }

    /// A repeat frame at `now_us`: the address paired if the hold is done.
    pub fn repeat(&mut self, now_us: u64) -> Option<u8> {
        let h = self.hold.as_mut()?;
        if now_us.saturating_sub(h.last_us) > self.cfg.max_gap_us {
            self.hold = None;
            return None;
        }
        h.last_us = now_us;
        if now_us.saturating_sub(h.since_us) < self.cfg.hold_us {
            return None;
        }
        let address = h.address;
        self.hold = None;
        self.done = true;
        Some(address)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const CFG: PairingConfig = PairingConfig::hold(0x47);

    /// A frame at `t0` and repeats every 108 ms for `held_us`.
    fn hold(p: &mut Pairing, t0: u64, address: u8, key: u8, held_us: u64) -> Option<u8> {
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
        assert!(!p.window_open(2_500_000), "paired: the window closes");
        assert_eq!(hold(&mut p, 3_500_000, 0x00, 0x47, 2_000_000), None);
    }

    #[test]
    fn short_holds_other_keys_gaps_and_late_holds_do_not() {
        let mut p = Pairing::new(CFG);
        assert_eq!(hold(&mut p, 100_000, 0x5a, 0x47, 900_000), None, "0.9 s");
        assert_eq!(hold(&mut p, 1_200_000, 0x5a, 0x45, 2_000_000), None, "On");
        assert_eq!(hold(&mut p, 5_000_000, 0x5a, 0x47, 2_000_000), None, "late");
        // A gap of three lost repeats breaks the hold.
        let mut p = Pairing::new(CFG);
        p.frame(0, 0x5a, 0x47);
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
        p.frame(0, 0x5a, 0x47);
        p.repeat(108_000);
        p.frame(200_000, 0x11, 0x47);
        assert_eq!(p.repeat(1_100_000), None, "gap from the new frame");
        assert_eq!(hold(&mut p, 1_500_000, 0x11, 0x47, 1_100_000), Some(0x11));
    }

    proptest! {
        /// Whatever arrives, pairing happens only after a frame of the key
        /// inside the window and at least the hold time later.
        #[test]
        fn pairs_only_after_a_whole_hold(events in proptest::collection::vec((0u64..400_000, any::<bool>(), any::<u8>(), prop_oneof![Just(0x47u8), any::<u8>()]), 0..60)) {
            let mut p = Pairing::new(CFG);
            let mut t = 0;
            let mut key_frame_at = None;
            for (dt, is_frame, address, command) in events {
                t += dt;
                if is_frame {
                    p.frame(t, address, command);
                    key_frame_at = (command == 0x47 && t < CFG.window_us).then_some((t, address));
                } else if let Some(a) = p.repeat(t) {
                    let (t0, address) = key_frame_at.expect("a key frame started it");
                    prop_assert_eq!(a, address);
                    prop_assert!(t - t0 >= CFG.hold_us);
                }
            }
        }
    }
}
