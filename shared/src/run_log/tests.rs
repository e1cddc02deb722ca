//! The run log on the host: the record and image round trips, `decode`'s
//! totality and its typed errors, the readout requests, and the recorder
//! over a whole 10-minute run of the real main-loop pass.
use super::image::{FLAG_CLOSED, FLAG_RECOVERED, MAGIC};
use super::readout::{info_line, Line, LINE_MAX, MAX_REQUEST};
use super::record::RecordError;
use super::*;
use crate::battery::BatteryStatus;
use crate::board;
use crate::command::Command;
use crate::controller::{Controller, MotorState};
use crate::main_loop::{HallEdge, MainLoop, MainLoopConfig, MotorControl};
use crate::nec::{for_each_edge, frame_pulses_us, Level};
use crate::rate::{RateEvent, RateOutput, SensorFault};
use proptest::prelude::*;
use std::vec::Vec;

extern crate std;

fn header() -> Header {
    Header {
        sample_period_ms: 100,
        record_count: 0,
        dropped_records: 3,
        foreign_frames: 7,
        paired_address: Some(0x5a),
        flags: FLAG_CLOSED,
    }
}

fn record(i: u32) -> Record {
    Record {
        t_ms: 1_000 + 100 * i,
        set_point_mhz: Some(1_000),
        rate_mhz: (i > 2).then_some(990 + (i % 20) as u16),
        duty_per_10k: (3_000 + i % 500) as u16,
        cell_mv: 4_100 - (i % 300) as u16,
        events: if i == 0 {
            Events::STARTED
        } else {
            Events::NONE
        },
        fault: None,
        foreign_frames: (i % 3) as u8,
    }
}

fn image(records: &[Record]) -> Vec<u8> {
    let mut out = std::vec![0u8; HEADER_LEN + RECORD_LEN * records.len()];
    let n = encode(&header(), records, &mut out).unwrap();
    assert_eq!(n, out.len());
    out
}

#[test]
fn round_trip_and_layout() {
    let records: Vec<Record> = (0..50).map(record).collect();
    let bytes = image(&records);
    assert_eq!(&bytes[..4], &MAGIC);
    assert_eq!(u32::from_le_bytes(bytes[12..16].try_into().unwrap()), 50);
    assert_eq!(u16::from_le_bytes([bytes[24], bytes[25]]), 0x5a);
    let log = decode(&bytes).unwrap();
    assert_eq!(log.header.record_count, 50);
    assert_eq!(log.header.paired_address, Some(0x5a));
    assert_eq!(log.records().collect::<Vec<_>>(), records);
}

#[test]
fn crc_is_zlibs_crc32() {
    // CRC-32/ISO-HDLC's check value (the catalogue's "123456789").
    let crc = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);
    assert_eq!(crc.checksum(b"123456789"), 0xcbf4_3926);
    // The image's CRC is over header bytes 0-27 then the records.
    let bytes = image(&[record(1)]);
    let stored = u32::from_le_bytes(bytes[28..32].try_into().unwrap());
    let mut covered = bytes[..28].to_vec();
    covered.extend_from_slice(&bytes[32..]);
    assert_eq!(stored, crc.checksum(&covered));
}

#[test]
fn typed_errors() {
    let good = image(&[record(0), record(1)]);
    assert_eq!(decode(&good[..10]), Err(DecodeError::TooShort { len: 10 }));
    let mut bad = good.clone();
    bad[0] = b'X';
    assert!(matches!(decode(&bad), Err(DecodeError::BadMagic(_))));
    assert!(matches!(
        decode(&good[..good.len() - 1]),
        Err(DecodeError::Truncated {
            expected: 64,
            got: 63
        })
    ));
    let mut long = good.clone();
    long.push(0);
    assert!(matches!(
        decode(&long),
        Err(DecodeError::TrailingBytes { .. })
    ));
    let mut flipped = good.clone();
    flipped[40] ^= 1;
    assert!(matches!(decode(&flipped), Err(DecodeError::Crc { .. })));
    // A record that is malformed under a correct CRC (a bug, not damage).
    let mut r = record(1).to_bytes();
    r[14] = 9;
    assert_eq!(Record::from_bytes(&r), Err(RecordError::FaultCode(9)));
    let mut with_bad = good[..HEADER_LEN].to_vec();
    with_bad.extend_from_slice(&r);
    let h = Header {
        record_count: 1,
        ..header()
    };
    let mut d = ImageDigest::new(&h);
    d.update(&r);
    with_bad[..HEADER_LEN].copy_from_slice(&h.to_bytes(d.finalize()));
    assert_eq!(
        decode(&with_bad),
        Err(DecodeError::Record {
            index: 0,
            error: RecordError::FaultCode(9)
        })
    );
}

