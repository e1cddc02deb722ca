//! What the port does with a control request on endpoint 0: the eight
//! bytes of a SETUP packet decoded, and one [`Action`] for the controller
//! code to carry out. Standard requests: GET_DESCRIPTOR, SET_ADDRESS,
//! SET/GET_CONFIGURATION, GET_STATUS, GET/SET_INTERFACE (alternate setting 0
//! only), CLEAR_FEATURE(ENDPOINT_HALT); CDC's SET_LINE_CODING,
//! GET_LINE_CODING, SET_CONTROL_LINE_STATE. Everything else is stalled.
//!
//! The line coding is kept and echoed (a host's terminal reads it back) but
//! changes nothing: the port is a USB pipe, not a UART.
//!
//! References: USB 2.0 specification, 9.3 (the SETUP data) and 9.4 (the
//! standard requests); PSTN 1.2, 6.3.10-6.3.12 (the ACM requests).

use super::descriptors::{self, MAX_PACKET};

/// A SETUP packet's fields (USB 2.0, table 9-2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setup {
    pub request_type: u8,
    pub request: u8,
    pub value: u16,
    pub index: u16,
    pub length: u16,
}

impl Setup {
    /// The fields of the packet's eight little-endian bytes.
    pub fn parse(bytes: [u8; 8]) -> Self {
        Self {
            request_type: bytes[0],
            request: bytes[1],
            value: u16::from_le_bytes([bytes[2], bytes[3]]),
            index: u16::from_le_bytes([bytes[4], bytes[5]]),
            length: u16::from_le_bytes([bytes[6], bytes[7]]),
        }
    }
}

/// Where an IN data stage's bytes come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reply {
    Static(&'static [u8]),
    /// The line coding the host set last (7 bytes, [`DEFAULT_LINE_CODING`]
    /// until then).
    LineCoding,
}

/// What the device does with a request.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// An IN data stage (see [`data_stage`] for how much goes), then the
    /// host's zero-length status.
    Send(Reply),
    /// A zero-length IN status, after which the device takes the address
    /// (USB 2.0, 9.4.6: the status stage still goes to address 0).
    SetAddress(u8),
    /// A zero-length IN status; configured or not (value 0). Either resets
    /// the bulk endpoints' data toggles to DATA0.
    SetConfiguration(bool),
    /// A zero-length IN status; the endpoint's data toggle back to DATA0.
    ClearHalt(u8),
    /// A zero-length IN status, nothing else.
    Ack,
    /// An OUT data stage with the 7 bytes of the line coding, then a
    /// zero-length IN status.
    ReceiveLineCoding,
    /// STALL on endpoint 0 until the next SETUP.
    Stall,
}

/// 9600 baud, 1 stop bit, no parity, 8 data bits (PSTN 1.2, table 17).
pub const DEFAULT_LINE_CODING: [u8; 7] = [0x80, 0x25, 0, 0, 0, 0, 8];
pub const LINE_CODING_LEN: u16 = 7;

const GET_STATUS: u8 = 0x00;
const CLEAR_FEATURE: u8 = 0x01;
const SET_ADDRESS: u8 = 0x05;
const GET_DESCRIPTOR: u8 = 0x06;
const GET_CONFIGURATION: u8 = 0x08;
const SET_CONFIGURATION: u8 = 0x09;
const GET_INTERFACE: u8 = 0x0a;
const SET_INTERFACE: u8 = 0x0b;
const SET_LINE_CODING: u8 = 0x20;
const GET_LINE_CODING: u8 = 0x21;
const SET_CONTROL_LINE_STATE: u8 = 0x22;

const DEVICE_TO_HOST: u8 = 0x80;
const TYPE_MASK: u8 = 0x60;
const TYPE_STANDARD: u8 = 0x00;
const TYPE_CLASS: u8 = 0x20;
const RECIPIENT_ENDPOINT: u8 = 0x02;
const ENDPOINT_HALT: u16 = 0;

