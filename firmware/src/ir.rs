//! IR receiver and Hall edges: the one bank-0 GPIO interrupt timestamps
//! every edge of the receiver output and of the two Hall latches with the
//! 1 MHz timer and queues it (one queue each); the main loop drains the
//! queues into the shared NEC decoder and rate estimator. A Hall edge
//! carries both latches' levels from one read of `SIO.GPIO_IN`, so the
//! quadrature state is consistent whichever latch switched.
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
use rp2040_hal::gpio::{
    bank0::{Gpio13, Gpio14, Gpio15},
    FunctionSioInput, Interrupt, Pin, PullUp,
};
use rp2040_hal::pac::{self, interrupt};
use rp2040_hal::Timer;
use swimbot_shared::{HallEdge, Level};

const _: () = assert!(board::IR_GPIO == 15, "the typed pin below is GPIO15");
const _: () = assert!(board::HALL_A_GPIO == 13 && board::HALL_B_GPIO == 14);

/// A pin's EDGE_LOW and EDGE_HIGH bits in IO_BANK0's INTRn (4 bits per
/// pin: level low, level high, edge low, edge high; 8 pins a register).
/// All three pins share INTR1 (asserted in `board`).
const INTR_REG: usize = board::IR_GPIO as usize / 8;
const fn edge_bits(gpio: u8) -> u32 {
    0b1100 << ((gpio as u32 % 8) * 4)
}
const EDGE_LOW_BIT: u32 = 1 << ((board::IR_GPIO as u32 % 8) * 4 + 2);
const EDGE_HIGH_BIT: u32 = EDGE_LOW_BIT << 1;
const HALL_BITS: u32 = edge_bits(board::HALL_A_GPIO) | edge_bits(board::HALL_B_GPIO);

pub type IrPin = Pin<Gpio15, FunctionSioInput, PullUp>;
pub type HallAPin = Pin<Gpio13, FunctionSioInput, PullUp>;
pub type HallBPin = Pin<Gpio14, FunctionSioInput, PullUp>;

/// A frame is 68 edges over 68 ms; the main loop drains the queue every
/// pass (well under 1 ms), so 32 entries is ample margin. On overflow edges
/// are dropped and counted: the decoder then rejects the damaged frame.
const QUEUE_LEN: usize = 32;

#[derive(Clone, Copy)]
pub struct Edge {
    pub level: Level,
    pub t_us: u32,
}

/// At the estimator's 10 Hz overspeed limit, 160 Hall edges a second:
/// 0.16 per 1 ms pass. On overflow edges are dropped and counted; the
/// estimator sees the skipped quadrature state and restarts its window.
const HALL_QUEUE_LEN: usize = 32;

struct Isr {
    pin: IrPin,
    timer: Timer,
    _hall: (HallAPin, HallBPin),
}

static ISR: Mutex<RefCell<Option<Isr>>> = Mutex::new(RefCell::new(None));
static EDGES: Mutex<RefCell<Deque<Edge, QUEUE_LEN>>> = Mutex::new(RefCell::new(Deque::new()));
static DROPPED: Mutex<RefCell<u32>> = Mutex::new(RefCell::new(0));
static HALL: Mutex<RefCell<Deque<HallEdge, HALL_QUEUE_LEN>>> =
    Mutex::new(RefCell::new(Deque::new()));
static HALL_DROPPED: Mutex<RefCell<u32>> = Mutex::new(RefCell::new(0));

/// Hand the pins to the interrupt and enable both edges of each.
pub fn start(pin: IrPin, hall: (HallAPin, HallBPin), timer: Timer) {
    for edge in [Interrupt::EdgeLow, Interrupt::EdgeHigh] {
        pin.set_interrupt_enabled(edge, true);
        hall.0.set_interrupt_enabled(edge, true);
        hall.1.set_interrupt_enabled(edge, true);
    }
    let isr = Isr {
        pin,
        timer,
        _hall: hall,
    };
    critical_section::with(|cs| ISR.borrow_ref_mut(cs).replace(isr));
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

/// Drain the Hall queue, oldest first.
pub fn drain_hall() -> impl Iterator<Item = HallEdge> {
    core::iter::from_fn(|| critical_section::with(|cs| HALL.borrow_ref_mut(cs).pop_front()))
}

/// Hall edges lost to a full queue since the last call.
pub fn take_hall_dropped() -> u32 {
    critical_section::with(|cs| core::mem::take(&mut *HALL_DROPPED.borrow_ref_mut(cs)))
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
        let all = intr.read().bits() & (EDGE_LOW_BIT | EDGE_HIGH_BIT | HALL_BITS);
        intr.write(|w| unsafe { w.bits(all) });
        if all & HALL_BITS != 0 {
            hall_edge(cs, t_us);
        }
        let latched = all & (EDGE_LOW_BIT | EDGE_HIGH_BIT);
        if latched == 0 {
            return;
        }
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

/// Queue the Hall latches' present levels, read together. Both edges of
/// one latch within the interrupt latency (a bounce) leave the level where
/// it started: the estimator sees no step and ignores the entry.
fn hall_edge(cs: critical_section::CriticalSection<'_>, t_us: u32) {
    // SAFETY: a read of the SIO input register, no side effects.
    let levels = unsafe { &*pac::SIO::ptr() }.gpio_in().read().bits();
    let edge = HallEdge {
        t_us,
        a: levels & (1 << board::HALL_A_GPIO) != 0,
        b: levels & (1 << board::HALL_B_GPIO) != 0,
    };
    if HALL.borrow_ref_mut(cs).push_back(edge).is_err() {
        let mut d = HALL_DROPPED.borrow_ref_mut(cs);
        *d = d.saturating_add(1);
    }
}
