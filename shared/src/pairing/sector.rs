//! The paired remote in flash: one 4 KiB sector of entries appended one
//! per pairing; the last valid entry before the end (the first erased
//! 8-byte-aligned word) is the paired remote. An entry is 8 bytes at an
//! 8-byte-aligned offset: `R`, the address's two bytes (low first), the On
//! and Off keys, their XOR, that XOR inverted, `!R`. Entries of the
//! earlier 4-byte form (`P`, an 8-bit address, it inverted, `!P`: a
//! standard remote with the board's keys) still read, so a robot paired
//! by older firmware stays paired; an 8-byte entry after an odd number of
//! them leaves one erased 4-byte word, which is skipped.
//!
//! Appending needs only a page program (under 3 ms), never an erase, so
//! pairing costs no stall; only a full sector waits for an erase (allowed
//! only with the motor off, `PassOutput::may_erase_flash`). A torn or
//! foreign entry is not valid and is skipped.

use crate::command::{KeyMap, PairedRemote};
use crate::nec::Address;

/// Bytes of one entry.
pub const ENTRY_LEN: usize = 8;
/// Bytes of the sector.
pub const SECTOR_LEN: usize = 4_096;
const TAG: u8 = b'R';
/// The 4-byte entries of the earlier format.
const OLD_TAG: u8 = b'P';
const WORD: usize = 4;

fn check(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |x, b| x ^ b)
}

fn entry(r: PairedRemote) -> [u8; ENTRY_LEN] {
    let [lo, hi] = r.address.0.to_le_bytes();
    let x = check(&[lo, hi, r.on, r.off]);
    [TAG, lo, hi, r.on, r.off, x, !x, !TAG]
}

fn valid(e: &[u8]) -> Option<PairedRemote> {
    let ok = e.len() == ENTRY_LEN && e[0] == TAG && e[7] == !TAG;
    let x = check(e.get(1..5)?);
    (ok && e[5] == x && e[6] == !x).then(|| PairedRemote {
        address: Address(u16::from_le_bytes([e[1], e[2]])),
        on: e[3],
        off: e[4],
    })
}

fn valid_old(e: &[u8], keys: KeyMap) -> Option<PairedRemote> {
    (e.len() == WORD && e[0] == OLD_TAG && e[2] == !e[1] && e[3] == !OLD_TAG).then_some(
        PairedRemote {
            address: Address::standard(e[1]),
            ..PairedRemote::of_keys(keys)
        },
    )
}

fn erased(e: &[u8]) -> bool {
    e.iter().all(|&b| b == 0xFF)
}

/// Walks the sector's entries: calls `f` with each valid one; returns the
/// offset where the next entry goes (8-byte aligned).
fn walk(sector: &[u8], keys: KeyMap, mut f: impl FnMut(PairedRemote)) -> usize {
    let mut at = 0;
    while let Some(word) = sector.get(at..at + WORD) {
        if erased(word) {
            if at % ENTRY_LEN == 0 {
                return at;
            }
            at += WORD; // the gap before an 8-byte entry
            continue;
        }
        if let Some(r) = sector.get(at..at + ENTRY_LEN).and_then(valid) {
            f(r);
            at += ENTRY_LEN;
            continue;
        }
        if let Some(r) = valid_old(word, keys) {
            f(r);
        }
        at += WORD; // an old entry, or a torn/foreign word
    }
    at.next_multiple_of(ENTRY_LEN)
}

/// The paired remote kept in `sector` (`None`: unpaired); entries of the
/// earlier format get `keys`' On and Off.
pub fn stored(sector: &[u8], keys: KeyMap) -> Option<PairedRemote> {
    let mut last = None;
    walk(sector, keys, |r| last = Some(r));
    last
}

/// Where pairing a remote goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Append {
    /// Program these bytes at this offset in the sector (8-byte aligned,
    /// so never across a page; a page with 0xFF elsewhere).
    At {
        offset: usize,
        bytes: [u8; ENTRY_LEN],
    },
    /// No erased entry left: erase the sector, then append.
    EraseFirst,
}

