//! Where the run log lives on the robot: slots in a flash region reserved
//! at the top of flash (`memory.x`), written a 256-byte page at a time
//! during the run and erased only while the motor is off. The decisions
//! (which slot to write, which to erase, where the next record goes, what
//! an image read out holds) are here, host-tested against a flash model;
//! the firmware supplies the three flash operations ([`LogFlash`]) and
//! calls [`LogStore::erase_step`] only when erasing is allowed (motor off,
//! gate low, IR quiet; an erase stalls every flash fetch for 45-2000 ms).
//!
//! Each slot (`StoreLayout::slot_len`, 256 KiB on the robot) is one
//! power-up's log: a header page (magic `SWSL`, version, sample period,
//! session number and its complement) and then 16-byte records from the
//! second page on, appended across every run of that power-up. A record
//! that is all 0xFF is the end (a valid record's duty is at most 10000).
//!
//! Three slots: the newest power-up's log that has records (kept for the
//! readout, also after any number of power-ups without a run), a blank
//! slot the new power-up writes into at once, without erasing first, and
//! the oldest, erased while the motor is off to become the next power-up's
//! blank slot. Erasing goes from a slot's last 64 KiB block to its first,
//! so a blank header page (the first block) means the whole slot is blank
//! even after a power loss in the middle of an erase; a slot whose header
//! page is neither blank nor valid is erased before use. A page is read
//! back after programming; a mismatch (worn or foreign data) ends the
//! slot's log there, and later records are counted as dropped.

use super::image::{Header, ImageDigest, FLAG_CLOSED, FLAG_RECOVERED, HEADER_LEN};
use super::record::{Record, RECORD_LEN};

/// One flash program operation.
pub const PAGE_LEN: usize = 256;
/// One erase operation (the flash's 64 KiB block erase, 0xD8).
pub const BLOCK_LEN: u32 = 65_536;
const RECORDS_PER_PAGE: usize = PAGE_LEN / RECORD_LEN;
const SLOT_MAGIC: [u8; 4] = *b"SWSL";
const SLOT_VERSION: u16 = 1;

/// The flash behind the log region; offsets from the region's start.
pub trait LogFlash {
    fn read(&self, offset: u32, buf: &mut [u8]);
    /// Program one page at a page-aligned offset (bits only go 1 -> 0).
    fn program_page(&mut self, offset: u32, page: &[u8; PAGE_LEN]);
    /// Erase the block at a block-aligned offset (every byte 0xFF).
    fn erase_block(&mut self, offset: u32);
}

/// How the log region is cut into slots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoreLayout {
    pub slots: u8,
    /// A multiple of `BLOCK_LEN`.
    pub slot_len: u32,
}

impl StoreLayout {
    /// Records a slot holds after its header page.
    pub const fn records_per_slot(&self) -> u32 {
        (self.slot_len - PAGE_LEN as u32) / RECORD_LEN as u32
    }

    /// Bytes of the whole region.
    pub const fn region_len(&self) -> u32 {
        self.slots as u32 * self.slot_len
    }

