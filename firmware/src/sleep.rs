//! Sleep between passes of the main loop: the core waits for an interrupt
//! (WFI) until an IR edge arrives or a timer alarm, armed for
//! `WAKE_PERIOD_US` at each sleep, wakes it. Every decision still happens
//! in a main-loop pass; only the idle spinning between passes is gone.
//!
//! Why: a polling loop kept the core busy at 125 MHz between 1 ms events,
//! drawing the cell for nothing, and made the rp2040js emulator execute
//! every one of those idle instructions. Asleep, a simulated second costs
//! about a thousand passes instead of 125 million cycles.
//!
//! Race-free by construction: the alarm is armed and the IR queue checked
//! with interrupts masked (PRIMASK), and WFI wakes on a pending interrupt
//! even while masked, so neither an edge nor the alarm can slip in between
//! the check and the sleep; the handler runs once the mask is lifted.

use core::cell::RefCell;
use critical_section::Mutex;
use fugit::ExtU32;
use rp2040_hal::pac::{self, interrupt};
use rp2040_hal::timer::{Alarm, Alarm0};
use rp2040_hal::Timer;

use crate::{board, ir};

/// Longest sleep (`board::WAKE_PERIOD_US`): the main loop runs at least
/// this often (1 kHz), fine enough for the soft-start ramp, the LED
/// patterns and the battery samples.
use board::WAKE_PERIOD_US;

static ALARM: Mutex<RefCell<Option<Alarm0>>> = Mutex::new(RefCell::new(None));

/// Take alarm 0 of `timer` for the wake-up and enable its interrupt.
pub fn start(timer: &mut Timer) {
    // `alarm_0` is `None` only if taken before; nothing else takes it.
    let mut alarm = timer.alarm_0().unwrap();
    alarm.enable_interrupt();
    critical_section::with(|cs| ALARM.borrow_ref_mut(cs).replace(alarm));
    // SAFETY: the handler only touches state behind critical sections, and
    // that state is initialised above.
    unsafe { pac::NVIC::unmask(pac::Interrupt::TIMER_IRQ_0) };
}

/// Sleep until the next IR edge or for at most `wake_us` (capped at
/// `WAKE_PERIOD_US`); return at once if an edge is already queued.
pub fn until_next_event(wake_us: u32) {
    critical_section::with(|cs| {
        if let Some(alarm) = ALARM.borrow_ref_mut(cs).as_mut() {
            // At most 1 ms, far below the 2^32 us limit: cannot fail.
            let _ = alarm.schedule(wake_us.clamp(1, WAKE_PERIOD_US).micros());
        }
        if !ir::has_edges(cs) {
            cortex_m::asm::wfi();
        }
    });
}

#[interrupt]
fn TIMER_IRQ_0() {
    critical_section::with(|cs| {
        if let Some(alarm) = ALARM.borrow_ref_mut(cs).as_mut() {
            alarm.clear_interrupt();
        }
    });
}
