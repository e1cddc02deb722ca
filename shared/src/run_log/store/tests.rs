//! The log store against a flash model (program = AND, erase = 0xFF),
//! across power-ups, power losses mid-run and mid-erase, foreign data in
//! the region and a full slot; every readout must decode.
use super::*;
use crate::run_log::image::{decode, HEADER_LEN, VERSION};
use crate::run_log::power_up::{LogOf, ThisRun};
use crate::run_log::readout::info_line;
use crate::run_log::record::Events;
use crate::run_log::record::RECORD_LEN;
use proptest::prelude::*;
use std::vec::Vec;

extern crate std;

const LAYOUT: StoreLayout = StoreLayout {
    slots: 3,
    slot_len: 4 * BLOCK_LEN,
};

#[derive(Clone)]
struct Flash {
    bytes: Vec<u8>,
    programs: u32,
    erases: u32,
    /// A page that does not take a program (worn out).
    stuck_page: Option<u32>,
}

impl Flash {
    fn blank() -> Self {
        Self {
            bytes: std::vec![0xFF; LAYOUT.region_len() as usize],
            programs: 0,
            erases: 0,
            stuck_page: None,
        }
    }
}

impl LogFlash for Flash {
    fn read(&self, offset: u32, buf: &mut [u8]) {
        let o = offset as usize;
        buf.copy_from_slice(&self.bytes[o..o + buf.len()]);
    }
    fn program_page(&mut self, offset: u32, page: &[u8; PAGE_LEN]) {
        assert_eq!(offset as usize % PAGE_LEN, 0);
        self.programs += 1;
        if self.stuck_page == Some(offset) {
            return;
        }
        let o = offset as usize;
        for (b, p) in self.bytes[o..o + PAGE_LEN].iter_mut().zip(page) {
            *b &= p;
        }
    }
    fn erase_block(&mut self, offset: u32) {
        assert_eq!(offset % BLOCK_LEN, 0);
        let o = offset as usize;
        self.bytes[o..o + BLOCK_LEN as usize].fill(0xFF);
        self.erases += 1;
    }
}

fn record(t: u32) -> Record {
    Record {
        t_ms: t * 100,
        set_point_mhz: Some(1_000),
        rate_mhz: Some(990 + (t % 20) as u16),
        duty_per_10k: 4_000,
        cell_mv: 3_900,
        events: if t == 0 {
            Events::STARTED
        } else {
            Events::NONE
        },
        fault: None,
        foreign_frames: (t % 2) as u8,
    }
}

/// A run of `n` records, the last one flushed (the run stopped).
fn run(store: &mut LogStore, flash: &mut Flash, from: u32, n: u32) {
    for t in from..from + n {
        store.append(flash, &record(t), t + 1 == from + n);
    }
}

/// The image a readout streams, in USB-sized pieces.
fn read_out(store: &LogStore, flash: &Flash, foreign: u32) -> Vec<u8> {
    let mut feeds = 0;
    let image = store.readout(flash, foreign, Some(0x5a), &mut || feeds += 1);
    // The header is not a record: only whole runs of FEED_EVERY records
    // are owed a feed.
    let records = (image.len() - HEADER_LEN) / RECORD_LEN;
    assert!(
        feeds >= records / FEED_EVERY as usize,
        "fed {feeds} times while reading {records} records"
    );
    let mut out = Vec::new();
    let mut buf = [0u8; 64];
    loop {
        let n = image.read(flash, out.len(), &mut buf);
        if n == 0 {
            break;
        }
        out.extend_from_slice(&buf[..n]);
    }
    assert_eq!(out.len(), image.len());
    out
}

fn records_of(bytes: &[u8]) -> Vec<Record> {
    decode(bytes).unwrap().records().collect()
}

#[test]
fn a_ten_minute_run_on_blank_flash() {
    let mut flash = Flash::blank();
    let mut store = LogStore::open(&flash, LAYOUT, 100);
    assert!(store.ready() && !store.erase_pending());
    run(&mut store, &mut flash, 0, 6_001);
    let bytes = read_out(&store, &flash, 9);
    let log = decode(&bytes).unwrap();
    assert_eq!(log.header.record_count, 6_001);
    assert_eq!(log.header.foreign_frames, 9, "this power-up's live count");
    assert_eq!(log.header.flags, FLAG_CLOSED);
    assert_eq!(
        log.records().collect::<Vec<_>>(),
        (0..6_001).map(record).collect::<Vec<_>>()
    );
    // A page per 16 records plus the header page and the closing flush.
    assert_eq!(flash.programs, 1 + 6_001_u32.div_ceil(16));
    assert_eq!(flash.erases, 0);
}

