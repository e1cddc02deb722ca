//! The paired address in flash: one 4 KiB sector of 4-byte entries
//! (`P`, address, address inverted, `!P`), appended one per pairing; the
//! last valid entry before the first erased one (all 0xFF) is the paired
//! remote. Appending needs only a page program (under 3 ms), never an
//! erase, so pairing costs no stall; only the 1025th pairing finds the
//! sector full and waits for an erase (allowed only with the motor off,
//! `PassOutput::may_erase_flash`). A torn or foreign entry is not valid
//! and is skipped.

/// Bytes of one entry.
pub const ENTRY_LEN: usize = 4;
/// Bytes of the sector.
pub const SECTOR_LEN: usize = 4_096;
const TAG: u8 = b'P';

fn entry(address: u8) -> [u8; ENTRY_LEN] {
    [TAG, address, !address, !TAG]
}

fn valid(e: &[u8]) -> Option<u8> {
    (e.len() == ENTRY_LEN && e[0] == TAG && e[2] == !e[1] && e[3] == !TAG).then_some(e[1])
}

fn erased(e: &[u8]) -> bool {
    e.iter().all(|&b| b == 0xFF)
}

/// The paired address kept in `sector` (`None`: unpaired).
pub fn stored(sector: &[u8]) -> Option<u8> {
    sector
        .chunks_exact(ENTRY_LEN)
        .take_while(|e| !erased(e))
        .filter_map(valid)
        .last()
}

/// Where pairing `address` goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Append {
    /// Program these bytes at this offset in the sector (a page with
    /// 0xFF elsewhere).
    At {
        offset: usize,
        bytes: [u8; ENTRY_LEN],
    },
    /// No erased entry left: erase the sector, then append.
    EraseFirst,
}

/// Where the next entry for `address` goes in `sector`.
pub fn append(sector: &[u8], address: u8) -> Append {
    let used = sector
        .chunks_exact(ENTRY_LEN)
        .rposition(|e| !erased(e))
        .map_or(0, |i| i + 1);
    if (used + 1) * ENTRY_LEN > sector.len().min(SECTOR_LEN) {
        return Append::EraseFirst;
    }
    Append::At {
        offset: used * ENTRY_LEN,
        bytes: entry(address),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn program(sector: &mut [u8], a: Append) {
        match a {
            Append::At { offset, bytes } => {
                for (s, b) in sector[offset..offset + ENTRY_LEN].iter_mut().zip(bytes) {
                    *s &= b;
                }
            }
            Append::EraseFirst => sector.fill(0xFF),
        }
    }

    #[test]
    fn the_last_pairing_wins_and_a_full_sector_is_erased() {
        let mut sector = [0xFF; SECTOR_LEN];
        assert_eq!(stored(&sector), None, "erased: unpaired");
        for a in [0x00, 0x5a, 0x11] {
            let at = append(&sector, a);
            program(&mut sector, at);
        }
        assert_eq!(stored(&sector), Some(0x11));
        for i in 0..(SECTOR_LEN / ENTRY_LEN - 3) {
            let at = append(&sector, i as u8);
            program(&mut sector, at);
        }
        assert_eq!(append(&sector, 0x42), Append::EraseFirst);
        program(&mut sector, Append::EraseFirst);
        let at = append(&sector, 0x42);
        program(&mut sector, at);
        assert_eq!(stored(&sector), Some(0x42));
    }

    #[test]
    fn torn_and_foreign_entries_are_skipped() {
        let mut sector = [0xFF; SECTOR_LEN];
        let at = append(&sector, 0x5a);
        program(&mut sector, at);
        // A torn entry (power lost mid-program): only its first byte.
        sector[4] = TAG;
        assert_eq!(stored(&sector), Some(0x5a));
        let at = append(&sector, 0x22);
        assert_eq!(
            at,
            Append::At {
                offset: 8,
                bytes: entry(0x22)
            }
        );
    }

    proptest! {
        #[test]
        fn any_sector_reads_without_panic(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
            let _ = stored(&bytes);
            if let Append::At { offset, .. } = append(&bytes, 7) {
                prop_assert!(offset + ENTRY_LEN <= bytes.len());
            }
        }
    }
}
