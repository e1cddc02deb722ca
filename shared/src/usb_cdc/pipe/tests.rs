//! The control pipe against a strict host: the enumeration Linux does, with
//! every data toggle, packet size, zero-length packet and the moment the
//! address is taken checked, and arbitrary event sequences.

use super::*;
use crate::usb_cdc::descriptors::{self, CONFIGURATION_DESCRIPTOR, DEVICE, PRODUCT};
use proptest::prelude::*;
use std::vec::Vec;

extern crate std;

fn bytes(request_type: u8, request: u8, value: u16, index: u16, length: u16) -> [u8; 8] {
    let [v0, v1] = value.to_le_bytes();
    let [i0, i1] = index.to_le_bytes();
    let [l0, l1] = length.to_le_bytes();
    [request_type, request, v0, v1, i0, i1, l0, l1]
}

/// What a host saw of one control transfer.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// IN data (its packets' sizes too).
    Data(Vec<u8>, Vec<usize>),
    /// No data stage, status done; the effects at SETUP and after the status.
    Done(Effect, Effect),
    Stalled,
}

/// An IN request, as a host runs it: DATA1, DATA0, ... until a short packet
/// or `length` bytes, then the OUT status, which the pipe must have armed.
fn control_in(pipe: &mut ControlPipe, setup: [u8; 8]) -> Outcome {
    let length = usize::from(u16::from_le_bytes([setup[6], setup[7]]));
    let mut step = pipe.setup(setup).packet;
    let (mut data, mut sizes, mut expect_data1) = (Vec::new(), Vec::new(), true);
    loop {
        match step {
            Packet::Stall => return Outcome::Stalled,
            Packet::In {
                data: packet,
                data1,
            } => {
                assert_eq!(data1, expect_data1, "data toggle of packet {}", sizes.len());
                assert!(packet.len() <= 64);
                expect_data1 = !expect_data1;
                data.extend_from_slice(packet);
                sizes.push(packet.len());
                let short = packet.len() < 64;
                step = pipe.in_done().packet;
                if short || data.len() == length {
                    break;
                }
            }
            other => panic!("in the data stage: {other:?}"),
        }
    }
    assert!(data.len() <= length, "more than asked");
    assert_eq!(step, Packet::Out, "status OUT armed after the data stage");
    assert_eq!(pipe.out_done(&[]).packet, Packet::None);
    Outcome::Data(data, sizes)
}

/// A request without data: the IN status on DATA1.
fn control_no_data(pipe: &mut ControlPipe, setup: [u8; 8]) -> Outcome {
    let Step { packet, effect } = pipe.setup(setup);
    match packet {
        Packet::Stall => Outcome::Stalled,
        Packet::In {
            data: &[],
            data1: true,
        } => {
            let after = pipe.in_done();
            assert_eq!(after.packet, Packet::None);
            Outcome::Done(effect, after.effect)
        }
        other => panic!("status stage: {other:?}"),
    }
}

fn data_of(outcome: Outcome) -> Vec<u8> {
    match outcome {
        Outcome::Data(data, _) => data,
        other => panic!("no data: {other:?}"),
    }
}

#[test]
fn linux_enumeration_reads_every_descriptor_and_takes_the_address_after_its_status() {
    let mut pipe = ControlPipe::new();
    // At address 0: the first 64 bytes of the device descriptor, then reset.
    assert_eq!(
        data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0100, 0, 64))),
        DEVICE
    );
    pipe.reset();
    assert_eq!(
        control_no_data(&mut pipe, bytes(0, 5, 9, 0, 0)),
        Outcome::Done(Effect::None, Effect::Address(9)),
        "the address only after the status stage"
    );
    assert_eq!(
        data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0100, 0, 18))),
        DEVICE
    );
    let head = data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0200, 0, 9)));
    assert_eq!(head, CONFIGURATION_DESCRIPTOR[..9]);
    let total = u16::from_le_bytes([head[2], head[3]]);
    assert_eq!(
        control_in(&mut pipe, bytes(0x80, 6, 0x0200, 0, total)),
        Outcome::Data(CONFIGURATION_DESCRIPTOR.to_vec(), std::vec![64, 3])
    );
    let languages = data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0300, 0, 255)));
    let english = u16::from_le_bytes([languages[2], languages[3]]);
    assert_eq!(
        data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0302, english, 255))),
        PRODUCT
    );
    assert!(!pipe.configured());
    assert_eq!(
        control_no_data(&mut pipe, bytes(0, 9, 1, 0, 0)),
        Outcome::Done(Effect::Configured(true), Effect::None)
    );
    assert!(pipe.configured());
    assert_eq!(data_of(control_in(&mut pipe, bytes(0x80, 8, 0, 0, 1))), [1]);
}

