//! Flash program and erase through the boot ROM: the run log's slots and
//! the pairing sector (offsets in `board`, regions in `memory.x`). While
//! the ROM talks to the flash chip no code or data can be fetched from it
//! (XIP is off), so each operation runs from RAM with every interrupt masked
//! but the IR/Hall edge interrupt, whose handler and vector are in RAM:
//! a page program stalls the chip for up to 3 ms (W25Q16JV: 0.4 ms
//! typical), a 64 KiB block erase for up to 2 s (150 ms typical), a 4 KiB
//! sector erase up to 400 ms (45 ms typical). The PWM keeps running in
//! hardware throughout; erases are only asked for while the motor is off
//! with the gate low (`PassOutput::may_erase_flash`), and they lengthen the
//! watchdog for their duration and restore it after.
//!
//! Hand-written rather than the `rp2040-flash` crate: its 0.6 release is
//! built on rp2040-hal 0.11, the firmware on 0.12. The sequence is the
//! C SDK's `flash_range_erase`/`flash_range_program` (connect, exit XIP,
//! erase or program, flush the cache, re-enter XIP) and the assembly that
//! of rp2040-flash (MIT/Apache-2.0), so no call leaves RAM in between.
//! Re-entering XIP with the ROM's `flash_enter_cmd_xip` gives the same
//! plain 03h read mode as the board's boot2 (`BOOT_LOADER_GENERIC_03H`).
//!
//! With the `emulator` feature (no boot ROM in the emulator's route (b))
//! the ROM functions do not exist: programs and erases do nothing there.

use crate::board;
use core::cell::RefCell;
use rp2040_hal::Watchdog;
use swimbot_shared::run_log::store::{LogFlash, BLOCK_LEN, PAGE_LEN};

/// Where flash appears in the address space (XIP, cached).
const XIP_BASE: u32 = 0x1000_0000;
/// Watchdog period while an erase stalls the chip: the slowest 64 KiB
/// block erase (2 s) with margin, within the RP2040's 8.3 s maximum
/// (0xFFFFFF / 2 us).
const ERASE_WATCHDOG_MS: u32 = 3_000;

/// The ROM's flash functions, looked up (from flash) before the stall.
#[cfg(not(feature = "emulator"))]
#[repr(C)]
struct RomFunctions {
    connect: unsafe extern "C" fn(),
    exit_xip: unsafe extern "C" fn(),
    erase: Option<unsafe extern "C" fn(u32, usize, u32, u8)>,
    program: Option<unsafe extern "C" fn(u32, *const u8, usize)>,
    flush: unsafe extern "C" fn(),
    enter_xip: unsafe extern "C" fn(),
}

/// Erase `len` bytes or program `data` at `offset` from the start of
/// flash, interrupts masked for the duration.
#[cfg(not(feature = "emulator"))]
fn rom_op(offset: u32, erase_len: u32, data: Option<&[u8; PAGE_LEN]>) {
    use rp2040_hal::rom_data;
    let f = RomFunctions {
        connect: rom_data::connect_internal_flash::ptr(),
        exit_xip: rom_data::flash_exit_xip::ptr(),
        erase: (erase_len > 0).then(rom_data::flash_range_erase::ptr),
        program: data.map(|_| rom_data::flash_range_program::ptr()),
        flush: rom_data::flash_flush_cache::ptr(),
        enter_xip: rom_data::flash_enter_cmd_xip::ptr(),
    };
    let (ptr, len) = match data {
        Some(d) => (d.as_ptr(), PAGE_LEN as u32),
        None => (core::ptr::null(), erase_len),
    };
    // SAFETY: only the IR/Hall interrupt is unmasked, and it and its vector
    // are in RAM (`ir.rs`, `RAM_VECTORS`); this core is the only one running
    // and no DMA reads flash, so nothing fetches from flash until XIP is
    // back; `ram_op` runs from RAM and calls only the ROM.
    with_only_ir_interrupt(|| unsafe { ram_op(offset, ptr, len, &f) });
}

/// The vector table while the flash is busy: a RAM copy of the one in flash
/// (VTOR needs 256-byte alignment for the RP2040's 16 + 32 entries).
#[cfg(not(feature = "emulator"))]
#[repr(C, align(256))]
struct Vectors([u32; 48]);

#[cfg(not(feature = "emulator"))]
static mut RAM_VECTORS: Vectors = Vectors([0; 48]);

/// Run `op` with every interrupt masked at the NVIC but the IR/Hall one,
/// whose handler runs from RAM, and the vector table in RAM: so edges are
/// still timestamped and queued while the flash is busy (a key pressed
/// during an erase is no longer lost).
#[cfg(not(feature = "emulator"))]
fn with_only_ir_interrupt(op: impl FnOnce()) {
    use cortex_m::peripheral::{NVIC, SCB};
    cortex_m::interrupt::free(|_| {
        // SAFETY: interrupts are masked while the NVIC and VTOR change; the
        // copy is of the live table, whose IO_IRQ_BANK0 entry is the RAM handler.
        unsafe {
            let (nvic, scb) = (&*NVIC::PTR, &*SCB::PTR);
            let vtor = scb.vtor.read();
            let table = &mut *core::ptr::addr_of_mut!(RAM_VECTORS);
            for (i, v) in table.0.iter_mut().enumerate() {
                *v = core::ptr::read_volatile((vtor as *const u32).add(i));
            }
            let enabled = nvic.iser[0].read();
            nvic.icer[0].write(!(1 << rp2040_hal::pac::Interrupt::IO_IRQ_BANK0 as u32));
            scb.vtor.write(table as *const Vectors as u32);
            cortex_m::interrupt::enable();
            op();
            cortex_m::interrupt::disable();
            scb.vtor.write(vtor);
            nvic.iser[0].write(enabled);
        }
    });
}

