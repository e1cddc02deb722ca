//! IR receiver edges: the GPIO interrupt timestamps every edge of the
//! receiver output with the 1 MHz timer and queues it; the main loop drains
//! the queue into the shared NEC decoder.
//!
//! Decoding stays out of the interrupt so that the interrupt stays short
//! (measured in the rp2040js emulator: 165 cycles per edge, 1.3 us at
//! 125 MHz, against NEC's 562 us time unit; the emulator run prints the
//! current figure) and all protocol logic runs in
//! the (watchdog-guarded) main loop; the timestamp is what must be taken
//! promptly, and the interrupt does.

use crate::board;
use core::cell::RefCell;
use critical_section::Mutex;
use embedded_hal::digital::InputPin;
use heapless::Deque;
use rp2040_hal::gpio::{bank0::Gpio15, FunctionSioInput, Interrupt, Pin, PullUp};
use rp2040_hal::pac::{self, interrupt};
use rp2040_hal::Timer;
use swimbot_shared::Level;

const _: () = assert!(board::IR_GPIO == 15, "the typed pin below is GPIO15");

/// GPIO15's EDGE_LOW and EDGE_HIGH bits in IO_BANK0's INTR1 (4 bits per
/// pin: level low, level high, edge low, edge high; GPIO8 at bit 0).
const INTR_REG: usize = board::IR_GPIO as usize / 8;
const EDGE_LOW_BIT: u32 = 1 << ((board::IR_GPIO as u32 % 8) * 4 + 2);
const EDGE_HIGH_BIT: u32 = EDGE_LOW_BIT << 1;

pub type IrPin = Pin<Gpio15, FunctionSioInput, PullUp>;

/// A frame is 68 edges over 68 ms; the main loop drains the queue every
/// pass (well under 1 ms), so 32 entries is ample margin. On overflow edges
/// are dropped and counted: the decoder then rejects the damaged frame.
const QUEUE_LEN: usize = 32;

#[derive(Clone, Copy)]
pub struct Edge {
    pub level: Level,
    pub t_us: u32,
}

struct Isr {
    pin: IrPin,
    timer: Timer,
}

static ISR: Mutex<RefCell<Option<Isr>>> = Mutex::new(RefCell::new(None));
static EDGES: Mutex<RefCell<Deque<Edge, QUEUE_LEN>>> = Mutex::new(RefCell::new(Deque::new()));
static DROPPED: Mutex<RefCell<u32>> = Mutex::new(RefCell::new(0));

/// Hand the pin to the interrupt and enable both edges.
pub fn start(pin: IrPin, timer: Timer) {
    pin.set_interrupt_enabled(Interrupt::EdgeLow, true);
    pin.set_interrupt_enabled(Interrupt::EdgeHigh, true);
    critical_section::with(|cs| ISR.borrow_ref_mut(cs).replace(Isr { pin, timer }));
    // SAFETY: the handler only touches state behind critical sections, and
    // that state is initialised above.
    unsafe { pac::NVIC::unmask(pac::Interrupt::IO_IRQ_BANK0) };
}

/// The oldest queued edge.
pub fn pop() -> Option<Edge> {
    critical_section::with(|cs| EDGES.borrow_ref_mut(cs).pop_front())
}

/// Drain the queue as (level, timestamp) pairs, oldest first.
pub fn drain() -> impl Iterator<Item = (Level, u32)> {
    core::iter::from_fn(|| pop().map(|e| (e.level, e.t_us)))
}

/// Whether an edge is waiting (for the sleep check, inside its critical section).
pub fn has_edges(cs: critical_section::CriticalSection<'_>) -> bool {
    !EDGES.borrow_ref(cs).is_empty()
}

/// Edges lost to a full queue since the last call.
pub fn take_dropped() -> u32 {
    critical_section::with(|cs| core::mem::take(&mut *DROPPED.borrow_ref_mut(cs)))
}

#[interrupt]
fn IO_IRQ_BANK0() {
    critical_section::with(|cs| {
        let mut isr = ISR.borrow_ref_mut(cs);
        let Some(isr) = isr.as_mut() else { return };
        let t_us = isr.timer.get_counter_low();
        // Clear exactly the latches that were read: an edge latched between
        // the read and the clear stays pending and re-enters the handler,
        // instead of being cleared unseen.
        // SAFETY: INTR is write-1-to-clear; only GPIO15's edge bits are
        // written, and only this handler touches them.
        let intr = unsafe { &*pac::IO_BANK0::ptr() }.intr(INTR_REG);
        let latched = intr.read().bits() & (EDGE_LOW_BIT | EDGE_HIGH_BIT);
        intr.write(|w| unsafe { w.bits(latched) });
        let fell = latched & EDGE_LOW_BIT != 0;
        let rose = latched & EDGE_HIGH_BIT != 0;
        // Both latched: a pulse shorter than the interrupt latency. The
        // present level tells which came last.
        let now_high = isr.pin.is_high().unwrap_or(true);
        let mut queue = EDGES.borrow_ref_mut(cs);
        let mut push = |level| {
            if queue.push_back(Edge { level, t_us }).is_err() {
                let mut d = DROPPED.borrow_ref_mut(cs);
                *d = d.saturating_add(1);
            }
        };
        match (fell, rose, now_high) {
            (true, true, true) => {
                push(Level::Low);
                push(Level::High);
            }
            (true, true, false) => {
                push(Level::High);
                push(Level::Low);
            }
            (true, false, _) => push(Level::Low),
            (false, true, _) => push(Level::High),
            (false, false, _) => {}
        }
    });
}