#[test]
fn cdc_line_coding_is_kept_echoed_and_forgotten_at_a_bus_reset() {
    let mut pipe = ControlPipe::new();
    let coding = [0x00, 0xc2, 0x01, 0x00, 0, 0, 8]; // 115200 8N1
    let Step { packet, .. } = pipe.setup(bytes(0x21, 0x20, 0, 0, 7));
    assert_eq!(packet, Packet::Out);
    assert_eq!(
        pipe.out_done(&coding).packet,
        Packet::In {
            data: &[],
            data1: true
        },
        "status IN on DATA1 after the OUT data"
    );
    assert_eq!(pipe.in_done().packet, Packet::None);
    assert_eq!(
        data_of(control_in(&mut pipe, bytes(0xa1, 0x21, 0, 0, 7))),
        coding
    );
    assert_eq!(
        control_no_data(&mut pipe, bytes(0x21, 0x22, 3, 0, 0)),
        Outcome::Done(Effect::None, Effect::None)
    );
    pipe.reset();
    assert_eq!(pipe.line_coding(), DEFAULT_LINE_CODING);
}

#[test]
fn a_stall_lasts_until_the_next_setup_and_an_aborted_answer_is_dropped() {
    let mut pipe = ControlPipe::new();
    assert_eq!(
        control_in(&mut pipe, bytes(0xc0, 0x33, 0, 0, 4)),
        Outcome::Stalled
    );
    assert_eq!(
        control_in(&mut pipe, bytes(0x80, 0, 0, 0, 2)),
        Outcome::Data(std::vec![0, 0], std::vec![2])
    );
    // The host gives up after the first packet of the configuration.
    let first = pipe.setup(bytes(0x80, 6, 0x0200, 0, 255)).packet;
    assert!(matches!(first, Packet::In { data, data1: true } if data.len() == 64));
    assert_eq!(
        data_of(control_in(&mut pipe, bytes(0x80, 6, 0x0100, 0, 18))),
        DEVICE
    );
    assert_eq!(
        pipe.in_done().packet,
        Packet::None,
        "nothing left of the old answer"
    );
}

#[test]
fn a_whole_packet_answer_shorter_than_asked_ends_with_a_zero_length_packet() {
    static SIXTY_FOUR: [u8; 64] = [7; 64];
    let mut pipe = ControlPipe::new();
    let first = pipe.send(&SIXTY_FOUR, true).packet;
    assert_eq!(
        first,
        Packet::In {
            data: &SIXTY_FOUR,
            data1: true
        }
    );
    assert_eq!(
        pipe.in_done().packet,
        Packet::In {
            data: &[],
            data1: false
        }
    );
    assert_eq!(pipe.in_done().packet, Packet::Out);
}

#[test]
fn set_configuration_0_and_clear_halt_are_effects_at_the_setup() {
    let mut pipe = ControlPipe::new();
    control_no_data(&mut pipe, bytes(0, 9, 1, 0, 0));
    assert_eq!(
        control_no_data(
            &mut pipe,
            bytes(0x02, 1, 0, u16::from(descriptors::DATA_EP_IN), 0)
        ),
        Outcome::Done(Effect::ClearHalt(descriptors::DATA_EP_IN), Effect::None)
    );
    assert_eq!(
        control_no_data(&mut pipe, bytes(0, 9, 0, 0, 0)),
        Outcome::Done(Effect::Configured(false), Effect::None)
    );
    assert!(!pipe.configured());
}

#[derive(Clone, Debug)]
enum Event {
    Setup([u8; 8]),
    InDone,
    OutDone(Vec<u8>),
    Reset,
}

fn event() -> impl Strategy<Value = Event> {
    prop_oneof![
        any::<[u8; 8]>().prop_map(Event::Setup),
        // Real requests more often than noise.
        (0usize..4, 0u16..300).prop_map(|(i, len)| {
            let [t, r, v] = [
                [0x80, 6, 0x0200],
                [0x80, 6, 0x0302],
                [0x21, 0x20, 0],
                [0, 5, 3],
            ][i];
            Event::Setup(bytes(t as u8, r as u8, v, 0, len))
        }),
        Just(Event::InDone),
        proptest::collection::vec(any::<u8>(), 0..80).prop_map(Event::OutDone),
        Just(Event::Reset),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// Whatever a host (or a broken one) does: no panic, no packet over 64
    /// bytes, every answer to a SETUP on DATA1, an address only when an
    /// IN packet is taken, and a stall never together with an effect.
    #[test]
    fn any_event_sequence_keeps_the_pipe_within_the_rules(events in proptest::collection::vec(event(), 0..40)) {
        let mut pipe = ControlPipe::new();
        for e in events {
            let (step, after_setup, in_done) = match &e {
                Event::Setup(b) => (pipe.setup(*b), true, false),
                Event::InDone => (pipe.in_done(), false, true),
                Event::OutDone(d) => (pipe.out_done(d), false, false),
                Event::Reset => { pipe.reset(); continue; }
            };
            if let Packet::In { data, data1 } = step.packet {
                prop_assert!(data.len() <= 64);
                if after_setup { prop_assert!(data1); }
            }
            if let Effect::Address(a) = step.effect {
                prop_assert!(in_done && a <= 127);
            }
            if step.packet == Packet::Stall { prop_assert_eq!(step.effect, Effect::None); }
        }
    }
}