    fn base(&self, slot: u8) -> u32 {
        u32::from(slot) * self.slot_len
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SlotState {
    Blank,
    Session(u32),
    /// Neither blank nor a valid header: erase before use.
    Foreign,
}

fn slot_state(flash: &impl LogFlash, layout: &StoreLayout, slot: u8) -> SlotState {
    let mut page = [0u8; PAGE_LEN];
    flash.read(layout.base(slot), &mut page);
    if page.iter().all(|&b| b == 0xFF) {
        return SlotState::Blank;
    }
    let session = u32::from_le_bytes([page[8], page[9], page[10], page[11]]);
    let check = u32::from_le_bytes([page[12], page[13], page[14], page[15]]);
    let valid = page[..4] == SLOT_MAGIC
        && u16::from_le_bytes([page[4], page[5]]) == SLOT_VERSION
        && check == !session;
    if valid {
        SlotState::Session(session)
    } else {
        SlotState::Foreign
    }
}

/// Record `i` of `slot` if it is one (not the blank end, not damaged).
fn record_at(flash: &impl LogFlash, layout: &StoreLayout, slot: u8, i: u32) -> Option<Record> {
    if i >= layout.records_per_slot() {
        return None;
    }
    let mut b = [0u8; RECORD_LEN];
    flash.read(record_offset(layout, slot, i), &mut b);
    Record::from_bytes(&b).ok()
}

fn record_offset(layout: &StoreLayout, slot: u8, i: u32) -> u32 {
    layout.base(slot) + PAGE_LEN as u32 + i * RECORD_LEN as u32
}

fn period_of(flash: &impl LogFlash, layout: &StoreLayout, slot: u8) -> u16 {
    let mut b = [0u8; 2];
    flash.read(layout.base(slot) + 6, &mut b);
    u16::from_le_bytes(b)
}

/// The log region's state for this power-up.
#[derive(Clone, Debug)]
pub struct LogStore {
    layout: StoreLayout,
    period_ms: u16,
    session: u32,
    /// This power-up's slot, and whether it must be erased first.
    write: u8,
    write_ready: bool,
    /// The newest earlier power-up's slot with records.
    newest: Option<u8>,
    /// Slot being erased, blocks still to erase (this power-up's slot
    /// first if it was not blank, then the next power-up's).
    erase: Option<(u8, u32)>,
    then_erase: Option<u8>,
    header_written: bool,
    count: u32,
    page: [u8; PAGE_LEN],
    broken: bool,
    dropped: u32,
}

mod readout_image;
pub use readout_image::ReadoutImage;

impl LogStore {
    /// Read the slots' headers and decide (at power-up).
    pub fn open(flash: &impl LogFlash, layout: StoreLayout, period_ms: u16) -> Self {
        let states: heapless::Vec<SlotState, 8> = (0..layout.slots.min(8))
            .map(|s| slot_state(flash, &layout, s))
            .collect();
        let session_of = |s: u8| match states[usize::from(s)] {
            SlotState::Session(n) => Some(n),
            _ => None,
        };
        let slots = || 0..states.len() as u8;
        let newest = slots()
            .filter(|&s| session_of(s).is_some() && record_at(flash, &layout, s, 0).is_some())
            .max_by_key(|&s| session_of(s));
        let max_session = slots().filter_map(session_of).max().unwrap_or(0);
        let blank =
            slots().find(|&s| states[usize::from(s)] == SlotState::Blank && Some(s) != newest);
        // No blank slot: the oldest other one (foreign data first).
        let oldest = |except: Option<u8>| {
            slots()
                .filter(|&s| Some(s) != newest && Some(s) != except)
                .min_by_key(|&s| session_of(s).map_or(0, |n| u64::from(n) + 1))
        };
        let (write, write_ready) = match blank {
            Some(s) => (s, true),
            None => (oldest(None).unwrap_or(0), false),
        };
        let blocks = layout.slot_len / BLOCK_LEN;
        let next_blank =
            oldest(Some(write)).filter(|&s| states[usize::from(s)] != SlotState::Blank);
        Self {
            layout,
            period_ms,
            session: max_session.wrapping_add(1),
            write,
            write_ready,
            newest,
            erase: if write_ready {
                next_blank.map(|s| (s, blocks))
            } else {
                Some((write, blocks))
            },
            then_erase: if write_ready { None } else { next_blank },
            header_written: false,
            count: 0,
            page: [0xFF; PAGE_LEN],
            broken: false,
            dropped: 0,
        }
    }

    /// Records written by this power-up, and those taken but not kept.
    pub fn count(&self) -> u32 {
        self.count
    }

    pub fn dropped(&self) -> u32 {
        self.dropped
    }

    /// This power-up's slot can take records (it is blank or erased).
    pub fn ready(&self) -> bool {
        self.write_ready
    }

    /// An erase is pending: call [`Self::erase_step`] when allowed.
    pub fn erase_pending(&self) -> bool {
        self.erase.is_some()
    }

    /// Erase one block of the pending slot (its last block first); true
    /// if a block was erased. Call only while erasing is allowed.
    pub fn erase_step(&mut self, flash: &mut impl LogFlash) -> bool {
        let Some((slot, left)) = self.erase else {
            return false;
        };
        let block = left.saturating_sub(1);
        flash.erase_block(self.layout.base(slot) + block * BLOCK_LEN);
        self.erase = if block > 0 {
            Some((slot, block))
        } else {
            if slot == self.write {
                self.write_ready = true;
            }
            let blocks = self.layout.slot_len / BLOCK_LEN;
            self.then_erase.take().map(|s| (s, blocks))
        };
        true
    }

    /// Keep `record`; program its page when the page is full or `flush`
    /// (the run stopped). Records that cannot be kept are counted.
    pub fn append(&mut self, flash: &mut impl LogFlash, record: &Record, flush: bool) {
        if !self.write_ready || self.broken || self.count >= self.layout.records_per_slot() {
            self.dropped = self.dropped.saturating_add(1);
            return;
        }
        if !self.header_written {
            self.write_header(flash);
            if self.broken {
                self.dropped = self.dropped.saturating_add(1);
                return;
            }
        }
        let in_page = self.count as usize % RECORDS_PER_PAGE;
        let at = in_page * RECORD_LEN;
        self.page[at..at + RECORD_LEN].copy_from_slice(&record.to_bytes());
        self.count += 1;
        let full = in_page + 1 == RECORDS_PER_PAGE;
        if full || flush {
            self.flush(flash);
        }
        if full {
            self.page = [0xFF; PAGE_LEN];
        }
    }

    fn write_header(&mut self, flash: &mut impl LogFlash) {
        let mut page = [0xFF; PAGE_LEN];
        page[..4].copy_from_slice(&SLOT_MAGIC);
        page[4..6].copy_from_slice(&SLOT_VERSION.to_le_bytes());
        page[6..8].copy_from_slice(&self.period_ms.to_le_bytes());
        page[8..12].copy_from_slice(&self.session.to_le_bytes());
        page[12..16].copy_from_slice(&(!self.session).to_le_bytes());
        self.program_checked(flash, self.layout.base(self.write), &page);
        self.header_written = true;
    }

    /// Program the page holding the last record (again, if it was
    /// programmed before: bytes already written are rewritten unchanged).
    fn flush(&mut self, flash: &mut impl LogFlash) {
        if self.count == 0 || self.broken {
            return;
        }
        let first = (self.count - 1) / RECORDS_PER_PAGE as u32 * RECORDS_PER_PAGE as u32;
        let offset = record_offset(&self.layout, self.write, first);
        let page = self.page;
        self.program_checked(flash, offset, &page);
    }

    fn program_checked(&mut self, flash: &mut impl LogFlash, offset: u32, page: &[u8; PAGE_LEN]) {
        flash.program_page(offset, page);
        let mut back = [0u8; PAGE_LEN];
        flash.read(offset, &mut back);
        if back == *page {
            return;
        }
        // Foreign or worn flash under the slot: what follows is lost, and
        // said so by the dropped count (the records of this page, if it is
        // a page of records; none if it is the header's).
        self.broken = true;
        if self.count > 0 && self.header_written {
            let in_page = (self.count - 1) % RECORDS_PER_PAGE as u32 + 1;
            self.count -= in_page;
            self.dropped = self.dropped.saturating_add(in_page);
        }
    }

    /// The image a `LOG` request answers: this power-up's log if it has
    /// records, else the newest earlier one, else an empty log; the
    /// dropped count is this power-up's in every case. `foreign`
    /// is the pass's count since power-up; `paired` the paired remote.
    /// Reading a whole slot through XIP takes longer than the watchdog's
    /// period (about 3 us per 8 bytes in the board's 03h read mode, 100 ms
    /// for 256 KiB): `feed` is called every [`FEED_EVERY`] records.
    pub fn readout(
        &self,
        flash: &impl LogFlash,
        foreign: u32,
        paired: Option<u8>,
        feed: &mut impl FnMut(),
    ) -> ReadoutImage {
        let own = self.count > 0;
        let slot = if own { Some(self.write) } else { self.newest };
        let count = match slot {
            Some(_) if own => self.count,
            Some(s) => self.scan(flash, s, feed),
            None => 0,
        };
        let earlier = slot.is_some() && !own;
        let mut header = Header {
            sample_period_ms: match slot {
                Some(s) if earlier => period_of(flash, &self.layout, s),
                _ => self.period_ms,
            },
            record_count: count,
            // This power-up's, also under an earlier power-up's records:
            // a run that was dropped is said so (`power_up`).
            dropped_records: self.dropped,
            foreign_frames: foreign,
            paired_address: paired,
            flags: FLAG_CLOSED | if earlier { FLAG_RECOVERED } else { 0 },
        };
        if let (true, Some(s)) = (earlier, slot) {
            // Its power-up's count is gone: the sum of its records'.
            let mut summed = 0u32;
            self.each_record(flash, s, count, feed, |r| {
                summed = summed.saturating_add(u32::from(r[15]));
            });
            header.foreign_frames = summed;
        }
        let mut digest = ImageDigest::new(&header);
        if let Some(s) = slot {
            self.each_record(flash, s, count, feed, |r| digest.update(r));
        }
        ReadoutImage::new(header.to_bytes(digest.finalize()), self.layout, slot, count)
    }

    fn each_record(
        &self,
        flash: &impl LogFlash,
        slot: u8,
        count: u32,
        feed: &mut impl FnMut(),
        mut f: impl FnMut(&[u8; RECORD_LEN]),
    ) {
        let mut b = [0u8; RECORD_LEN];
        for i in 0..count {
            flash.read(record_offset(&self.layout, slot, i), &mut b);
            f(&b);
            if i % FEED_EVERY == FEED_EVERY - 1 {
                feed();
            }
        }
    }

    /// Records in an earlier power-up's slot: up to the first that is not
    /// one (the blank end, or damage).
    fn scan(&self, flash: &impl LogFlash, slot: u8, feed: &mut impl FnMut()) -> u32 {
        let cap = self.layout.records_per_slot();
        for i in 0..cap {
            if record_at(flash, &self.layout, slot, i).is_none() {
                return i;
            }
            if i % FEED_EVERY == FEED_EVERY - 1 {
                feed();
            }
        }
        cap
    }
}

/// Records between two calls of a readout's `feed`: 4 kB, about 1.5 ms of
/// XIP reads on the chip.
pub const FEED_EVERY: u32 = 256;

const _: () = assert!(HEADER_LEN == 32);

#[cfg(test)]
mod tests;
