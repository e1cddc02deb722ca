//! On-target checks (`--features hil`, run by `cargo xtask hil` through
//! probe-rs): what only silicon can answer about the code the robot runs,
//! each printed over defmt-RTT with its measured number, the run ending in
//! a semihosting exit (code 0: all passed) that `probe-rs run` returns as
//! its own exit code. The motor gate stays low throughout: PWM slice 0
//! runs for its counter with its compare at 0, so its output never rises
//! (still: run it with the motor disconnected, bring-up checklist).
//!
//! 1. The flash chip's unique ID (the USB serial number) is read the same
//!    twice and is neither all 0x00 nor all 0xFF.
//! 2. A flash erase and page program, then XIP re-entered through the RAM
//!    copy of boot2: the data reads back through XIP, and the SSI's clock
//!    divider and frame settings are boot2's again (the ROM's
//!    `flash_enter_cmd_xip` would have changed them).
//! 3. The battery conversion's start against the PWM: over 2 000 starts at
//!    random targets, each after a flush of the XIP cache, the counter read
//!    right after the start exceeds the target by at most 64 counts (0.5 us
//!    at 125 MHz; the RAM loop's bound from its cycles is about 33).
//! 4. The idle speeds: Full -> Crystal -> Full, the relock timed; under
//!    2 ms, and the system clock measured by the frequency counter at
//!    125 MHz after it (12 MHz in between).

use crate::battery_adc;
use crate::flash;
use crate::power::{Power, Speed};
use rp2040_hal::pac;
use rp2040_hal::Watchdog;
use swimbot_shared::run_log::store::PAGE_LEN;

/// The first sector of the unused gap between the run log and the pairing
/// sector (memory.x): nothing else ever writes it.
const SCRATCH_OFFSET: u32 = 0x1C_0000;
const SECTOR_LEN: u32 = 4096;
const SSI: usize = 0x1800_0000;
const XIP_FLUSH: *mut u32 = 0x1400_0004 as *mut u32;

/// Run every check; never returns (semihosting exit).
pub fn run(power: &mut Power, watchdog: &mut Watchdog) -> ! {
    let results = [
        ("flash unique id", flash_id()),
        (
            "xip after a flash write (boot2 in RAM)",
            xip_after_write(watchdog),
        ),
        ("battery conversion start vs PWM", adc_start_latency()),
        ("crystal speed and back", speeds(power)),
    ];
    let mut failed = 0;
    for (name, ok) in results {
        if ok {
            defmt::info!("hil: ok   {=str}", name);
        } else {
            defmt::error!("hil: FAIL {=str}", name);
            failed += 1;
        }
    }
    defmt::info!("hil: {} of {} failed", failed, results.len());
    exit(failed == 0)
}

fn flash_id() -> bool {
    let (a, b) = (flash::unique_id(), flash::unique_id());
    defmt::info!("hil: flash unique id {=[u8]:02x}", a);
    a == b && a != [0; 8] && a != [0xff; 8]
}

fn ssi_settings() -> [u32; 3] {
    // SAFETY: reads of SSI CTRLR0, BAUDR and SPI_CTRLR0.
    unsafe { [0x00, 0x14, 0xf4].map(|off| core::ptr::read_volatile((SSI + off) as *const u32)) }
}

fn xip_after_write(watchdog: &mut Watchdog) -> bool {
    let before = ssi_settings();
    flash::erase(watchdog, SCRATCH_OFFSET, SECTOR_LEN);
    let mut page = [0u8; PAGE_LEN];
    for (i, b) in page.iter_mut().enumerate() {
        *b = (i as u8).wrapping_mul(37) ^ 0x5a;
    }
    flash::program_page(SCRATCH_OFFSET, &page);
    let mut back = [0u8; PAGE_LEN];
    flash::read(SCRATCH_OFFSET, &mut back);
    let after = ssi_settings();
    defmt::info!(
        "hil: SSI CTRLR0/BAUDR/SPI_CTRLR0 {:#x} before, {:#x} after",
        before,
        after
    );
    back == page && before == after
}