/// The action for `setup` on a device that is `configured` or not.
pub fn decide(setup: &Setup, configured: bool) -> Action {
    let into_device = setup.request_type & DEVICE_TO_HOST == 0;
    match setup.request_type & TYPE_MASK {
        TYPE_STANDARD if into_device => standard_out(setup, configured),
        TYPE_STANDARD => standard_in(setup, configured),
        TYPE_CLASS => class(setup, into_device),
        _ => Action::Stall,
    }
}

/// Standard requests without a data stage. The data endpoints exist only
/// in the configured state (USB 2.0, 9.4.1).
fn standard_out(setup: &Setup, configured: bool) -> Action {
    if setup.length != 0 {
        return Action::Stall;
    }
    match setup.request {
        SET_ADDRESS if setup.value <= 127 => Action::SetAddress(setup.value as u8),
        SET_CONFIGURATION if setup.value == 0 => Action::SetConfiguration(false),
        SET_CONFIGURATION if setup.value == u16::from(descriptors::CONFIGURATION) => {
            Action::SetConfiguration(true)
        }
        SET_INTERFACE if configured && setup.value == 0 && setup.index <= 1 => Action::Ack,
        CLEAR_FEATURE
            if configured
                && setup.request_type == RECIPIENT_ENDPOINT
                && setup.value == ENDPOINT_HALT
                && is_data_endpoint(setup.index) =>
        {
            Action::ClearHalt(setup.index as u8)
        }
        _ => Action::Stall,
    }
}

fn is_data_endpoint(index: u16) -> bool {
    [descriptors::DATA_EP_OUT, descriptors::DATA_EP_IN]
        .iter()
        .any(|&ep| u16::from(ep) == index)
}

/// Standard requests that answer with data.
fn standard_in(setup: &Setup, configured: bool) -> Action {
    const ZERO_STATUS: [u8; 2] = [0, 0];
    const ZERO: [u8; 1] = [0];
    const ONE: [u8; 1] = [descriptors::CONFIGURATION];
    let data: Option<&'static [u8]> = match setup.request {
        GET_DESCRIPTOR => descriptor(setup.value),
        // Bus-powered, no remote wake-up; no endpoint is ever halted.
        GET_STATUS => Some(&ZERO_STATUS),
        GET_CONFIGURATION if configured => Some(&ONE),
        GET_CONFIGURATION => Some(&ZERO),
        GET_INTERFACE if configured && setup.index <= 1 => Some(&ZERO),
        _ => None,
    };
    data.map_or(Action::Stall, |d| Action::Send(Reply::Static(d)))
}

/// A GET_DESCRIPTOR's descriptor: `value` is type (high byte) and index.
fn descriptor(value: u16) -> Option<&'static [u8]> {
    let [index, kind] = value.to_le_bytes();
    match kind {
        1 if index == 0 => Some(&descriptors::DEVICE),
        2 if index == 0 => Some(&descriptors::CONFIGURATION_DESCRIPTOR),
        3 => descriptors::string_descriptor(index),
        // A full-speed-only device has no device qualifier (USB 2.0,
        // 9.6.2) and, at bcdUSB 2.00, no BOS: both are stalled.
        _ => None,
    }
}

/// CDC's ACM requests. The recipient is not checked: rp2040js's CDC host
/// sends SET_CONTROL_LINE_STATE to the device instead of the interface.
fn class(setup: &Setup, into_device: bool) -> Action {
    match (setup.request, into_device) {
        (SET_LINE_CODING, true) if setup.length == LINE_CODING_LEN => Action::ReceiveLineCoding,
        (SET_CONTROL_LINE_STATE, true) if setup.length == 0 => Action::Ack,
        (GET_LINE_CODING, false) => Action::Send(Reply::LineCoding),
        _ => Action::Stall,
    }
}

/// How an IN data stage of `available` bytes goes out when the host asked
/// for `requested`: the bytes sent (at most `requested`), and whether a
/// zero-length packet must end it (a short answer that is a whole number
/// of packets, USB 2.0, 8.5.3.2).
pub fn data_stage(available: usize, requested: u16) -> (usize, bool) {
    let len = available.min(usize::from(requested));
    let zlp = len < usize::from(requested) && len % MAX_PACKET == 0 && len > 0;
    (len, zlp)
}
