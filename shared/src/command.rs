//! The robot's command set and its mapping from remote-control codes: the
//! protocol that the firmware and the host simulation both speak.
//!
//! The commands are on/off; the keys that choose the tail's rate are
//! `set_point`'s (they change a set-point, never the motor's state).
//! Frames from other remotes (another NEC address: many cheap remotes send
//! 0x00) are never a key and are counted. The remote obeyed is a
//! [`PairedRemote`]: its whole address (16 bits, `nec::Address`) and its
//! On and Off keys, learned in pairing, so that two remotes of one make
//! (one address) are told apart by the keys each robot was taught.

use crate::nec::{Address, AddressFilter, Level, NecDecoder, NecEvent};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Command {
    On,
    Off,
}

impl Command {
    /// Combine commands received together (e.g. drained from one queue in
    /// one main-loop pass): `Off` wins whatever the order, so a stop can
    /// never be masked by a start.
    pub fn merge(pending: Option<Command>, new: Command) -> Command {
        match (pending, new) {
            (Some(Command::Off), _) | (_, Command::Off) => Command::Off,
            _ => Command::On,
        }
    }
}

/// Which remote (NEC address) and which keys (command codes) mean what.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct KeyMap {
    pub address: u8,
    pub on: u8,
    pub off: u8,
}

impl KeyMap {
    /// The command for a decoded frame, if it is one of ours. Off is
    /// checked first so a (mis)configured map with `on == off` stops.
    pub const fn lookup(&self, address: u8, command: u8) -> Option<Command> {
        if address != self.address {
            None
        } else if command == self.off {
            Some(Command::Off)
        } else if command == self.on {
            Some(Command::On)
        } else {
            None
        }
    }
}

/// The remote a robot obeys: its address and which of its keys mean On
/// and Off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PairedRemote {
    pub address: Address,
    pub on: u8,
    pub off: u8,
}

impl PairedRemote {
    /// The key map's remote (a standard address, its keys).
    pub const fn of_keys(keys: KeyMap) -> Self {
        Self {
            address: Address::standard(keys.address),
            on: keys.on,
            off: keys.off,
        }
    }

    /// The command for a key of this remote. Off first, as in `KeyMap`.
    pub const fn lookup(&self, command: u8) -> Option<Command> {
        if command == self.off {
            Some(Command::Off)
        } else if command == self.on {
            Some(Command::On)
        } else {
            None
        }
    }
}

/// What a receiver edge completed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RemoteEvent {
    /// A frame from the paired remote: its command code.
    Key(u8),
    /// A frame from another remote (ignored, counted).
    Foreign { address: Address, command: u8 },
    /// A repeat frame (a key held): never a key press.
    Repeat,
}

/// NEC decoder plus key map: receiver edges in, commands out. Repeat frames
/// and frames from other remotes never produce a command. The remote obeyed
/// is the paired one (`pairing`): the key map's remote until
/// [`Remote::set_paired`] says otherwise; unpaired, none.
#[derive(Clone, Debug)]
pub struct Remote {
    decoder: NecDecoder,
    keys: KeyMap,
    paired: Option<PairedRemote>,
    foreign_frames: u32,
}

impl Remote {
    pub const fn new(keys: KeyMap) -> Self {
        Self {
            decoder: NecDecoder::new(AddressFilter::ANY),
            keys,
            paired: Some(PairedRemote::of_keys(keys)),
            foreign_frames: 0,
        }
    }

    pub fn edge(&mut self, level: Level, t_us: u32) -> Option<Command> {
        let code = self.edge_code(level, t_us)?;
        self.paired?.lookup(code)
    }

    /// The command code of a complete frame from our remote; repeat
    /// frames and other addresses (counted) give nothing.
    pub fn edge_code(&mut self, level: Level, t_us: u32) -> Option<u8> {
        match self.edge_event(level, t_us)? {
            RemoteEvent::Key(code) => Some(code),
            RemoteEvent::Foreign { .. } | RemoteEvent::Repeat => None,
        }
    }

