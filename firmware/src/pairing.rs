//! The paired remote (address and keys) in the pairing sector (`memory.x`'s
//! PAIRING, format `swimbot_shared::pairing::sector`): read at boot,
//! appended when the pass reports a new pairing (a page program, under
//! 3 ms), erased only in the rare case that the sector is full, and then
//! only when the pass allows an erase.

use crate::{board, flash};
use rp2040_hal::Watchdog;
use swimbot_shared::pairing::sector::{self, Append, SECTOR_LEN};
use swimbot_shared::run_log::store::PAGE_LEN;
use swimbot_shared::PairedRemote;

fn sector_bytes() -> [u8; SECTOR_LEN] {
    let mut s = [0u8; SECTOR_LEN];
    flash::read(board::PAIRING_FLASH_OFFSET, &mut s);
    s
}

/// The remote kept in flash (`None`: unpaired).
pub fn stored() -> Option<PairedRemote> {
    sector::stored(&sector_bytes(), board::KEYS)
}

/// A pairing waiting for the sector's erase.
pub struct PairingStore {
    pending: Option<PairedRemote>,
}

impl PairingStore {
    pub const fn new() -> Self {
        Self { pending: None }
    }

    /// Keep `address` as the paired remote.
    pub fn save(&mut self, address: PairedRemote) {
        match sector::append(&sector_bytes(), address) {
            Append::At { offset, bytes } => {
                let mut page = [0xFF; PAGE_LEN];
                let at = offset % PAGE_LEN;
                page[at..at + bytes.len()].copy_from_slice(&bytes);
                let page_offset = (offset - at) as u32;
                flash::program_page(board::PAIRING_FLASH_OFFSET + page_offset, &page);
                if stored() != Some(address) {
                    // Not kept (worn or foreign bytes): erase and retry.
                    self.pending = Some(address);
                }
            }
            Append::EraseFirst => self.pending = Some(address),
        }
    }

    pub fn erase_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// Erase the sector and write the pending pairing (call only when the
    /// pass allows an erase); false if it still did not hold, then given
    /// up (the pairing holds in RAM until power-off).
    pub fn erase_step(&mut self, watchdog: &mut Watchdog) -> bool {
        let Some(address) = self.pending.take() else {
            return true;
        };
        flash::erase(watchdog, board::PAIRING_FLASH_OFFSET, SECTOR_LEN as u32);
        self.save(address);
        self.pending.take().is_none()
    }
}
