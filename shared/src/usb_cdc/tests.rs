//! The descriptors parsed back as a host reads them, and the request
//! decoder against the requests Linux, Windows and rp2040js's CDC host send.

use super::control::{data_stage, decide, Action, Reply, Setup};
use super::descriptors::*;
use crate::board;
use std::vec::Vec;

extern crate std;

/// The descriptors of a configuration, split by their own length bytes.
fn split(mut bytes: &[u8]) -> Vec<&[u8]> {
    let mut out = Vec::new();
    while !bytes.is_empty() {
        let len = usize::from(bytes[0]);
        assert!(len >= 2 && len <= bytes.len(), "descriptor length {len}");
        out.push(&bytes[..len]);
        bytes = &bytes[len..];
    }
    out
}

fn setup(request_type: u8, request: u8, value: u16, index: u16, length: u16) -> Setup {
    let mut b = [0u8; 8];
    b[0] = request_type;
    b[1] = request;
    b[2..4].copy_from_slice(&value.to_le_bytes());
    b[4..6].copy_from_slice(&index.to_le_bytes());
    b[6..8].copy_from_slice(&length.to_le_bytes());
    Setup::parse(b)
}

#[test]
fn device_descriptor_names_the_board_ids_and_64_byte_control_packets() {
    assert_eq!(DEVICE[0] as usize, DEVICE.len());
    assert_eq!(DEVICE[1], 1);
    assert_eq!(DEVICE[7], 64);
    assert_eq!(u16::from_le_bytes([DEVICE[8], DEVICE[9]]), board::USB_VID);
    assert_eq!(u16::from_le_bytes([DEVICE[10], DEVICE[11]]), board::USB_PID);
    assert_eq!(DEVICE[17], 1, "one configuration");
    for index in &DEVICE[14..17] {
        assert!(string_descriptor(*index).is_some(), "string {index} exists");
    }
}

#[test]
fn configuration_parses_into_acm_and_data_interfaces_with_their_endpoints() {
    let parts = split(&CONFIGURATION_DESCRIPTOR);
    let total = u16::from_le_bytes([CONFIGURATION_DESCRIPTOR[2], CONFIGURATION_DESCRIPTOR[3]]);
    assert_eq!(usize::from(total), CONFIGURATION_DESCRIPTOR.len());
    assert_eq!(CONFIGURATION_DESCRIPTOR[5], CONFIGURATION);
    let interfaces: Vec<_> = parts.iter().filter(|d| d[1] == 4).collect();
    assert_eq!(interfaces.len(), 2);
    assert_eq!(usize::from(CONFIGURATION_DESCRIPTOR[4]), interfaces.len());
    assert_eq!(
        (interfaces[0][5], interfaces[0][6]),
        (0x02, 0x02),
        "CDC ACM"
    );
    assert_eq!(interfaces[1][5], 0x0a, "CDC data");
    // Each interface declares as many endpoints as follow it.
    let mut counts = [0u8; 2];
    let mut current = None;
    for d in &parts {
        match d[1] {
            4 => current = Some(usize::from(d[2])),
            5 => counts[current.expect("endpoint after an interface")] += 1,
            _ => {}
        }
    }
    assert_eq!(counts, [interfaces[0][4], interfaces[1][4]]);
    let endpoints: Vec<(u8, u8, u16)> = parts
        .iter()
        .filter(|d| d[1] == 5)
        .map(|d| (d[2], d[3], u16::from_le_bytes([d[4], d[5]])))
        .collect();
    assert_eq!(
        endpoints,
        [
            (NOTIFY_EP_IN, 3, 8),
            (DATA_EP_OUT, 2, 64),
            (DATA_EP_IN, 2, 64)
        ]
    );
    // The union names interface 0 as controlling interface 1.
    assert!(parts.iter().any(|d| d == &[5, 0x24, 0x06, 0, 1]));
}

#[test]
fn strings_are_utf16_of_the_ascii_names() {
    assert_eq!(string_descriptor(0), Some(&[4u8, 3, 0x09, 0x04][..]));
    let product = string_descriptor(2).unwrap();
    assert_eq!(usize::from(product[0]), product.len());
    let text: Vec<u8> = product[2..]
        .chunks(2)
        .map(|c| {
            assert_eq!(c[1], 0);
            c[0]
        })
        .collect();
    assert_eq!(text, board::USB_PRODUCT.as_bytes());
    assert_eq!(string_descriptor(4), None);
}

#[test]
fn enumeration_requests_get_their_descriptors() {
    let get =
        |kind: u16, index: u16, len| decide(&setup(0x80, 6, kind << 8 | index, 0, len), false);
    assert_eq!(get(1, 0, 64), Action::Send(Reply::Static(&DEVICE)));
    assert_eq!(
        get(2, 0, 9),
        Action::Send(Reply::Static(&CONFIGURATION_DESCRIPTOR))
    );
    assert_eq!(get(3, 2, 255), Action::Send(Reply::Static(&PRODUCT)));
    assert_eq!(get(3, 9, 255), Action::Stall, "no such string");
    assert_eq!(
        get(6, 0, 10),
        Action::Stall,
        "device qualifier: full speed only"
    );
    assert_eq!(get(15, 0, 5), Action::Stall, "BOS: bcdUSB 2.00");
    assert_eq!(get(2, 1, 9), Action::Stall, "one configuration");
}