    /// What the edge completed, if anything; frames from other remotes
    /// (every frame while unpaired) are counted.
    pub fn edge_event(&mut self, level: Level, t_us: u32) -> Option<RemoteEvent> {
        Some(match self.decoder.edge(level, t_us)? {
            NecEvent::Frame { address, command }
                if self.paired.is_some_and(|p| p.address == address) =>
            {
                RemoteEvent::Key(command)
            }
            NecEvent::Frame { address, command } => {
                self.foreign_frames = self.foreign_frames.saturating_add(1);
                RemoteEvent::Foreign { address, command }
            }
            NecEvent::Repeat => RemoteEvent::Repeat,
        })
    }

    /// Obey `remote` from now on (`None`: no remote).
    pub fn set_paired(&mut self, remote: Option<PairedRemote>) {
        self.paired = remote;
    }

    pub fn paired(&self) -> Option<PairedRemote> {
        self.paired
    }

    pub fn keys(&self) -> &KeyMap {
        &self.keys
    }

    /// Complete frames from other remotes since power-up.
    pub fn foreign_frames(&self) -> u32 {
        self.foreign_frames
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nec::{for_each_edge, frame_pulses_us, REPEAT_PULSES_US};
    use proptest::prelude::*;

    const KEYS: KeyMap = KeyMap {
        address: 0x00,
        on: 0x45,
        off: 0x47,
    };

    #[test]
    fn lookup() {
        assert_eq!(KEYS.lookup(0x00, 0x45), Some(Command::On));
        assert_eq!(KEYS.lookup(0x00, 0x47), Some(Command::Off));
        assert_eq!(KEYS.lookup(0x00, 0x46), None);
        assert_eq!(KEYS.lookup(0x01, 0x45), None);
        let same = KeyMap {
            on: 7,
            off: 7,
            ..KEYS
        };
        assert_eq!(same.lookup(0, 7), Some(Command::Off));
    }

    #[test]
    fn remote_frames_and_repeats() {
        let mut r = Remote::new(KEYS);
        let mut got = [None; 3];
        let mut t = for_each_edge(0, &frame_pulses_us(0, 0x45), |l, t| {
            if let Some(c) = r.edge(l, t) {
                got[0] = Some(c);
            }
        });
        t = for_each_edge(t + 40_000, &REPEAT_PULSES_US, |l, t| {
            if let Some(c) = r.edge(l, t) {
                got[1] = Some(c);
            }
        });
        for_each_edge(t + 100_000, &frame_pulses_us(0, 0x47), |l, t| {
            if let Some(c) = r.edge(l, t) {
                got[2] = Some(c);
            }
        });
        assert_eq!(got, [Some(Command::On), None, Some(Command::Off)]);
    }

    #[test]
    fn unpaired_obeys_nobody_and_pairing_moves_the_address() {
        let mut r = Remote::new(KEYS);
        r.set_paired(None);
        let mut got = None;
        let t = for_each_edge(0, &frame_pulses_us(0x00, 0x45), |l, t| {
            got = got.or(r.edge(l, t));
        });
        assert_eq!((got, r.foreign_frames()), (None, 1));
        r.set_paired(Some(PairedRemote {
            address: Address::standard(0x5a),
            ..PairedRemote::of_keys(KEYS)
        }));
        let mut events = [None; 2];
        let t = for_each_edge(t + 50_000, &frame_pulses_us(0x5a, 0x45), |l, t| {
            events[0] = events[0].or(r.edge_event(l, t));
        });
        for_each_edge(t + 50_000, &frame_pulses_us(0x00, 0x45), |l, t| {
            events[1] = events[1].or(r.edge_event(l, t));
        });
        assert_eq!(
            events,
            [
                Some(RemoteEvent::Key(0x45)),
                Some(RemoteEvent::Foreign {
                    address: Address::standard(0),
                    command: 0x45
                })
            ]
        );
        assert_eq!(r.foreign_frames(), 2);
    }

    proptest! {
        #[test]
        fn off_wins_in_any_order(cmds in proptest::collection::vec(prop_oneof![Just(Command::On), Just(Command::Off)], 1..20)) {
            let merged = cmds.iter().fold(None, |acc, &c| Some(Command::merge(acc, c)));
            let expect = if cmds.contains(&Command::Off) { Command::Off } else { Command::On };
            prop_assert_eq!(merged, Some(expect));
        }
    }
}
