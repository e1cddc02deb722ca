//! The firmware ELF as a UF2 file for the RP2040's BOOTSEL drive (RPI-RP2):
//! every loadable segment's bytes at its load address (`p_paddr`, so
//! `.data`'s initial values land in flash, not at their RAM address), cut
//! into 256-byte pages, one page per 512-byte UF2 block, family ID
//! `RP2040_FAMILY_ID`.
//!
//! Format: Microsoft's UF2 specification (github.com/microsoft/uf2,
//! README "File format"): per block, magic 0x0A324655 and 0x9E5D5157,
//! flags, target address, payload size, block number, block count, family
//! ID (flag 0x2000), 476 data bytes, end magic 0x0AB16F30, all
//! little-endian. The RP2040 bootrom takes 256-byte payloads only, each at
//! a 256-byte-aligned address in flash (RP2040 datasheet 2.8.4.2), which is
//! why partial pages are padded with zeros here, as pico-sdk's elf2uf2 does.
//!
//! Written by hand rather than taken from crates.io: the `uf2` crate there
//! is a single 0.1.0 release without a repository, and the whole format is
//! the 32-byte header above; the RP2040-specific part (paging, the flash
//! window, the family) would have to be written around any crate anyway.

use object::read::elf::{ElfFile32, FileHeader, ProgramHeader};
use object::LittleEndian;
use std::collections::BTreeMap;
use std::path::Path;

pub const MAGIC_START0: u32 = 0x0A32_4655;
pub const MAGIC_START1: u32 = 0x9E5D_5157;
pub const MAGIC_END: u32 = 0x0AB1_6F30;
/// Flag: the family ID field is present.
pub const FLAG_FAMILY_ID: u32 = 0x0000_2000;
/// The RP2040's family in the UF2 family table.
pub const RP2040_FAMILY_ID: u32 = 0xE48B_FF56;
pub const BLOCK_BYTES: usize = 512;
pub const PAGE_BYTES: usize = 256;
/// The XIP flash window the bootrom writes through.
pub const FLASH_START: u32 = 0x1000_0000;
const FLASH_END: u32 = 0x1100_0000;
const PT_LOAD: u32 = 1;

/// The flash image: 256-byte pages by address, zero-padded.
pub type Pages = BTreeMap<u32, [u8; PAGE_BYTES]>;

/// The flash pages of an ELF's loadable segments (those with file bytes
/// and a load address in flash). Fails if there is none, if a segment runs
/// out of the flash window, or if the image does not start at
/// `FLASH_START` (where the bootrom looks for the second-stage loader).
pub fn pages_of_elf(elf: &[u8]) -> Result<Pages, String> {
    let file = ElfFile32::<LittleEndian>::parse(elf).map_err(|e| format!("not an ELF32: {e}"))?;
    let endian = file.endian();
    let headers = file
        .elf_header()
        .program_headers(endian, elf)
        .map_err(|e| format!("unreadable program headers: {e}"))?;
    let mut pages = Pages::new();
    for ph in headers {
        let size = ph.p_filesz(endian);
        if ph.p_type(endian) != PT_LOAD || size == 0 {
            continue;
        }
        let addr = ph.p_paddr(endian);
        if !(FLASH_START..FLASH_END).contains(&addr) {
            continue; // e.g. a RAM-only segment with file bytes: not flashed
        }
        if u64::from(addr) + u64::from(size) > u64::from(FLASH_END) {
            return Err(format!(
                "segment at {addr:#010x} ({size} B) runs past the flash window"
            ));
        }
        let data = ph
            .data(endian, elf)
            .map_err(|_| format!("segment at {addr:#010x}: bytes outside the file"))?;
        put(&mut pages, addr, data);
    }
    match pages.keys().next() {
        None => Err("no loadable segment in flash (is this the RP2040 firmware?)".into()),
        Some(&first) if first != FLASH_START => Err(format!(
            "image starts at {first:#010x}, not {FLASH_START:#010x}: no second-stage loader"
        )),
        Some(_) => Ok(pages),
    }
}

