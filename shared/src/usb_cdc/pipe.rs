//! Endpoint 0's control transfers as a state machine free of the
//! controller: a SETUP, a finished IN packet or a received OUT packet in,
//! the next packet to hand the controller (and what the device must change)
//! out. It owns the data toggles of endpoint 0 (every stage after SETUP
//! starts on DATA1 and the data stage alternates), the split of an answer
//! into 64-byte packets with the closing zero-length packet, the address
//! taken only after its status stage, and the configured state.
//!
//! References: USB 2.0 specification, 8.5.3 (control transfers), 8.6.1
//! (data toggles of control transfers), 9.4.6 (SET_ADDRESS).

use super::control::{data_stage, decide, Action, Reply, Setup, DEFAULT_LINE_CODING};
use super::descriptors::MAX_PACKET;

/// The packet to hand the controller on endpoint 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packet<'a> {
    None,
    /// IN: these bytes (at most 64; empty = a zero-length packet).
    In {
        data: &'a [u8],
        data1: bool,
    },
    /// OUT, up to 64 bytes on DATA1: a status stage or SET_LINE_CODING's data.
    Out,
    /// STALL in both directions until the next SETUP.
    Stall,
}

/// What the device changes besides endpoint 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    None,
    /// Answer to this address from now on (its status stage is done).
    Address(u8),
    /// The bulk endpoints on (from DATA0, OUT armed) or off.
    Configured(bool),
    /// This bulk endpoint's data toggle back to DATA0.
    ClearHalt(u8),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Step<'a> {
    pub packet: Packet<'a>,
    pub effect: Effect,
}

#[derive(Clone, Copy, Debug)]
enum State {
    Idle,
    /// IN data stage: `rest` still to go, then a zero-length packet if
    /// `zlp`, then the host's status.
    Sending {
        rest: &'static [u8],
        zlp: bool,
    },
    /// The zero-length IN status is out; then take this address, if any.
    Status {
        address: Option<u8>,
    },
    /// Waiting for SET_LINE_CODING's 7 bytes.
    LineCoding,
}

#[derive(Debug)]
pub struct ControlPipe {
    state: State,
    /// The next IN packet's data PID.
    data1: bool,
    configured: bool,
    line_coding: [u8; 7],
}

impl Default for ControlPipe {
    fn default() -> Self {
        Self::new()
    }
}

impl ControlPipe {
    pub const fn new() -> Self {
        Self {
            state: State::Idle,
            data1: true,
            configured: false,
            line_coding: DEFAULT_LINE_CODING,
        }
    }

    /// SET_CONFIGURATION 1 taken (and no bus reset since).
    pub fn configured(&self) -> bool {
        self.configured
    }

    pub fn line_coding(&self) -> [u8; 7] {
        self.line_coding
    }

    /// A bus reset: address 0 (the controller's), not configured.
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// A SETUP packet: it ends whatever transfer was going on.
    pub fn setup(&mut self, bytes: [u8; 8]) -> Step<'_> {
        let setup = Setup::parse(bytes);
        self.data1 = true;
        self.state = State::Idle;
        let effect = match decide(&setup, self.configured) {
            Action::Send(Reply::Static(data)) => {
                // The first packet goes even if empty (a request for 0
                // bytes gets its zero-length packet).
                let (len, zlp) = data_stage(data.len(), setup.length);
                return self.send(&data[..len], zlp);
            }
            Action::Send(Reply::LineCoding) => {
                let (len, _) = data_stage(self.line_coding.len(), setup.length);
                self.state = State::Sending {
                    rest: &[],
                    zlp: false,
                };
                return self.packet_in(len);
            }
            Action::ReceiveLineCoding => {
                self.state = State::LineCoding;
                return step(Packet::Out, Effect::None);
            }
            Action::Stall => return step(Packet::Stall, Effect::None),
            Action::SetAddress(address) => return self.status_in(Some(address), Effect::None),
            Action::SetConfiguration(on) => {
                self.configured = on;
                Effect::Configured(on)
            }
            Action::ClearHalt(endpoint) => Effect::ClearHalt(endpoint),
            Action::Ack => Effect::None,
        };
        self.status_in(None, effect)
    }

    /// The last IN packet was taken by the host.
    pub fn in_done(&mut self) -> Step<'_> {
        match self.state {
            State::Sending { rest, zlp } if !rest.is_empty() => self.send(rest, zlp),
            State::Sending { zlp: true, .. } => self.send(&[], false),
            State::Sending { .. } => {
                // The host's zero-length status.
                self.state = State::Idle;
                step(Packet::Out, Effect::None)
            }
            State::Status { address } => {
                self.state = State::Idle;
                let effect = address.map_or(Effect::None, Effect::Address);
                step(Packet::None, effect)
            }
            State::Idle | State::LineCoding => step(Packet::None, Effect::None),
        }
    }

    /// An OUT packet came: SET_LINE_CODING's data (kept, then the status)
    /// or the status of an IN transfer (nothing to do).
    pub fn out_done(&mut self, data: &[u8]) -> Step<'_> {
        if let State::LineCoding = self.state {
            let n = data.len().min(self.line_coding.len());
            self.line_coding[..n].copy_from_slice(&data[..n]);
            return self.status_in(None, Effect::None);
        }
        step(Packet::None, Effect::None)
    }

    /// Up to a packet of `rest`; the remainder (then a zero-length packet
    /// if `zlp`) after the host takes it.
    fn send(&mut self, rest: &'static [u8], zlp: bool) -> Step<'_> {
        let (now, later) = rest.split_at(rest.len().min(MAX_PACKET));
        self.state = State::Sending { rest: later, zlp };
        step(
            Packet::In {
                data: now,
                data1: self.toggle(),
            },
            Effect::None,
        )
    }

    /// The first `len` bytes of the line coding as one IN packet.
    fn packet_in(&mut self, len: usize) -> Step<'_> {
        let data1 = self.toggle();
        step(
            Packet::In {
                data: &self.line_coding[..len],
                data1,
            },
            Effect::None,
        )
    }

    fn status_in(&mut self, address: Option<u8>, effect: Effect) -> Step<'_> {
        self.state = State::Status { address };
        step(
            Packet::In {
                data: &[],
                data1: self.toggle(),
            },
            effect,
        )
    }

    fn toggle(&mut self) -> bool {
        let data1 = self.data1;
        self.data1 = !data1;
        data1
    }
}

fn step(packet: Packet<'_>, effect: Effect) -> Step<'_> {
    Step { packet, effect }
}

#[cfg(test)]
mod tests;
