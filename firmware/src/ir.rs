//! IR receiver and Hall edges: the one bank-0 GPIO interrupt timestamps
//! every edge of the receiver output and of the two Hall latches with the
//! 1 MHz timer and queues it (one queue each); the main loop drains the
//! queues into the shared NEC decoder and rate estimator. A Hall edge
//! carries both latches' levels from one read of `SIO.GPIO_IN`, so the
//! quadrature state is consistent whichever latch switched.
//!
//! The handler runs from RAM and touches only peripherals and the two
//! lock-free rings below, so it keeps taking edges while a flash erase or
//! page program has the flash busy (`flash.rs` leaves this interrupt alone
//! unmasked then, through a vector table in RAM): a key pressed during an
//! erase is queued and decoded when the erase ends.
//!
//! Decoding stays out of the interrupt so that the interrupt stays short
//! (measured in the rp2040js emulator: 89 cycles per edge, 0.7 us at
//! 125 MHz, against NEC's 562 us time unit; the emulator run prints the
//! current figure) and all protocol logic runs in
//! the (watchdog-guarded) main loop; the timestamp is what must be taken
//! promptly, and the interrupt does.

use crate::board;
use core::cell::UnsafeCell;
use core::sync::atomic::{compiler_fence, AtomicU32, Ordering};
use rp2040_hal::gpio::{
    bank0::{Gpio13, Gpio14, Gpio15},
    FunctionSioInput, Interrupt, Pin, PullUp,
};
use rp2040_hal::pac::{self, interrupt};
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

#[derive(Clone, Copy)]
pub struct Edge {
    pub level: Level,
    pub t_us: u32,
}

/// A single-producer (this interrupt), single-consumer (the main loop)
/// ring. Hand-written rather than heapless's `spsc::Queue`: the push has
/// to be inlined into the RAM handler with no call left into flash, which
/// `#[inline(always)]` here guarantees and a crate's generic code does not.
/// `N` is a power of two, so the masked index needs no bounds check (whose
/// panic path is in flash).
struct Ring<T: Copy, const N: usize> {
    slots: UnsafeCell<[T; N]>,
    /// Pushes so far (written by the interrupt only).
    head: AtomicU32,
    /// Pops so far (written by the main loop only).
    tail: AtomicU32,
    /// Entries lost to a full ring (the interrupt adds, the main loop takes
    /// them inside a critical section).
    dropped: AtomicU32,
}

// SAFETY: one producer (the interrupt) and one consumer (the main loop) on
// one core; a slot is written before `head` publishes it and read before
// `tail` frees it.
unsafe impl<T: Copy, const N: usize> Sync for Ring<T, N> {}

impl<T: Copy, const N: usize> Ring<T, N> {
    const MASK: u32 = {
        assert!(N.is_power_of_two());
        N as u32 - 1
    };

    const fn new(fill: T) -> Self {
        Self {
            slots: UnsafeCell::new([fill; N]),
            head: AtomicU32::new(0),
            tail: AtomicU32::new(0),
            dropped: AtomicU32::new(0),
        }
    }

    #[inline(always)]
    fn push(&self, v: T) {
        let head = self.head.load(Ordering::Relaxed);
        if head.wrapping_sub(self.tail.load(Ordering::Acquire)) >= N as u32 {
            let d = self.dropped.load(Ordering::Relaxed);
            self.dropped.store(d.saturating_add(1), Ordering::Relaxed);
            return;
        }
        // SAFETY: the slot is outside the consumer's range until `head` moves.
        unsafe { (*self.slots.get())[(head & Self::MASK) as usize] = v };
        compiler_fence(Ordering::Release);
        self.head.store(head.wrapping_add(1), Ordering::Release);
    }

    fn pop(&self) -> Option<T> {
        let tail = self.tail.load(Ordering::Relaxed);
        if tail == self.head.load(Ordering::Acquire) {
            return None;
        }
        // SAFETY: the slot was published by `head` and is not reused until
        // `tail` moves past it.
        let v = unsafe { (*self.slots.get())[(tail & Self::MASK) as usize] };
        self.tail.store(tail.wrapping_add(1), Ordering::Release);
        Some(v)
    }

    fn is_empty(&self) -> bool {
        self.tail.load(Ordering::Relaxed) == self.head.load(Ordering::Acquire)
    }

    fn take_dropped(&self) -> u32 {
        critical_section::with(|_| {
            let d = self.dropped.load(Ordering::Relaxed);
            self.dropped.store(0, Ordering::Relaxed);
            d
        })
    }
}