/// 254 records make a 4 096-byte image, a multiple of 16 * FEED_EVERY,
/// yet fewer than FEED_EVERY records: no feed is owed (the case proptest
/// once found when the bound counted the header as record bytes). One
/// more whole run of records is owed its feed.
#[test]
fn feeds_are_owed_per_record_not_per_header_byte() {
    let mut flash = Flash::blank();
    let mut store = LogStore::open(&flash, LAYOUT, 100);
    run(&mut store, &mut flash, 0, 254);
    assert_eq!(read_out(&store, &flash, 0).len(), 4_096);
    let mut feeds = 0;
    let _ = store.readout(&flash, 0, None, &mut || feeds += 1);
    assert_eq!(feeds, 0, "254 records, fewer than FEED_EVERY");
    run(&mut store, &mut flash, 254, 2);
    let mut feeds = 0;
    let _ = store.readout(&flash, 0, None, &mut || feeds += 1);
    assert!(feeds >= 1, "256 records owe a feed");
}

#[test]
fn power_ups_keep_the_newest_log_and_erase_the_oldest() {
    let mut flash = Flash::blank();
    let mut s1 = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s1, &mut flash, 0, 40);
    // Power-up 2, no run: the readout is power-up 1's log, counts rebuilt.
    let s2 = LogStore::open(&flash, LAYOUT, 100);
    let bytes = read_out(&s2, &flash, 0);
    let log = decode(&bytes).unwrap();
    assert_eq!(log.header.flags, FLAG_CLOSED | FLAG_RECOVERED);
    assert_eq!(
        log.header.foreign_frames, 20,
        "the sum of the records' counts"
    );
    assert_eq!(records_of(&bytes), (0..40).map(record).collect::<Vec<_>>());
    // Power-up 3 runs; power-up 4 runs: power-up 1's slot must be erased.
    let mut s3 = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s3, &mut flash, 100, 30);
    let mut s4 = LogStore::open(&flash, LAYOUT, 100);
    assert!(s4.ready(), "a blank slot was left for it");
    assert!(s4.erase_pending(), "the oldest log is erased for the next");
    let before = read_out(&s4, &flash, 0);
    let _ = before.len();
    assert_eq!(
        records_of(&before),
        (100..130).map(record).collect::<Vec<_>>()
    );
    while s4.erase_step(&mut flash) {}
    assert_eq!(flash.erases, 4, "one slot, block by block");
    run(&mut s4, &mut flash, 200, 5);
    assert_eq!(
        records_of(&read_out(&s4, &flash, 0)),
        (200..205).map(record).collect::<Vec<_>>()
    );
    let s5 = LogStore::open(&flash, LAYOUT, 100);
    assert!(s5.ready() && s5.erase_pending(), "power-up 3's log is next");
    assert_eq!(
        records_of(&read_out(&s5, &flash, 0)),
        (200..205).map(record).collect::<Vec<_>>()
    );
}

#[test]
fn a_power_loss_mid_run_keeps_every_programmed_page() {
    let mut flash = Flash::blank();
    let mut s1 = LogStore::open(&flash, LAYOUT, 100);
    for t in 0..100 {
        s1.append(&mut flash, &record(t), false);
    }
    // Power lost: the RAM page (records 96-99) is gone, the rest is kept.
    let s2 = LogStore::open(&flash, LAYOUT, 100);
    assert_eq!(
        records_of(&read_out(&s2, &flash, 0)),
        (0..96).map(record).collect::<Vec<_>>()
    );
}

#[test]
fn a_power_loss_mid_erase_erases_again() {
    let mut flash = Flash::blank();
    for from in [0, 1_000, 2_000] {
        // Each power-up too short to erase anything.
        let mut s = LogStore::open(&flash, LAYOUT, 100);
        run(&mut s, &mut flash, from, 3_000);
    }
    // All three slots hold logs; the next power-up must erase before use.
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    assert!(!s.ready());
    s.erase_step(&mut flash);
    s.erase_step(&mut flash);
    // Power lost after half the blocks (the last ones): the header page
    // is intact, the slot still reads as a (shortened) log, and the next
    // power-up erases it again before writing.
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s, &mut flash, 9_000, 3);
    assert_eq!(s.dropped(), 3, "not erased yet: nothing kept");
    while s.erase_step(&mut flash) {}
    assert!(s.ready());
    run(&mut s, &mut flash, 9_100, 3);
    let bytes = read_out(&s, &flash, 0);
    assert_eq!(
        records_of(&bytes),
        (9_100..9_103).map(record).collect::<Vec<_>>()
    );
    assert_eq!(decode(&bytes).unwrap().header.dropped_records, 3);
}

