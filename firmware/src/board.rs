//! The board's constants live in `swimbot_shared::board` (one place for
//! the firmware, the host simulation and the tests). This module re-exports
//! them and places them in the ELF as `SWIMBOT_BOARD`, where the emulator's
//! board model reads them (`tests/emulator/lib/facts.js`).

pub use swimbot_shared::board::*;

/// Kept in flash (a few hundred bytes) so that the image itself says which
/// pins, divider and timings it was built for.
#[used]
#[no_mangle]
pub static SWIMBOT_BOARD: [u32; EXPORT.len()] = EXPORT;
