//! An image being read out: its header (counted and checked when the
//! request came) and the records streamed from flash behind it, in pieces
//! as large as the USB endpoint takes.

use super::{record_offset, LogFlash, StoreLayout};
use crate::run_log::image::HEADER_LEN;
use crate::run_log::record::RECORD_LEN;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadoutImage {
    header: [u8; HEADER_LEN],
    layout: StoreLayout,
    slot: Option<u8>,
    count: u32,
}

impl ReadoutImage {
    pub(super) fn new(
        header: [u8; HEADER_LEN],
        layout: StoreLayout,
        slot: Option<u8>,
        count: u32,
    ) -> Self {
        Self {
            header,
            layout,
            slot,
            count,
        }
    }

    /// Bytes of the whole image.
    pub fn len(&self) -> usize {
        HEADER_LEN + self.count as usize * RECORD_LEN
    }

    pub fn is_empty(&self) -> bool {
        false
    }

    pub fn header(&self) -> &[u8; HEADER_LEN] {
        &self.header
    }

    /// Copy the image's bytes from `pos` into `buf`; how many (0 at the end).
    pub fn read(&self, flash: &impl LogFlash, pos: usize, buf: &mut [u8]) -> usize {
        let n = buf.len().min(self.len().saturating_sub(pos));
        let mut done = 0;
        while done < n {
            let at = pos + done;
            if at < HEADER_LEN {
                let k = (HEADER_LEN - at).min(n - done);
                buf[done..done + k].copy_from_slice(&self.header[at..at + k]);
                done += k;
                continue;
            }
            let rel = at - HEADER_LEN;
            let k = (RECORD_LEN - rel % RECORD_LEN).min(n - done);
            match self.slot {
                Some(s) => {
                    let record = (rel / RECORD_LEN) as u32;
                    let offset = record_offset(&self.layout, s, record) + (rel % RECORD_LEN) as u32;
                    flash.read(offset, &mut buf[done..done + k]);
                }
                None => buf[done..done + k].fill(0),
            }
            done += k;
        }
        n
    }
}