fn put(pages: &mut Pages, addr: u32, data: &[u8]) {
    for (i, &b) in data.iter().enumerate() {
        let a = addr + i as u32;
        let page = a & !(PAGE_BYTES as u32 - 1);
        pages.entry(page).or_insert([0; PAGE_BYTES])[(a - page) as usize] = b;
    }
}

/// The UF2 file of `pages`: one block per page, in address order.
pub fn uf2_of_pages(pages: &Pages) -> Vec<u8> {
    let count = pages.len() as u32;
    let mut out = Vec::with_capacity(pages.len() * BLOCK_BYTES);
    for (n, (&addr, page)) in pages.iter().enumerate() {
        let header = [
            MAGIC_START0,
            MAGIC_START1,
            FLAG_FAMILY_ID,
            addr,
            PAGE_BYTES as u32,
            n as u32,
            count,
            RP2040_FAMILY_ID,
        ];
        for word in header {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(page);
        out.resize(out.len() + (476 - PAGE_BYTES), 0);
        out.extend_from_slice(&MAGIC_END.to_le_bytes());
    }
    out
}

/// `elf` converted, written to `uf2`; returns the block count.
pub fn write(elf: &Path, uf2: &Path) -> Result<usize, String> {
    let data = std::fs::read(elf).map_err(|e| {
        format!(
            "cannot read firmware ELF {}: {e} (build it with `cargo fw`)",
            elf.display()
        )
    })?;
    let pages = pages_of_elf(&data).map_err(|e| format!("{}: {e}", elf.display()))?;
    std::fs::write(uf2, uf2_of_pages(&pages)).map_err(|e| format!("{}: {e}", uf2.display()))?;
    Ok(pages.len())
}

/// Where a board in BOOTSEL mode is mounted: a folder named RPI-RP2 that
/// holds the bootrom's INFO_UF2.TXT, under the usual mount roots (udisks
/// on Linux, macOS's /Volumes), or `SWIMBOT_UF2_DRIVE` if set.
pub fn find_drive() -> Option<std::path::PathBuf> {
    if let Some(dir) = std::env::var_os("SWIMBOT_UF2_DRIVE") {
        return Some(dir.into());
    }
    let user = std::env::var("USER").unwrap_or_default();
    let roots = [
        format!("/media/{user}"),
        format!("/run/media/{user}"),
        "/media".to_string(),
        "/mnt".to_string(),
        "/Volumes".to_string(),
    ];
    roots
        .iter()
        .map(|r| Path::new(r).join("RPI-RP2"))
        .find(|d| d.join("INFO_UF2.TXT").is_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(block: &[u8], i: usize) -> u32 {
        u32::from_le_bytes(block[4 * i..4 * i + 4].try_into().unwrap())
    }

    /// A minimal little-endian ELF32 (ARM) with the given PT_LOAD segments
    /// (paddr, vaddr, bytes), laid out after the headers.
    fn elf(segments: &[(u32, u32, Vec<u8>)]) -> Vec<u8> {
        let phoff = 52u32;
        let data_start = phoff + 32 * segments.len() as u32;
        let mut out = Vec::new();
        out.extend_from_slice(&[0x7f, b'E', b'L', b'F', 1, 1, 1, 0]);
        out.extend_from_slice(&[0; 8]);
        out.extend_from_slice(&2u16.to_le_bytes()); // ET_EXEC
        out.extend_from_slice(&40u16.to_le_bytes()); // EM_ARM
        out.extend_from_slice(&1u32.to_le_bytes());
        out.extend_from_slice(&FLASH_START.to_le_bytes()); // entry
        out.extend_from_slice(&phoff.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes()); // shoff
        out.extend_from_slice(&0u32.to_le_bytes()); // flags
        out.extend_from_slice(&52u16.to_le_bytes());
        out.extend_from_slice(&32u16.to_le_bytes());
        out.extend_from_slice(&(segments.len() as u16).to_le_bytes());
        out.extend_from_slice(&40u16.to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
        let mut offset = data_start;
        for (paddr, vaddr, bytes) in segments {
            for w in [
                PT_LOAD,
                offset,
                *vaddr,
                *paddr,
                bytes.len() as u32,
                bytes.len() as u32,
                5,
                4,
            ] {
                out.extend_from_slice(&w.to_le_bytes());
            }
            offset += bytes.len() as u32;
        }
        for (_, _, bytes) in segments {
            out.extend_from_slice(bytes);
        }
        out
    }

    #[test]
    fn blocks_carry_the_rp2040_header_and_pages_from_flash_start() {
        let text: Vec<u8> = (0..700u32).map(|i| (i * 7) as u8).collect();
        // .data: loaded at its flash address, runs in RAM.
        let data = vec![0xAB; 10];
        let pages = pages_of_elf(&elf(&[
            (FLASH_START, FLASH_START, text.clone()),
            (FLASH_START + 0x400, 0x2000_0000, data.clone()),
        ]))
        .unwrap();
        let uf2 = uf2_of_pages(&pages);
        // 700 B -> pages 0, 0x100, 0x200; .data -> page 0x400.
        assert_eq!(uf2.len(), 4 * BLOCK_BYTES);
        let mut image = vec![0u8; 0x500];
        for (n, block) in uf2.chunks(BLOCK_BYTES).enumerate() {
            assert_eq!(word(block, 0), MAGIC_START0);
            assert_eq!(word(block, 1), MAGIC_START1);
            assert_eq!(word(block, 2), FLAG_FAMILY_ID);
            assert_eq!(word(block, 4), 256, "payload");
            assert_eq!(word(block, 5), n as u32, "block number");
            assert_eq!(word(block, 6), 4, "block count");
            assert_eq!(word(block, 7), RP2040_FAMILY_ID);
            assert_eq!(word(block, 127), MAGIC_END);
            let addr = word(block, 3);
            assert_eq!(addr % 256, 0);
            let at = (addr - FLASH_START) as usize;
            image[at..at + 256].copy_from_slice(&block[32..288]);
        }
        assert_eq!(word(&uf2, 3), FLASH_START, "first block at flash start");
        assert_eq!(&image[..700], &text[..], "text round-trips");
        assert!(image[700..0x300].iter().all(|&b| b == 0), "page padding");
        assert_eq!(&image[0x400..0x40a], &data[..], ".data at its load address");
    }

    #[test]
    fn images_not_starting_at_flash_or_without_flash_are_refused() {
        let e = pages_of_elf(&elf(&[(
            FLASH_START + 0x100,
            FLASH_START + 0x100,
            vec![1; 4],
        )]));
        assert!(e.unwrap_err().contains("second-stage"));
        let e = pages_of_elf(&elf(&[(0x2000_0000, 0x2000_0000, vec![1; 4])]));
        assert!(e.unwrap_err().contains("no loadable segment"));
        assert!(pages_of_elf(b"not an elf").unwrap_err().contains("ELF32"));
    }

    /// The real firmware, when it has been built: its UF2 holds exactly the
    /// bytes of its loadable segments, block by block.
    #[test]
    fn the_built_firmware_round_trips() {
        let path = super::super::workspace_root().join(super::super::FW_ELF);
        let Ok(elf) = std::fs::read(&path) else {
            eprintln!("skipped: {} not built", path.display());
            return;
        };
        let pages = pages_of_elf(&elf).unwrap();
        let uf2 = uf2_of_pages(&pages);
        assert_eq!(uf2.len(), pages.len() * BLOCK_BYTES);
        let file = ElfFile32::<LittleEndian>::parse(&*elf).unwrap();
        let endian = file.endian();
        let mut by_addr = std::collections::HashMap::new();
        for block in uf2.chunks(BLOCK_BYTES) {
            by_addr.insert(word(block, 3), block[32..288].to_vec());
        }
        let mut checked = 0;
        for ph in file.elf_header().program_headers(endian, &*elf).unwrap() {
            if ph.p_type(endian) != PT_LOAD || ph.p_filesz(endian) == 0 {
                continue;
            }
            let base = ph.p_paddr(endian);
            for (i, &b) in ph.data(endian, &*elf).unwrap().iter().enumerate() {
                let a = base + i as u32;
                let page = &by_addr[&(a & !255)];
                assert_eq!(page[(a & 255) as usize], b, "byte at {a:#010x}");
                checked += 1;
            }
        }
        assert!(checked > 1024, "a real image: {checked} bytes");
    }
}
