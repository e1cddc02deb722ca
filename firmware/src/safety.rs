//! Fail-safe stop: whatever went wrong (a panic, a HardFault), force the
//! motor gate low through the registers and reset the chip through the
//! watchdog. Nothing here trusts the state of the code that failed: no
//! HAL objects, no locks, only register writes that are valid in any state.
//!
//! Debug behaviour (decided): the watchdog does not pause for a debugger,
//! so a core halted at a breakpoint is reset after `WATCHDOG_MS` like a
//! hung one: a halted core can never leave the motor running. (The PAUSE_*
//! bits are set at reset; rp2040-hal's `Watchdog::start` writes CTRL from
//! that reset value, which kept them set and made its `pause_on_debug`
//! setting void; `watchdog_runs_under_debugger` clears them after `start`.)
//! Stepping through code on the bench therefore needs the watchdog
//! disabled in that build, by hand, with the motor disconnected.
//!
//! With the `probe` feature, panic-probe reports the panic over RTT
//! instead (then ends in `udf`, which faults into `HardFault` below, which
//! stops the motor as well).

use crate::board;
use rp2040_hal::pac;

/// Clear the watchdog's PAUSE_DBG0/DBG1/JTAG bits (see the module docs).
pub fn watchdog_runs_under_debugger() {
    // SAFETY: a read-modify-write of CTRL's pause bits only; the HAL's
    // `Watchdog` writes CTRL only in `start`/`disable`, both before this.
    let watchdog = unsafe { &*pac::WATCHDOG::ptr() };
    watchdog.ctrl().modify(|_, w| {
        w.pause_dbg0().clear_bit();
        w.pause_dbg1().clear_bit();
        w.pause_jtag().clear_bit()
    });
}

/// Force GPIO16 low and reset. Callable from any context, any state.
pub fn stop_and_reset() -> ! {
    force_gate_low();
    reset()
}

/// Motor gate low: PWM compare 0 and the pin taken back to SIO, output low.
fn force_gate_low() {
    cortex_m::interrupt::disable();
    let gate = 1u32 << board::MOTOR_PWM_GPIO;
    // SAFETY: plain register writes through the PAC; the caller (a fault or
    // panic handler) owns the machine from now on, and every write below
    // leaves the gate low whatever state the peripherals were in.
    unsafe {
        let pwm = &*pac::PWM::ptr();
        pwm.ch(0).cc().write(|w| w.bits(0));
        let sio = &*pac::SIO::ptr();
        sio.gpio_out_clr().write(|w| w.bits(gate));
        sio.gpio_oe_set().write(|w| w.bits(gate));
        let io = &*pac::IO_BANK0::ptr();
        io.gpio(usize::from(board::MOTOR_PWM_GPIO))
            .gpio_ctrl()
            .write(|w| w.funcsel().sio());
    }
}

/// Reset through the watchdog's trigger bit.
fn reset() -> ! {
    // SAFETY: as above.
    unsafe {
        // What a watchdog reset resets: everything but the oscillators (as
        // rp2040-hal's `Watchdog::start` sets it; set again in case the
        // fault came before the watchdog was started).
        let psm = &*pac::PSM::ptr();
        psm.wdsel().write(|w| {
            w.bits(0x0001_ffff);
            w.xosc().clear_bit();
            w.rosc().clear_bit()
        });
        let watchdog = &*pac::WATCHDOG::ptr();
        watchdog.ctrl().write(|w| w.trigger().set_bit());
    }
    loop {
        cortex_m::asm::nop();
    }
}

#[cfg(not(feature = "probe"))]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    // The gate first: logging could itself fail (a panic inside the logger).
    force_gate_low();
    if let Some(at) = info.location() {
        defmt::error!(
            "panic at {=str}:{=u32}: motor off, reset",
            at.file(),
            at.line()
        );
    }
    reset()
}

#[cortex_m_rt::exception]
unsafe fn HardFault(_frame: &cortex_m_rt::ExceptionFrame) -> ! {
    stop_and_reset()
}