/// Where the next entry for `remote` goes in `sector`.
pub fn append(sector: &[u8], remote: PairedRemote) -> Append {
    // The keys only name old entries, which do not decide where to append.
    let offset = walk(sector, crate::board::KEYS, |_| {});
    if offset + ENTRY_LEN > sector.len().min(SECTOR_LEN) {
        return Append::EraseFirst;
    }
    Append::At {
        offset,
        bytes: entry(remote),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const KEYS: KeyMap = crate::board::KEYS;

    fn remote(address: u16, on: u8) -> PairedRemote {
        PairedRemote {
            address: Address(address),
            on,
            off: 0x47,
        }
    }

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
        assert_eq!(stored(&sector, KEYS), None, "erased: unpaired");
        for r in [
            remote(0xFF00, 0x45),
            remote(0x1234, 0x16),
            remote(0xA55A, 0x0c),
        ] {
            let at = append(&sector, r);
            program(&mut sector, at);
        }
        assert_eq!(stored(&sector, KEYS), Some(remote(0xA55A, 0x0c)));
        for i in 0..(SECTOR_LEN / ENTRY_LEN - 3) {
            let at = append(&sector, remote(i as u16, 1));
            program(&mut sector, at);
        }
        assert_eq!(append(&sector, remote(0x42, 2)), Append::EraseFirst);
        program(&mut sector, Append::EraseFirst);
        let at = append(&sector, remote(0x42, 2));
        program(&mut sector, at);
        assert_eq!(stored(&sector, KEYS), Some(remote(0x42, 2)));
    }

    #[test]
    fn old_entries_read_with_the_boards_keys_and_a_new_one_follows() {
        let mut sector = [0xFF; SECTOR_LEN];
        sector[..4].copy_from_slice(&[OLD_TAG, 0x5a, !0x5a, !OLD_TAG]);
        assert_eq!(
            stored(&sector, KEYS),
            Some(PairedRemote {
                address: Address::standard(0x5a),
                ..PairedRemote::of_keys(KEYS)
            })
        );
        let at = append(&sector, remote(0x1280, 0x16));
        assert!(matches!(at, Append::At { offset: 8, .. }), "{at:?}");
        program(&mut sector, at);
        assert_eq!(stored(&sector, KEYS), Some(remote(0x1280, 0x16)));
    }

    #[test]
    fn torn_and_foreign_entries_are_skipped() {
        let mut sector = [0xFF; SECTOR_LEN];
        let at = append(&sector, remote(0x1234, 0x16));
        program(&mut sector, at);
        // A torn entry (power lost mid-program): only its first bytes.
        sector[8] = TAG;
        sector[9] = 0x99;
        assert_eq!(stored(&sector, KEYS), Some(remote(0x1234, 0x16)));
        // A changed key byte fails the check.
        let mut bad = sector;
        bad[3] ^= 1;
        assert_eq!(stored(&bad, KEYS), None);
        let at = append(&sector, remote(0x22, 0x45));
        assert!(matches!(at, Append::At { offset: 16, .. }), "{at:?}");
    }

    proptest! {
        #[test]
        fn any_sector_reads_without_panic(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
            let _ = stored(&bytes, KEYS);
            if let Append::At { offset, .. } = append(&bytes, remote(7, 7)) {
                prop_assert!(offset + ENTRY_LEN <= bytes.len());
                prop_assert_eq!(offset % ENTRY_LEN, 0);
            }
        }

        #[test]
        fn what_is_appended_is_read_back(address: u16, on: u8, off: u8, old in 0usize..5) {
            let mut sector = [0xFF; 256];
            for i in 0..old {
                sector[4 * i..4 * i + 4].copy_from_slice(&[OLD_TAG, i as u8, !(i as u8), !OLD_TAG]);
            }
            let r = PairedRemote { address: Address(address), on, off };
            let at = append(&sector, r);
            program(&mut sector, at);
            prop_assert_eq!(stored(&sector, KEYS), Some(r));
        }
    }
}