/// A frame is 68 edges over 68 ms; the main loop drains the ring every
/// pass (well under 1 ms), so 32 entries is ample margin; a 150 ms block
/// erase (2 s at worst) holds the main loop, and a frame in it needs 68:
/// 128 entries. On overflow edges are dropped and counted: the decoder
/// then rejects the damaged frame.
// The fill values are all-zero bytes, so the rings go to .bss, not .data
// (whose initial image would cost flash).
static EDGES: Ring<Edge, 128> = Ring::new(Edge {
    level: Level::Low,
    t_us: 0,
});

/// At the estimator's 10 Hz overspeed limit, 160 Hall edges a second:
/// 0.16 per 1 ms pass. On overflow edges are dropped and counted; the
/// estimator sees the skipped quadrature state and restarts its window.
/// (The motor is off during an erase; a 3 ms page program meets one at most.)
static HALL: Ring<HallEdge, 32> = Ring::new(HallEdge {
    t_us: 0,
    a: false,
    b: false,
});

/// Enable both edges of each pin and the interrupt. The pins stay
/// configured; the handler reads them through the registers.
pub fn start(pin: IrPin, hall: (HallAPin, HallBPin)) {
    for edge in [Interrupt::EdgeLow, Interrupt::EdgeHigh] {
        pin.set_interrupt_enabled(edge, true);
        hall.0.set_interrupt_enabled(edge, true);
        hall.1.set_interrupt_enabled(edge, true);
    }
    // SAFETY: the handler only touches the rings, which are ready.
    unsafe { pac::NVIC::unmask(pac::Interrupt::IO_IRQ_BANK0) };
}

/// Drain the queue as (level, timestamp) pairs, oldest first.
pub fn drain() -> impl Iterator<Item = (Level, u32)> {
    core::iter::from_fn(|| EDGES.pop().map(|e| (e.level, e.t_us)))
}

/// Drain the Hall queue, oldest first.
pub fn drain_hall() -> impl Iterator<Item = HallEdge> {
    core::iter::from_fn(|| HALL.pop())
}

/// Hall edges lost to a full queue since the last call.
pub fn take_hall_dropped() -> u32 {
    HALL.take_dropped()
}

/// Whether an edge is waiting (for the sleep check, inside its critical section).
pub fn has_edges(_cs: critical_section::CriticalSection<'_>) -> bool {
    !EDGES.is_empty()
}

/// Edges lost to a full queue since the last call.
pub fn take_dropped() -> u32 {
    EDGES.take_dropped()
}

/// In RAM, and nothing it does calls into flash (registers, the rings):
/// it runs while a flash operation has the flash busy.
#[interrupt]
#[link_section = ".data.ram_irq"]
fn IO_IRQ_BANK0() {
    // SAFETY: reads of the timer, SIO input and IO_BANK0 interrupt
    // registers; INTR is write-1-to-clear, and only this handler writes
    // these pins' edge bits.
    let (timer, sio, io) = unsafe {
        (
            &*pac::TIMER::ptr(),
            &*pac::SIO::ptr(),
            &*pac::IO_BANK0::ptr(),
        )
    };
    let t_us = timer.timerawl().read().bits();
    // Clear exactly the latches that were read: an edge latched between
    // the read and the clear stays pending and re-enters the handler,
    // instead of being cleared unseen.
    let intr = io.intr(INTR_REG);
    let all = intr.read().bits() & (EDGE_LOW_BIT | EDGE_HIGH_BIT | HALL_BITS);
    intr.write(|w| unsafe { w.bits(all) });
    // Both latches' levels and the IR pin's from one read.
    let levels = sio.gpio_in().read().bits();
    if all & HALL_BITS != 0 {
        // Both edges of one latch within the interrupt latency (a bounce)
        // leave the level where it started: the estimator sees no step.
        HALL.push(HallEdge {
            t_us,
            a: levels & (1 << board::HALL_A_GPIO) != 0,
            b: levels & (1 << board::HALL_B_GPIO) != 0,
        });
    }
    let fell = all & EDGE_LOW_BIT != 0;
    let rose = all & EDGE_HIGH_BIT != 0;
    // Both latched: a pulse shorter than the interrupt latency (or edges
    // held back by masked interrupts). The present level tells which came last.
    let now_high = levels & (1 << board::IR_GPIO) != 0;
    let push = |level| EDGES.push(Edge { level, t_us });
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
}