#[test]
fn an_empty_log_is_a_valid_image() {
    let bytes = image(&[]);
    assert_eq!(bytes.len(), HEADER_LEN);
    assert!(decode(&bytes).unwrap().is_empty());
    let mut small = [0u8; 8];
    assert_eq!(
        encode(&header(), &[record(0)], &mut small),
        Err(EncodeError::BufferTooSmall { needed: 48, got: 8 })
    );
}

#[test]
fn readout_requests() {
    let mut r = RequestReader::new();
    let mut feed = |s: &[u8]| s.iter().filter_map(|&b| r.push(b)).collect::<Vec<_>>();
    assert_eq!(feed(b"LOG\n"), [Request::Log]);
    assert_eq!(feed(b"INFO\r\n"), [Request::Info]);
    assert_eq!(feed(b"log\nLOGX\n\n"), [Request::Unknown; 3]);
    // A line longer than the reader keeps is unknown, even if it ends in LOG.
    let mut long = std::vec![b'x'; MAX_REQUEST * 4];
    long.extend_from_slice(b"LOG\nLOG\n");
    assert_eq!(feed(&long), [Request::Unknown, Request::Log]);
    let h = Header {
        record_count: u32::MAX,
        dropped_records: u32::MAX,
        foreign_frames: u32::MAX,
        sample_period_ms: u16::MAX,
        ..header()
    };
    let line = std::string::String::from_utf8(info_line(&h, None).to_vec()).unwrap();
    assert_eq!(
        line,
        "swimbot-log v2 records=4294967295 period_ms=65535 dropped=4294967295 \
         foreign=4294967295 paired=0x5a log=this this_run=partly-dropped\n"
    );
    // The longest words go together (an earlier power-up's records are
    // never this one's, kept or partly).
    assert_eq!(line.len(), 133);
    assert!(line.len() <= LINE_MAX, "the longest line fits");
    let earlier = info_line(
        &Header {
            flags: FLAG_CLOSED | FLAG_RECOVERED,
            ..h
        },
        None,
    );
    assert!(earlier.ends_with(b"paired=0x5a log=earlier this_run=dropped\n"));
    let unpaired = info_line(
        &Header {
            paired_address: Some(0x0b),
            ..header()
        },
        None,
    );
    // No record and 3 dropped: this power-up's run was lost, nothing to send.
    assert_eq!(
        unpaired.as_slice(),
        b"swimbot-log v2 records=0 period_ms=100 dropped=3 foreign=7 paired=0x0b \
          log=none this_run=dropped\n"
    );
    let none = info_line(
        &Header {
            paired_address: None,
            ..header()
        },
        None,
    );
    assert!(none.ends_with(b"paired=none log=none this_run=dropped\n"));
}

/// A version-1 file still reads; of an earlier power-up's log it cannot
/// say whether the run of the power-up that read it out was dropped (its
/// dropped count was 0 there by definition).
#[test]
fn version_1_images_decode_and_say_what_they_cannot_tell() {
    let records: Vec<Record> = (0..4).map(record).collect();
    let v1 = |flags: u16| {
        let mut bytes = image(&records);
        bytes[4..6].copy_from_slice(&1u16.to_le_bytes());
        bytes[26..28].copy_from_slice(&flags.to_le_bytes());
        let crc = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);
        let mut d = crc.digest();
        d.update(&bytes[..28]);
        d.update(&bytes[HEADER_LEN..]);
        let sum = d.finalize();
        bytes[28..32].copy_from_slice(&sum.to_le_bytes());
        bytes
    };
    let own = v1(FLAG_CLOSED);
    let log = decode(&own).unwrap();
    assert_eq!(log.version, 1);
    assert_eq!(log.this_run(), Some(ThisRun::PartlyDropped { dropped: 3 }));
    let earlier = v1(FLAG_CLOSED | FLAG_RECOVERED);
    assert_eq!(decode(&earlier).unwrap().this_run(), None);
    // Version 2, the same header: this power-up dropped 3 and kept none.
    let mut bytes = std::vec![0u8; HEADER_LEN + RECORD_LEN * 4];
    let h = Header {
        flags: FLAG_CLOSED | FLAG_RECOVERED,
        ..header()
    };
    encode(&h, &records, &mut bytes).unwrap();
    let log = decode(&bytes).unwrap();
    assert_eq!(log.version, 2);
    assert_eq!(log.this_run(), Some(ThisRun::Dropped { dropped: 3 }));
    assert_eq!(LogOf::of(&log.header), LogOf::EarlierPowerUp);
    bytes[4] = 3;
    assert!(matches!(
        decode(&bytes),
        Err(DecodeError::UnsupportedVersion(3))
    ));
}

