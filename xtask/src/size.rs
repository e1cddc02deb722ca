//! Flash and static RAM use of an RP2040 ELF, read from its section table.
//!
//! Flash holds every allocated section placed in the XIP window plus the
//! load image of `.data`; static RAM is every allocated section placed in
//! SRAM (`.data`, `.bss`, `.uninit`, where defmt-rtt keeps its buffer).

use object::{Object, ObjectSection, SectionFlags};
use std::path::Path;

const FLASH_START: u64 = 0x1000_0000;
const FLASH_END: u64 = 0x1100_0000;
pub const RAM_START: u64 = 0x2000_0000;
const RAM_END: u64 = 0x2004_2000;
const SHF_ALLOC: u64 = 0x2;

pub struct Usage {
    pub flash_bytes: u64,
    pub ram_bytes: u64,
    pub sections: Vec<(String, u64, &'static str)>,
    /// The lowest address of a static in RAM: above the RAM's origin only
    /// when flip-link has put the stack below the statics.
    pub lowest_static_ram: Option<u64>,
}

pub fn measure(elf: &Path) -> Result<Usage, String> {
    let data = std::fs::read(elf).map_err(|e| {
        format!(
            "cannot read firmware ELF {}: {e} (build it with `cargo fw`)",
            elf.display()
        )
    })?;
    let file = object::File::parse(&*data)
        .map_err(|e| format!("{} is not a readable ELF: {e}", elf.display()))?;
    let mut usage = Usage {
        flash_bytes: 0,
        ram_bytes: 0,
        sections: Vec::new(),
        lowest_static_ram: None,
    };
    for section in file.sections() {
        let SectionFlags::Elf { sh_flags } = section.flags() else {
            continue;
        };
        if sh_flags & SHF_ALLOC == 0 || section.size() == 0 {
            continue;
        }
        let name = section.name().unwrap_or("?").to_string();
        let size = section.size();
        let addr = section.address();
        let in_ram = (RAM_START..RAM_END).contains(&addr);
        let in_flash = (FLASH_START..FLASH_END).contains(&addr);
        // NOBITS sections (.bss, .uninit) take no bytes in the image.
        let has_file_bytes = !matches!(
            section.kind(),
            object::SectionKind::UninitializedData | object::SectionKind::UninitializedTls
        );
        if in_flash {
            usage.flash_bytes += size;
            usage.sections.push((name, size, "flash"));
        } else if in_ram {
            usage.ram_bytes += size;
            usage.lowest_static_ram = Some(usage.lowest_static_ram.map_or(addr, |a| a.min(addr)));
            // Initialised RAM data is copied from flash at reset.
            if has_file_bytes {
                usage.flash_bytes += size;
                usage.sections.push((name, size, "RAM + flash image"));
            } else {
                usage.sections.push((name, size, "RAM"));
            }
        }
    }
    Ok(usage)
}
