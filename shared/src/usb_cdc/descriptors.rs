//! The port's descriptors as const byte arrays: one full-speed device, one
//! configuration, the CDC communication interface (ACM) with its
//! notification endpoint and the data interface with one bulk OUT and one
//! bulk IN endpoint, and the strings. The device never changes them, so they
//! are data, not code that writes them.
//!
//! References: USB 2.0 specification, 9.6 (standard descriptors); USB CDC
//! 1.2, 5.2.3 (functional descriptors); PSTN 1.2, 5.3 (ACM).

use crate::board;

/// Packet size of every endpoint with data (control and bulk): the largest
/// full-speed bulk packet.
pub const MAX_PACKET: usize = 64;
/// The CDC notification endpoint (interrupt IN 1): declared, as ACM asks,
/// never written (the port has no line state to report).
pub const NOTIFY_EP_IN: u8 = 0x81;
/// Bytes from the host (bulk OUT 1).
pub const DATA_EP_OUT: u8 = 0x01;
/// Bytes to the host (bulk IN 2).
pub const DATA_EP_IN: u8 = 0x82;
/// The one configuration's `bConfigurationValue`.
pub const CONFIGURATION: u8 = 1;
/// The CDC communication interface (class requests go to it).
pub const COMM_INTERFACE: u8 = 0;

const CDC_CLASS: u8 = 0x02;
const ACM_SUBCLASS: u8 = 0x02;
const CDC_DATA_CLASS: u8 = 0x0a;
const CS_INTERFACE: u8 = 0x24;

/// bcdUSB 2.00: a full-speed device without a BOS descriptor.
#[rustfmt::skip]
pub const DEVICE: [u8; 18] = {
    let [vid_lo, vid_hi] = board::USB_VID.to_le_bytes();
    let [pid_lo, pid_hi] = board::USB_PID.to_le_bytes();
    [
        18, 1, // bLength, DEVICE
        0x00, 0x02, // bcdUSB 2.00
        CDC_CLASS, 0, 0, // the device is a CDC device; no IAD needed
        MAX_PACKET as u8, // bMaxPacketSize0
        vid_lo, vid_hi, pid_lo, pid_hi, //
        0x00, 0x01, // bcdDevice 1.00
        1, 2, 3, // iManufacturer, iProduct, iSerialNumber
        1, // bNumConfigurations
    ]
};

const CONFIGURATION_LEN: usize = 67;

/// The configuration with its interfaces, functional descriptors and
/// endpoints, in the order a host reads them.
#[rustfmt::skip]
pub const CONFIGURATION_DESCRIPTOR: [u8; CONFIGURATION_LEN] = [
    // configuration: 2 interfaces, bus-powered, 100 mA
    9, 2, CONFIGURATION_LEN as u8, 0, 2, CONFIGURATION, 0, 0x80, 50,
    // interface 0: CDC communication, ACM, no protocol, 1 endpoint
    9, 4, COMM_INTERFACE, 0, 1, CDC_CLASS, ACM_SUBCLASS, 0, 0,
    // header: CDC 1.10
    5, CS_INTERFACE, 0x00, 0x10, 0x01,
    // call management: none, data interface 1
    5, CS_INTERFACE, 0x01, 0x00, 1,
    // ACM: line coding and control line state requests supported
    4, CS_INTERFACE, 0x02, 0x02,
    // union: interface 0 controls interface 1
    5, CS_INTERFACE, 0x06, COMM_INTERFACE, 1,
    // notification endpoint: interrupt IN, 8 bytes, every 255 ms
    7, 5, NOTIFY_EP_IN, 0x03, 8, 0, 255,
    // interface 1: CDC data, 2 endpoints
    9, 4, 1, 0, 2, CDC_DATA_CLASS, 0, 0, 0,
    // bulk OUT and bulk IN, 64 bytes
    7, 5, DATA_EP_OUT, 0x02, MAX_PACKET as u8, 0, 0,
    7, 5, DATA_EP_IN, 0x02, MAX_PACKET as u8, 0, 0,
];

/// String 0: the one language, US English.
pub const LANGUAGES: [u8; 4] = [4, 3, 0x09, 0x04];
pub const MANUFACTURER: [u8; 2 + 2 * 7] = string("swimbot");
pub const PRODUCT: [u8; 2 + 2 * board::USB_PRODUCT.len()] = string(board::USB_PRODUCT);
pub const SERIAL_NUMBER: [u8; 4] = string("1");

/// The string descriptor of `index` (0 = the language list), if any.
pub fn string_descriptor(index: u8) -> Option<&'static [u8]> {
    match index {
        0 => Some(&LANGUAGES),
        1 => Some(&MANUFACTURER),
        2 => Some(&PRODUCT),
        3 => Some(&SERIAL_NUMBER),
        _ => None,
    }
}

/// An ASCII string as a string descriptor (UTF-16LE); a longer or
/// non-ASCII text fails the build.
const fn string<const N: usize>(text: &str) -> [u8; N] {
    let bytes = text.as_bytes();
    assert!(N == 2 + 2 * bytes.len() && N <= 255, "descriptor length");
    let mut out = [0u8; N];
    out[0] = N as u8;
    out[1] = 3;
    let mut i = 0;
    while i < bytes.len() {
        assert!(bytes[i].is_ascii(), "ASCII only");
        out[2 + 2 * i] = bytes[i];
        i += 1;
    }
    out
}