fn adc_start_latency() -> bool {
    const TOP: u16 = 4999;
    // SAFETY: slice 0 configured through the PAC; its compare stays 0, so
    // its output (the gate) stays low.
    let pwm = unsafe { &*pac::PWM::ptr() };
    pwm.ch(0).top().write(|w| unsafe { w.bits(u32::from(TOP)) });
    pwm.ch(0).div().write(|w| unsafe { w.bits(1 << 4) });
    pwm.ch(0).cc().write(|w| unsafe { w.bits(0) });
    pwm.ch(0).csr().write(|w| w.en().set_bit());
    let mut worst = 0i32;
    let mut seed = 0x1234_5678u32;
    for _ in 0..2_000 {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let target = 100 + (seed >> 16) as i32 % (i32::from(TOP) - 300);
        // SAFETY: a write of XIP_CTRL FLUSH (safe while executing from
        // flash: the cache refills); the start's own code is in RAM.
        unsafe { core::ptr::write_volatile(XIP_FLUSH, 1) };
        let late = critical_section::with(|_| {
            battery_adc::start_at_phase_for_test(target);
            i32::from(pwm.ch(0).ctr().read().ctr().bits()) - target
        });
        worst = worst.max(late);
    }
    pwm.ch(0).csr().write(|w| w.en().clear_bit());
    defmt::info!(
        "hil: conversion start at most {} PWM counts after the target ({} ns)",
        worst,
        worst * 8
    );
    (0..=64).contains(&worst)
}

fn speeds(power: &mut Power) -> bool {
    // SAFETY: reads of the free-running timer.
    let timer = unsafe { &*pac::TIMER::ptr() };
    power.set_speed(Speed::Crystal);
    let slow = sys_khz();
    let t0 = timer.timerawl().read().bits();
    power.set_speed(Speed::Full);
    let relock_us = timer.timerawl().read().bits().wrapping_sub(t0);
    let fast = sys_khz();
    defmt::info!(
        "hil: clk_sys {} kHz on the crystal, {} kHz after the relock ({} us)",
        slow,
        fast,
        relock_us
    );
    relock_us < 2_000 && slow.abs_diff(12_000) < 100 && fast.abs_diff(125_000) < 500
}

/// clk_sys measured by the clock block's frequency counter (RP2040
/// datasheet 2.15.6, FC0 with clk_ref as reference).
fn sys_khz() -> u32 {
    // SAFETY: the frequency counter is used by nothing else.
    let clocks = unsafe { &*pac::CLOCKS::ptr() };
    // Bounded waits: a counter that never finishes reads as 0 kHz (a fail).
    let wait = |done: &dyn Fn() -> bool| (0..1_000_000).any(|_| done());
    if !wait(&|| clocks.fc0_status().read().running().bit_is_clear()) {
        return 0;
    }
    clocks.fc0_ref_khz().write(|w| unsafe { w.bits(12_000) });
    clocks.fc0_interval().write(|w| unsafe { w.bits(10) });
    clocks.fc0_min_khz().write(|w| unsafe { w.bits(0) });
    clocks
        .fc0_max_khz()
        .write(|w| unsafe { w.bits(0x1ff_ffff) });
    clocks.fc0_src().write(|w| unsafe { w.bits(0x08) }); // clk_sys
    if !wait(&|| clocks.fc0_status().read().done().bit_is_set()) {
        return 0;
    }
    clocks.fc0_result().read().khz().bits()
}

/// Semihosting SYS_EXIT (ADP_Stopped_ApplicationExit or RunTimeErrorUnknown):
/// `probe-rs run` ends with the matching exit code.
fn exit(ok: bool) -> ! {
    const APPLICATION_EXIT: u32 = 0x2_0026;
    const RUNTIME_ERROR: u32 = 0x2_0023;
    let reason = if ok { APPLICATION_EXIT } else { RUNTIME_ERROR };
    loop {
        // SAFETY: the semihosting call (BKPT 0xAB, r0 = SYS_EXIT, r1 = the
        // reason); with no debugger attached the BKPT faults into the
        // HardFault handler, which keeps the gate low and resets.
        unsafe {
            core::arch::asm!("bkpt 0xab", in("r0") 0x18u32, in("r1") reason);
        }
    }
}