#[test]
fn an_answer_line_takes_bytes_whole_or_not_at_all() {
    let full = Line::from_bytes(&[b'x'; LINE_MAX]);
    assert_eq!(full.len(), LINE_MAX);
    assert!(full.iter().all(|&b| b == b'x'));
    assert!(Line::from_bytes(&[b'x'; LINE_MAX + 1]).is_empty());
    assert_eq!(Line::from_bytes(b"ERR\n").as_slice(), b"ERR\n");
}

/// The motor at constant voltage (the rate controller would stop it for a
/// stall without a simulated rotor): the pass's state machine, soft start
/// and 10-minute limit are the controller's.
#[derive(Clone, Debug)]
struct Constant(Controller);

impl MotorControl for Constant {
    fn hall_edge(&mut self, _: HallEdge) {}
    fn step(&mut self, now_us: u64, c: Option<Command>, b: BatteryStatus) -> RateOutput {
        let o = self.0.step(now_us, c, b);
        RateOutput {
            duty: o.duty,
            state: o.state,
            event: o.event.map(RateEvent::Motor),
            reference_mhz: 1_000,
            saturated: false,
        }
    }
    fn set_rate(&self) -> Option<u32> {
        Some(1_000)
    }
    fn set_rate_mhz(&mut self, _: Option<u32>) {}
    fn fault(&self) -> Option<SensorFault> {
        None
    }
    fn rate_mhz(&self) -> Option<u32> {
        Some(1_000)
    }
    fn senses_rotor(&self) -> bool {
        false
    }
}

fn frame(at_us: u32, address: u8, command: u8) -> Vec<(Level, u32)> {
    let mut v = Vec::new();
    for_each_edge(at_us, &frame_pulses_us(address, command), |l, t| {
        v.push((l, t))
    });
    v
}