#[test]
fn address_and_configuration_are_taken_and_reported() {
    assert_eq!(decide(&setup(0, 5, 1, 0, 0), false), Action::SetAddress(1));
    assert_eq!(decide(&setup(0, 5, 200, 0, 0), false), Action::Stall);
    assert_eq!(
        decide(&setup(0, 9, 1, 0, 0), false),
        Action::SetConfiguration(true)
    );
    assert_eq!(
        decide(&setup(0, 9, 0, 0, 0), true),
        Action::SetConfiguration(false)
    );
    assert_eq!(decide(&setup(0, 9, 2, 0, 0), false), Action::Stall);
    let get_config = |configured| decide(&setup(0x80, 8, 0, 0, 1), configured);
    assert_eq!(get_config(true), Action::Send(Reply::Static(&[1])));
    assert_eq!(get_config(false), Action::Send(Reply::Static(&[0])));
    assert_eq!(
        decide(&setup(0x80, 0, 0, 0, 2), true),
        Action::Send(Reply::Static(&[0, 0]))
    );
}

#[test]
fn acm_requests_of_linux_windows_and_rp2040js_are_accepted() {
    // Linux/Windows: to interface 0; rp2040js: to the device.
    assert_eq!(
        decide(&setup(0x21, 0x20, 0, 0, 7), true),
        Action::ReceiveLineCoding
    );
    assert_eq!(
        decide(&setup(0xa1, 0x21, 0, 0, 7), true),
        Action::Send(Reply::LineCoding)
    );
    assert_eq!(decide(&setup(0x21, 0x22, 3, 0, 0), true), Action::Ack);
    assert_eq!(decide(&setup(0x20, 0x22, 3, 0, 0), true), Action::Ack);
    assert_eq!(
        decide(&setup(0x21, 0x20, 0, 0, 6), true),
        Action::Stall,
        "short line coding"
    );
    assert_eq!(
        decide(&setup(0x21, 0x23, 0, 0, 0), true),
        Action::Stall,
        "SEND_BREAK"
    );
}

#[test]
fn clear_halt_only_for_the_data_endpoints_and_the_rest_stalls() {
    assert_eq!(
        decide(&setup(0x02, 1, 0, 0x82, 0), true),
        Action::ClearHalt(0x82)
    );
    assert_eq!(
        decide(&setup(0x02, 1, 0, 0x01, 0), true),
        Action::ClearHalt(0x01)
    );
    assert_eq!(decide(&setup(0x02, 1, 0, 0x83, 0), true), Action::Stall);
    assert_eq!(
        decide(&setup(0x02, 1, 0, 0x82, 0), false),
        Action::Stall,
        "not configured: no data endpoints yet"
    );
    assert_eq!(
        decide(&setup(0x00, 1, 1, 0, 0), true),
        Action::Stall,
        "remote wake-up"
    );
    assert_eq!(
        decide(&setup(0x00, 3, 1, 0, 0), true),
        Action::Stall,
        "SET_FEATURE"
    );
    assert_eq!(
        decide(&setup(0x40, 1, 0, 0, 0), true),
        Action::Stall,
        "vendor"
    );
    assert_eq!(
        decide(&setup(0x00, 5, 1, 0, 4), true),
        Action::Stall,
        "data on SET_ADDRESS"
    );
}

#[test]
fn every_setup_packet_decodes_without_panic_and_consistently() {
    // Exhaustive over the request byte and type, a spread of the rest.
    for request_type in 0..=255u8 {
        for request in 0..=255u8 {
            for &(value, index, length) in
                &[(0, 0, 0), (0x0100, 0, 64), (0x0302, 0, 255), (1, 0x82, 7)]
            {
                let s = setup(request_type, request, value, index, length);
                match decide(&s, request_type & 1 == 0) {
                    Action::Send(_) => {
                        assert!(request_type & 0x80 != 0, "IN data only to IN requests")
                    }
                    Action::Stall => {}
                    _ => assert!(request_type & 0x80 == 0, "OUT requests only: {s:?}"),
                }
            }
        }
    }
}

#[test]
fn data_stage_is_cut_to_the_request_and_ends_short_or_with_a_zero_length_packet() {
    assert_eq!(data_stage(67, 9), (9, false), "first configuration read");
    assert_eq!(
        data_stage(67, 255),
        (67, false),
        "ends with a 3-byte packet"
    );
    assert_eq!(
        data_stage(64, 255),
        (64, true),
        "a whole packet, host wants more"
    );
    assert_eq!(data_stage(64, 64), (64, false), "exactly what was asked");
    assert_eq!(data_stage(128, 4096), (128, true));
    assert_eq!(data_stage(18, 0), (0, false));
}
