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
//!
//! XIP is re-entered by running a RAM copy of the image's own boot2
//! (`BOOT2_RAM`), as pico-sdk's `flash_enable_xip_via_boot2` and
//! embassy-rp do, not the ROM's `flash_enter_cmd_xip`: that one sets the
//! SSI's clock divider and read command to its own slow defaults, so after
//! the first flash write every cache miss would have cost more than at
//! boot. boot2 returns to its caller when called with a non-zero LR (its
//! `exit_from_boot2`), and its code is position-independent.
//!
//! The flash chip's 64-bit unique ID (command 4Bh, W25Q16JV 8.2.31) is
//! read once at boot (`unique_id`), the same way (the C SDK's
//! `flash_get_unique_id`): from RAM, with XIP off and chip select forced
//! by the QSPI pad's override.
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
        enter_xip: boot2_in_ram(),
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
/// during an erase is not lost).
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

/// boot2 (256 bytes, the last 4 its CRC), copied to RAM with `.data`
/// at reset: re-run after each flash operation to re-enter XIP with
/// boot2's own SSI settings. Word-aligned for the Thumb code in it.
#[cfg(not(feature = "emulator"))]
#[repr(C, align(4))]
struct Boot2([u8; 256]);

#[cfg(not(feature = "emulator"))]
#[link_section = ".data.boot2_copy"]
static BOOT2_RAM: Boot2 = Boot2(crate::BOOT2_IMAGE);

/// `BOOT2_RAM`'s entry as a function (Thumb bit set).
#[cfg(not(feature = "emulator"))]
fn boot2_in_ram() -> unsafe extern "C" fn() {
    let entry = core::ptr::addr_of!(BOOT2_RAM) as usize | 1;
    // SAFETY: the address of boot2's first instruction, in RAM; boot2
    // returns to its caller (non-zero LR).
    unsafe { core::mem::transmute::<usize, unsafe extern "C" fn()>(entry) }
}

/// The flash chip's unique ID (command 4Bh: four dummy bytes, then eight
/// ID bytes). Called once at boot, interrupts masked, before anything
/// else could fetch from flash.
#[cfg(not(feature = "emulator"))]
pub fn unique_id() -> [u8; 8] {
    use rp2040_hal::rom_data;
    let f = IdFunctions {
        connect: rom_data::connect_internal_flash::ptr(),
        exit_xip: rom_data::flash_exit_xip::ptr(),
        flush: rom_data::flash_flush_cache::ptr(),
        enter_xip: boot2_in_ram(),
    };
    let mut buf = [0u8; 13];
    buf[0] = 0x4b;
    // SAFETY: interrupts masked and the other core asleep, so nothing
    // fetches from flash until `ram_unique_id` has re-entered XIP; it runs
    // from RAM and calls only the ROM and the RAM boot2.
    cortex_m::interrupt::free(|_| unsafe { ram_unique_id(&f, buf.as_mut_ptr(), buf.len()) });
    let mut id = [0u8; 8];
    id.copy_from_slice(&buf[5..]);
    id
}

/// The emulator's image has no ROM: a fixed ID.
#[cfg(feature = "emulator")]
pub fn unique_id() -> [u8; 8] {
    [0; 8]
}

#[cfg(not(feature = "emulator"))]
#[repr(C)]
struct IdFunctions {
    connect: unsafe extern "C" fn(),
    exit_xip: unsafe extern "C" fn(),
    flush: unsafe extern "C" fn(),
    enter_xip: unsafe extern "C" fn(),
}

/// The command exchange of pico-sdk's `flash_do_cmd`: chip select forced
/// low through IO_QSPI's SS pad override, `len` bytes of `buf` sent, the
/// same number received into it (at most 14 in flight: the SSI's FIFOs are
/// 16 deep), chip select high again. Only volatile accesses and calls
/// through `f`, so nothing here is fetched from flash (checked in the
/// disassembly: no `bl` to flash).
#[cfg(not(feature = "emulator"))]
#[inline(never)]
#[link_section = ".data.ram_func"]
unsafe fn ram_unique_id(f: &IdFunctions, buf: *mut u8, len: usize) {
    const SS_CTRL: *mut u32 = 0x4001_800c as *mut u32; // IO_QSPI GPIO_QSPI_SS_CTRL
    const OUTOVER_MASK: u32 = 3 << 8;
    const OUTOVER_LOW: u32 = 2 << 8;
    const OUTOVER_HIGH: u32 = 3 << 8;
    const SSI_SR: *const u32 = 0x1800_0028 as *const u32;
    const SSI_DR0: *mut u32 = 0x1800_0060 as *mut u32;
    const TFNF: u32 = 1 << 1;
    const RFNE: u32 = 1 << 3;
    (f.connect)();
    (f.exit_xip)();
    let ss = core::ptr::read_volatile(SS_CTRL) & !OUTOVER_MASK;
    core::ptr::write_volatile(SS_CTRL, ss | OUTOVER_LOW);
    let (mut tx, mut rx) = (0usize, 0usize);
    while rx < len {
        let sr = core::ptr::read_volatile(SSI_SR);
        if sr & TFNF != 0 && tx < len && tx - rx < 14 {
            core::ptr::write_volatile(SSI_DR0, u32::from(core::ptr::read_volatile(buf.add(tx))));
            tx += 1;
        }
        if sr & RFNE != 0 && rx < tx {
            core::ptr::write_volatile(buf.add(rx), core::ptr::read_volatile(SSI_DR0) as u8);
            rx += 1;
        }
    }
    core::ptr::write_volatile(SS_CTRL, ss | OUTOVER_HIGH);
    (f.flush)();
    (f.enter_xip)();
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
        "blx r4", // boot2 (RAM copy): XIP as at boot
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