#[test]
fn a_whole_ten_minute_run_at_10_hz() {
    let control = Constant(Controller::new(board::CONTROLLER));
    let mut m = MainLoop::with_control(MainLoopConfig::BOARD, control, false);
    let mut rec = Recorder::new(board::LOG_PERIOD_US);
    let counts = board::BATTERY.mv_to_counts(3_900);
    let mut records = Vec::new();
    let mut pass = |m: &mut MainLoop<Constant>, t_us: u64, edges: Vec<(Level, u32)>| {
        let out = m.pass(t_us, edges, [], || counts);
        (out, rec.observe(t_us, &out))
    };
    for t in (0..1_000_000).step_by(1_000) {
        records.extend(pass(&mut m, t, Vec::new()).1);
    }
    // Two foreign frames while off, then On from our remote.
    records.extend(pass(&mut m, 1_100_000, frame(1_000_000, 0x42, board::NEC_CMD_ON)).1);
    records.extend(pass(&mut m, 1_200_000, frame(1_100_000, 0x42, board::NEC_CMD_ON)).1);
    assert_eq!(records.len(), 0, "nothing recorded with the motor off");
    let on = frame(1_200_000, board::NEC_ADDRESS, board::NEC_CMD_ON);
    let (on, first) = pass(&mut m, 1_300_000, on);
    assert_eq!(on.state, MotorState::Ramping);
    records.extend(first);
    let mut t = 1_300_000;
    while m.state() != MotorState::Off {
        t += 1_000;
        records.extend(pass(&mut m, t, Vec::new()).1);
    }
    // The 10-minute limit stopped it: 6000 intervals plus the closing record.
    assert_eq!(records.len(), 6_001);
    let first = records[0];
    assert!(first.events.contains(Events::ON) && first.events.contains(Events::STARTED));
    assert_eq!(
        first.foreign_frames, 2,
        "the frames while off are in the first record"
    );
    assert_eq!(first.t_ms, 1_300);
    let last = records[records.len() - 1];
    assert!(last.events.contains(Events::STOPPED_MAX_RUN_TIME));
    assert_eq!(last.duty_per_10k, 0);
    assert!(records.windows(2).all(|w| w[1].t_ms - w[0].t_ms == 100));
    let running = &records[10..6_000];
    assert!(running
        .iter()
        .all(|r| r.duty_per_10k > 0 && r.cell_mv > 3_800));
    let bytes = image(&records);
    assert_eq!(bytes.len(), 32 + 16 * 6_001);
    assert_eq!(decode(&bytes).unwrap().records().count(), 6_001);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]
    /// Passes at any gaps up to the wake period: while the motor runs the
    /// records come one sample period apart at least and at most one pass
    /// later, the first in the starting pass, the last in the stopping one.
    #[test]
    fn records_keep_the_period_whatever_the_pass_timing(gaps in proptest::collection::vec(1u64..=1_000, 3_000..6_000), off_at in 500usize..2_500) {
        let control = Constant(Controller::new(board::CONTROLLER));
        let mut m = MainLoop::with_control(MainLoopConfig::BOARD, control, false);
        let mut rec = Recorder::new(board::LOG_PERIOD_US);
        let counts = board::BATTERY.mv_to_counts(3_900);
        let mut t = 0u64;
        let mut taken = Vec::new();
        for (i, gap) in gaps.iter().enumerate() {
            t += gap * 100;
            let edges = match i {
                0 => frame(0, board::NEC_ADDRESS, board::NEC_CMD_ON),
                i if i == off_at => frame(t as u32 - 80_000, board::NEC_ADDRESS, board::NEC_CMD_OFF),
                _ => Vec::new(),
            };
            let out = m.pass(t + 80_000, edges, [], || counts);
            if let Some(r) = rec.observe(t + 80_000, &out) {
                taken.push((t + 80_000, r));
            }
        }
        let period = u64::from(board::LOG_PERIOD_US);
        prop_assert!(taken.len() >= 2);
        prop_assert!(taken[0].1.events.contains(Events::STARTED));
        let last = taken[taken.len() - 1];
        prop_assert!(last.1.events.contains(Events::STOPPED_COMMAND));
        for w in taken[..taken.len() - 1].windows(2) {
            let dt = w[1].0 - w[0].0;
            prop_assert!(dt >= period && dt <= period + 100_000, "records {} us apart", dt);
        }
        prop_assert!(taken.iter().all(|(at, _)| *at <= last.0), "a record after the stop");
    }

    #[test]
    fn decode_is_total(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let _ = decode(&bytes);
    }

    #[test]
    fn decode_is_total_on_damaged_images(n in 0usize..20, at in any::<prop::sample::Index>(), byte: u8, cut in any::<prop::sample::Index>()) {
        let records: Vec<Record> = (0..n as u32).map(record).collect();
        let mut bytes = image(&records);
        let i = at.index(bytes.len());
        let changed = bytes[i] != byte;
        bytes[i] = byte;
        let got = decode(&bytes);
        if changed {
            prop_assert!(got.is_err(), "a changed byte at {} went unnoticed", i);
        }
        let len = cut.index(bytes.len());
        prop_assert!(decode(&bytes[..len]).is_err());
    }

    #[test]
    fn records_round_trip(t_ms: u32, set in 0u16..=u16::MAX, rate: Option<u16>, duty in 0u16..=10_000, mv: u16, ev: u16, fault in 0u8..7, foreign: u8) {
        let mut b = [0u8; RECORD_LEN];
        b[0..4].copy_from_slice(&t_ms.to_le_bytes());
        b[4..6].copy_from_slice(&set.to_le_bytes());
        b[6..8].copy_from_slice(&rate.unwrap_or(u16::MAX).to_le_bytes());
        b[8..10].copy_from_slice(&duty.to_le_bytes());
        b[10..12].copy_from_slice(&mv.to_le_bytes());
        b[12..14].copy_from_slice(&ev.to_le_bytes());
        b[14] = fault;
        b[15] = foreign;
        let r = Record::from_bytes(&b).unwrap();
        prop_assert_eq!(r.to_bytes(), b);
    }
}
