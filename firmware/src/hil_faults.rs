//! `hil-faults` images only (`cargo xtask hil` builds one; never flashed
//! to a robot): fault injection over the USB port, and the gate's fall
//! timed on the jig, for the on-target check of the fail-safes.
//!
//! The jig (firmware/README.md, "Fail-safe timing on the jig"): the motor
//! disconnected, GPIO16 (the gate) wired to GPIO17, a spare input. Core 1
//! runs `watch` from RAM for the whole run: at every falling edge of GPIO17
//! it stores the 1 MHz timer in watchdog SCRATCH7, so the last fall before
//! a reset survives it (SCRATCH4-7 are cleared by a power-on only; the
//! cut-off latch uses SCRATCH0-3, and SCRATCH4 stays 0, clear of the boot
//! ROM's watchdog-boot magic).
//!
//! Requests (beside `LOG`, `INFO`, `BOOTSEL`):
//! - `FAULT PANIC`, `FAULT HANG`, `FAULT OVERFLOW`: answered `OK FAULT`;
//!   once the answer is out, the gate is driven at 50 % (PWM compare
//!   written directly: the main loop, which holds the motor off with USB
//!   in, writes the compare only when its own duty changes) so that GPIO17
//!   sees edges; 100 ms later the injection time goes to SCRATCH6 and its
//!   kind to SCRATCH5, and the main loop panics, hangs, or recurses until
//!   the stack runs off the RAM (what `fault-test` does in the emulator).
//! - `FAULT RESULT`: what the previous boot recorded, read at this boot:
//!   `FAULT RESULT kind=K injected_us=I gate_fall_us=F reset=R` (`R`:
//!   `watchdog`, `force` or `other`), or `FAULT RESULT none`. The host
//!   (`xtask/src/hil.rs`) judges `F - I`.

use core::sync::atomic::{AtomicU32, Ordering};
use rp2040_hal::pac;

/// The jig's loopback input.
pub const LOOPBACK_GPIO: u32 = 17;
const SIO_GPIO_IN: *const u32 = 0xd000_0004 as *const u32;
const TIMERAWL: *const u32 = 0x4005_4028 as *const u32;
/// Watchdog SCRATCH5-7 (RP2040 datasheet 4.7.6: SCRATCH0 at 0x0c).
const SCRATCH5: *mut u32 = 0x4005_8020 as *mut u32;
const SCRATCH6: *mut u32 = 0x4005_8024 as *mut u32;
const SCRATCH7: *mut u32 = 0x4005_8028 as *mut u32;
/// SCRATCH5's upper half: this image's record, not a stray value.
const TAG: u32 = 0x5b1f_0000;
const KINDS: [&[u8]; 3] = [b"panic", b"hang", b"overflow"];
/// Time from the answer to the 50 % drive, and from it to the injection.
const ANSWER_US: u32 = 20_000;
const DRIVE_US: u32 = 100_000;

/// The previous boot's record, taken at boot: kind + 1 (0: none),
/// injection time, last gate fall, reset reason (0 other, 1 watchdog, 2 force).
static RECORD: [AtomicU32; 4] = [
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
    AtomicU32::new(0),
];

/// Core 1's loop, in RAM (it must not fetch from the flash that core 0
/// programs): the timer at each falling edge of the loopback input.
#[inline(never)]
#[link_section = ".data.ram_func"]
pub fn watch() -> ! {
    let mask = 1 << LOOPBACK_GPIO;
    let mut was_high = false;
    loop {
        // SAFETY: reads of SIO GPIO_IN and TIMERAWL, a write of SCRATCH7,
        // which nothing else writes in this image.
        unsafe {
            let high = core::ptr::read_volatile(SIO_GPIO_IN) & mask != 0;
            if was_high && !high {
                core::ptr::write_volatile(SCRATCH7, core::ptr::read_volatile(TIMERAWL));
            }
            was_high = high;
        }
    }
}

/// At boot, before core 1 starts: keep the previous boot's record, clear it.
pub fn take_record(watchdog_reset: bool, forced_reset: bool) {
    // SAFETY: core 1 is not running yet; these registers are this module's.
    let (kind, injected, fall) = unsafe {
        (
            core::ptr::read_volatile(SCRATCH5),
            core::ptr::read_volatile(SCRATCH6),
            core::ptr::read_volatile(SCRATCH7),
        )
    };
    if kind & 0xffff_0000 == TAG && (kind & 0xffff) < KINDS.len() as u32 {
        let reason = if forced_reset {
            2
        } else {
            u32::from(watchdog_reset)
        };
        for (slot, v) in RECORD
            .iter()
            .zip([(kind & 0xffff) + 1, injected, fall, reason])
        {
            slot.store(v, Ordering::Relaxed);
        }
    }
    // SAFETY: as above.
    unsafe {
        core::ptr::write_volatile(SCRATCH5, 0);
        core::ptr::write_volatile(SCRATCH7, 0);
    }
}