#[cfg(feature = "emulator")]
fn rom_op(_offset: u32, _erase_len: u32, _data: Option<&[u8; PAGE_LEN]>) {}

/// The stall itself, from RAM. Registers as in rp2040-flash's
/// `write_flash_inner`: r8-r10 keep the arguments across the ROM calls
/// (the ROM preserves them and r4-r7, where `f` is).
#[cfg(not(feature = "emulator"))]
#[inline(never)]
#[link_section = ".data.ram_func"]
unsafe fn ram_op(offset: u32, data: *const u8, len: u32, f: *const RomFunctions) {
    core::arch::asm!(
        "mov r8, r0",
        "mov r9, r2",
        "mov r10, r1",
        "ldr r4, [{f}, #0]",
        "blx r4", // connect_internal_flash()
        "ldr r4, [{f}, #4]",
        "blx r4", // flash_exit_xip()
        "mov r0, r8",
        "mov r1, r10",
        "movs r2, #1",
        "lsls r2, r2, #16", // 64 KiB blocks where aligned, sectors elsewhere
        "movs r3, #0xd8",   // the block erase command
        "ldr r4, [{f}, #8]",
        "cmp r4, #0",
        "beq 1f",
        "blx r4", // flash_range_erase(offset, len, 1 << 16, 0xd8)
        "1:",
        "mov r0, r8",
        "mov r1, r9",
        "mov r2, r10",
        "ldr r4, [{f}, #12]",
        "cmp r4, #0",
        "beq 2f",
        "blx r4", // flash_range_program(offset, data, len)
        "2:",
        "ldr r4, [{f}, #16]",
        "blx r4", // flash_flush_cache()
        "ldr r4, [{f}, #20]",
        "blx r4", // flash_enter_cmd_xip()
        f = in(reg) f,
        in("r0") offset,
        in("r2") data,
        in("r1") len,
        out("r3") _,
        out("r4") _,
        out("r8") _,
        out("r9") _,
        out("r10") _,
        clobber_abi("C"),
    );
}

/// Read flash through XIP.
pub fn read(offset: u32, buf: &mut [u8]) {
    let end = offset as usize + buf.len();
    if end > board::FLASH_BYTES as usize {
        buf.fill(0xFF);
        return;
    }
    // SAFETY: inside the 2 MiB flash window (checked), read-only, and no
    // flash operation runs (they mask interrupts and return first).
    let src = unsafe { core::slice::from_raw_parts((XIP_BASE + offset) as *const u8, buf.len()) };
    buf.copy_from_slice(src);
}

/// Program one page at `offset` from the start of flash.
pub fn program_page(offset: u32, page: &[u8; PAGE_LEN]) {
    rom_op(offset, 0, Some(page));
}

/// Erase `len` bytes at `offset` (sector-aligned), the watchdog lengthened
/// meanwhile. The caller has checked that the motor is off.
pub fn erase(watchdog: &mut Watchdog, offset: u32, len: u32) {
    // One load of the counter with the long period (RP2040-E1: it counts
    // down twice per microsecond tick, hence the factor 2, as the HAL's
    // `start` does); the feed after the erase reloads the usual 80 ms.
    // SAFETY: a write of the watchdog's LOAD register only.
    let wd = unsafe { &*rp2040_hal::pac::WATCHDOG::ptr() };
    wd.load()
        .write(|w| unsafe { w.bits(ERASE_WATCHDOG_MS * 1_000 * 2) });
    rom_op(offset, len, None);
    watchdog.feed();
}

/// The run log's region, for `LogStore`; it holds the watchdog, which an
/// erase lengthens and a long readout feeds.
pub struct LogRegion<'a> {
    watchdog: RefCell<&'a mut Watchdog>,
}

impl<'a> LogRegion<'a> {
    pub fn new(watchdog: &'a mut Watchdog) -> Self {
        Self {
            watchdog: RefCell::new(watchdog),
        }
    }

    pub fn feed(&self) {
        self.watchdog.borrow().feed();
    }
}

impl LogFlash for LogRegion<'_> {
    fn read(&self, offset: u32, buf: &mut [u8]) {
        read(board::LOG_FLASH_OFFSET + offset, buf);
    }

    fn program_page(&mut self, offset: u32, page: &[u8; PAGE_LEN]) {
        program_page(board::LOG_FLASH_OFFSET + offset, page);
    }

    fn erase_block(&mut self, offset: u32) {
        erase(
            self.watchdog.get_mut(),
            board::LOG_FLASH_OFFSET + offset,
            BLOCK_LEN,
        );
    }
}