/// A power-up with no erased slot runs: its readout is the newest earlier
/// log, and says so with this power-up's dropped count (it said 0 before,
/// and a lab took the earlier run for this one).
#[test]
fn a_dropped_run_is_said_in_the_readout() {
    let mut flash = Flash::blank();
    for from in [0, 1_000, 2_000] {
        let mut s = LogStore::open(&flash, LAYOUT, 100);
        run(&mut s, &mut flash, from, 30);
    }
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    assert!(!s.ready());
    let unrun = decode(&read_out(&s, &flash, 0)).unwrap().header;
    assert_eq!(ThisRun::of(&unrun, VERSION), Some(ThisRun::NoRun));
    run(&mut s, &mut flash, 3_000, 17);
    let bytes = read_out(&s, &flash, 0);
    let log = decode(&bytes).unwrap();
    assert_eq!(log.version, VERSION);
    assert_eq!(LogOf::of(&log.header), LogOf::EarlierPowerUp);
    assert_eq!(
        records_of(&bytes),
        (2_000..2_030).map(record).collect::<Vec<_>>()
    );
    assert_eq!(log.header.dropped_records, 17);
    assert_eq!(log.this_run(), Some(ThisRun::Dropped { dropped: 17 }));
    let info = info_line(&log.header, None);
    assert!(
        info.ends_with(b" dropped=17 foreign=15 paired=0x5a log=earlier this_run=dropped\n"),
        "{:?}",
        core::str::from_utf8(&info)
    );
    // Erased, a second run is kept: this power-up's log, partly dropped.
    while s.erase_step(&mut flash) {}
    run(&mut s, &mut flash, 4_000, 5);
    let log = decode(&read_out(&s, &flash, 0)).unwrap().this_run();
    assert_eq!(log, Some(ThisRun::PartlyDropped { dropped: 17 }));
}

#[test]
fn foreign_data_is_erased_or_ends_the_log() {
    // Garbage over the whole region (a previous firmware's file system).
    let mut flash = Flash::blank();
    flash
        .bytes
        .iter_mut()
        .enumerate()
        .for_each(|(i, b)| *b = (i * 7 % 251) as u8);
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    assert!(!s.ready());
    assert_eq!(
        decode(&read_out(&s, &flash, 0))
            .unwrap()
            .header
            .record_count,
        0
    );
    while s.erase_step(&mut flash) {}
    run(&mut s, &mut flash, 0, 20);
    assert_eq!(records_of(&read_out(&s, &flash, 0)).len(), 20);
    // Garbage under a blank header page: the read-back check ends the log.
    let mut flash = Flash::blank();
    flash.bytes[PAGE_LEN * 3 + 5] = 0x00;
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s, &mut flash, 0, 40);
    let bytes = read_out(&s, &flash, 0);
    let log = decode(&bytes).unwrap();
    assert_eq!(
        log.header.record_count, 32,
        "the pages before the foreign byte"
    );
    assert_eq!(log.header.dropped_records, 8);
}

#[test]
fn a_header_page_that_does_not_program_drops_the_run() {
    let mut flash = Flash::blank();
    flash.stuck_page = Some(0);
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s, &mut flash, 0, 20);
    assert_eq!((s.count(), s.dropped()), (0, 20));
    let bytes = read_out(&s, &flash, 0);
    let log = decode(&bytes).unwrap();
    assert_eq!(
        (log.header.record_count, log.header.dropped_records),
        (0, 20)
    );
    // A records page that does not program: its records are dropped too.
    let mut flash = Flash::blank();
    flash.stuck_page = Some(2 * PAGE_LEN as u32);
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    run(&mut s, &mut flash, 0, 40);
    assert_eq!((s.count(), s.dropped()), (16, 24));
}

#[test]
fn a_full_slot_counts_what_it_drops() {
    let mut flash = Flash::blank();
    let mut s = LogStore::open(&flash, LAYOUT, 100);
    let cap = LAYOUT.records_per_slot();
    assert_eq!(cap, 16_368, "27 min at 10 Hz");
    run(&mut s, &mut flash, 0, cap + 10);
    assert_eq!((s.count(), s.dropped()), (cap, 10));
    let bytes = read_out(&s, &flash, 0);
    assert_eq!(decode(&bytes).unwrap().header.record_count, cap);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]
    /// Any sequence of runs, power-ups and erase steps: no panic, every
    /// readout decodes, and it holds the last power-up's records that were
    /// flushed (or the newest earlier log if that power-up kept none), and
    /// this power-up's dropped count whatever log it holds.
    #[test]
    fn any_history_reads_out(steps in proptest::collection::vec((0u32..40, any::<bool>(), 0u32..5), 1..12)) {
        let mut flash = Flash::blank();
        let mut store = LogStore::open(&flash, LAYOUT, 100);
        let mut t = 0;
        for (n, reopen, erases) in steps {
            run(&mut store, &mut flash, t, n);
            t += n;
            for _ in 0..erases {
                store.erase_step(&mut flash);
            }
            let bytes = read_out(&store, &flash, 0);
            let log = decode(&bytes);
            prop_assert!(log.is_ok(), "{:?}", log);
            let log = log.unwrap();
            if store.count() > 0 {
                prop_assert_eq!(log.header.record_count, store.count());
            }
            // Whatever the records, the readout says what this power-up lost.
            prop_assert_eq!(log.header.dropped_records, store.dropped());
            let kept = store.count() > 0;
            let said = log.this_run();
            prop_assert_eq!(said, Some(match (kept, store.dropped()) {
                (true, 0) => ThisRun::Kept,
                (true, d) => ThisRun::PartlyDropped { dropped: d },
                (false, 0) => ThisRun::NoRun,
                (false, d) => ThisRun::Dropped { dropped: d },
            }));
            if reopen {
                store = LogStore::open(&flash, LAYOUT, 100);
            }
        }
    }
}
