//! The firmware's flash layout checked in the linked image: `memory.x`'s
//! RUNLOG and PAIRING regions (its symbols `__swimbot_runlog_start`,
//! `__swimbot_runlog_end`, `__swimbot_pairing_start`) against the offsets
//! the code writes to (`shared/src/board.rs`, exported in the image as
//! `SWIMBOT_BOARD`: `LOGA`, `LOGS`, `LOGN`, `PAIR`), and the code's flash
//! below the run log. Two places state the layout; this keeps them one.

use object::{Object, ObjectSection, ObjectSymbol};
use std::path::Path;

const XIP_BASE: u64 = 0x1000_0000;

fn symbol(file: &object::File, name: &str) -> Result<u64, String> {
    file.symbols()
        .find(|s| s.name() == Ok(name))
        .map(|s| s.address())
        .ok_or_else(|| format!("the firmware ELF has no symbol {name} (memory.x defines it)"))
}

/// The value of `tag` in the image's SWIMBOT_BOARD facts.
fn fact(file: &object::File, tag: &[u8; 4]) -> Result<u64, String> {
    let sym = file
        .symbols()
        .find(|s| s.name() == Ok("SWIMBOT_BOARD"))
        .ok_or("the firmware ELF has no SWIMBOT_BOARD")?;
    let section = file
        .section_by_index(sym.section_index().ok_or("SWIMBOT_BOARD has no section")?)
        .map_err(|e| e.to_string())?;
    let data = section.data().map_err(|e| e.to_string())?;
    let at = (sym.address() - section.address()) as usize;
    let words: Vec<u32> = data
        .get(at..at + sym.size() as usize)
        .ok_or("SWIMBOT_BOARD lies outside its section")?
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect();
    let want = u32::from_be_bytes(*tag);
    words
        .chunks_exact(2)
        .skip(1)
        .find(|p| p[0] == want)
        .map(|p| u64::from(p[1]))
        .ok_or_else(|| format!("SWIMBOT_BOARD has no fact {}", String::from_utf8_lossy(tag)))
}

/// A line describing the layout, or what disagrees.
pub fn check(elf: &Path) -> Result<String, String> {
    let data = std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
    let file = object::File::parse(&*data).map_err(|e| e.to_string())?;
    let (start, end) = (
        symbol(&file, "__swimbot_runlog_start")?,
        symbol(&file, "__swimbot_runlog_end")?,
    );
    let pairing = symbol(&file, "__swimbot_pairing_start")?;
    let log_offset = fact(&file, b"LOGA")?;
    let log_len = fact(&file, b"LOGS")? * fact(&file, b"LOGN")?;
    let pairing_offset = fact(&file, b"PAIR")?;
    if start != XIP_BASE + log_offset || end - start != log_len {
        return Err(format!(
            "memory.x's RUNLOG is {start:#010x}..{end:#010x}, the code writes the log at \
             {:#010x}..{:#010x} (shared/src/board.rs)",
            XIP_BASE + log_offset,
            XIP_BASE + log_offset + log_len
        ));
    }
    if pairing != XIP_BASE + pairing_offset {
        return Err(format!(
            "memory.x's PAIRING is at {pairing:#010x}, the code writes the pairing at {:#010x}",
            XIP_BASE + pairing_offset
        ));
    }
    let code_end = file
        .sections()
        .filter(|s| (XIP_BASE..start).contains(&s.address()))
        .map(|s| s.address() + s.size())
        .max()
        .unwrap_or(XIP_BASE);
    if code_end > start {
        return Err(format!(
            "the image reaches {code_end:#010x}, into the run log at {start:#010x}"
        ));
    }
    Ok(format!(
        "flash layout: code up to {code_end:#010x}, run log {start:#010x}..{end:#010x}, pairing sector {pairing:#010x} (memory.x = shared/src/board.rs)"
    ))
}