/// A `FAULT ...` line being typed on the port; the injection it armed.
#[derive(Default)]
pub struct Faults {
    line: heapless::Vec<u8, 16>,
    overflow: bool,
    /// (kind, when the answer went out: the start of the schedule).
    armed: Option<(u32, u32)>,
}

/// Bytes of the longest answer line.
pub const ANSWER_MAX: usize = 96;

impl Faults {
    /// One byte from the port; at a newline that ends a `FAULT` line, its
    /// answer (written into `out`, its length returned).
    pub fn push(&mut self, byte: u8, now_us: u32, out: &mut [u8; ANSWER_MAX]) -> Option<usize> {
        if byte != b'\n' {
            self.overflow |= self.line.push(byte).is_err();
            return None;
        }
        let line = self.line.clone();
        let overflow = self.overflow;
        self.line.clear();
        self.overflow = false;
        let line = line.strip_suffix(b"\r").unwrap_or(&line);
        let rest = line.strip_prefix(b"FAULT ").filter(|_| !overflow)?;
        let mut w = Writer { buf: out, len: 0 };
        if rest == b"RESULT" {
            result(&mut w);
        } else if let Some(k) = KINDS.iter().position(|k| rest.eq_ignore_ascii_case(k)) {
            self.armed = Some((k as u32, now_us));
            w.put(b"OK FAULT\n");
        } else {
            w.put(b"ERR fault kind\n");
        }
        Some(w.len)
    }

    /// Each pass: drive the gate, then inject, on the armed schedule.
    pub fn poll(&mut self, now_us: u32) {
        let Some((kind, from)) = self.armed else {
            return;
        };
        let since = now_us.wrapping_sub(from);
        if since >= ANSWER_US {
            drive_gate_half();
        }
        if since >= ANSWER_US + DRIVE_US {
            // SAFETY: this module's scratch registers.
            unsafe {
                core::ptr::write_volatile(SCRATCH6, core::ptr::read_volatile(TIMERAWL));
                core::ptr::write_volatile(SCRATCH5, TAG | kind);
            }
            inject(kind);
        }
    }
}

/// PWM slice 0 channel A's compare at half its TOP (RP2040 datasheet
/// 4.5.3: CH0_CC at 0x4005000c, CH0_TOP at 0x40050010).
fn drive_gate_half() {
    // SAFETY: the motor is disconnected on the jig (the precondition of this
    // image); the compare's A half only.
    let pwm = unsafe { &*pac::PWM::ptr() };
    let top = pwm.ch(0).top().read().bits() & 0xffff;
    pwm.ch(0)
        .cc()
        .modify(|r, w| unsafe { w.bits((r.bits() & 0xffff_0000) | top.div_ceil(2)) });
}

fn inject(kind: u32) -> ! {
    match kind {
        0 => panic!("hil-faults: injected panic"),
        1 =>
        {
            #[allow(clippy::empty_loop)]
            loop {}
        }
        _ => {
            overflow(0);
            unreachable!()
        }
    }
}

/// Recurses until the stack runs off the bottom of RAM (flip-link puts it
/// there), 64 bytes a frame; `black_box` keeps every frame real.
#[allow(unconditional_recursion)]
#[inline(never)]
fn overflow(depth: u32) -> u32 {
    let frame = core::hint::black_box([depth; 16]);
    overflow(depth + 1).wrapping_add(frame[(depth & 15) as usize])
}

fn result(w: &mut Writer) {
    let [kind, injected, fall, reason] = RECORD.each_ref().map(|a| a.load(Ordering::Relaxed));
    if kind == 0 {
        w.put(b"FAULT RESULT none\n");
        return;
    }
    w.put(b"FAULT RESULT kind=");
    w.put(KINDS[(kind - 1) as usize]);
    w.put(b" injected_us=");
    w.num(injected);
    w.put(b" gate_fall_us=");
    w.num(fall);
    w.put(b" reset=");
    w.put([&b"other"[..], b"watchdog", b"force"][reason as usize % 3]);
    w.put(b"\n");
}

struct Writer<'a> {
    buf: &'a mut [u8; ANSWER_MAX],
    len: usize,
}

impl Writer<'_> {
    fn put(&mut self, s: &[u8]) {
        let n = s.len().min(ANSWER_MAX - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&s[..n]);
        self.len += n;
    }

    fn num(&mut self, mut v: u32) {
        let mut digits = [0u8; 10];
        let mut i = digits.len();
        loop {
            i -= 1;
            digits[i] = b'0' + (v % 10) as u8;
            v /= 10;
            if v == 0 {
                break;
            }
        }
        self.put(&digits[i..]);
    }
}
