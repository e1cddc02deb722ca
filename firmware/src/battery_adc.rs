//! Battery voltage sensing: one ADC0 conversion of the divider tap per
//! call, taken at a fixed phase of the motor's PWM period.
//!
//! Why a fixed phase: each on-pulse draws about 0.5 A through the cell's
//! ~0.6 ohm, so the tap swings by ~0.35 V at 25 kHz, and a 2 us one-shot
//! conversion started at a random time reads either level (the emulator
//! measured every phase). The reading is taken in the middle of the
//! on-pulse: the loaded voltage, which is what both users need (the motor
//! sees `duty x loaded voltage`, so the compensation is exact, and the
//! cut-off is specified under load). By mid-pulse the current has settled:
//! the motor's L/R is 3.6 us, and a running motor's pulses are 28-36 us
//! long at 25 kHz. With the motor off (or at 100 %) there is no ripple and
//! the reading is taken at once. Averaging stays the monitor's job.
//!
//! The alternative, an RC filter on the tap (corner well below 25 kHz,
//! e.g. 100 nF on the 45 kohm divider: 4.5 ms), would read the cycle mean
//! instead, which is not the voltage the motor sees during its pulses.

//!
//! The conversion is started on time by code in RAM (`start_at_phase`):
//! polling the PWM counter from flash, a few XIP cache misses (3-5 us each
//! on a cold line) could push the start past a 24-36 us pulse. In RAM,
//! with interrupts masked, nothing waits on the flash: the start lies
//! after the target count by at most one pass of the polling loop plus the
//! write of ADC CS (cycles counted in the disassembly: `firmware/README.md`,
//! "Battery conversion timing"). A hardware start (a DMA channel paced by
//! the PWM's wrap DREQ writing CS.START_ONCE) was weighed: the wrap is the
//! start of the on-pulse, not its middle, unless the slice runs
//! phase-correct (which rp2040js does not emulate) or a second slice is
//! phase-locked to it, and whether a wrap DREQ left pending from an earlier
//! period fires the transfer at once is not settled without a board.

use crate::board;
use rp2040_hal::adc::{Adc, AdcPin};
use rp2040_hal::gpio::{bank0::Gpio26, FunctionSioInput, Pin, PullNone};
use rp2040_hal::pac;

const _: () = assert!(board::BATTERY_ADC_GPIO == 26 && board::BATTERY_ADC_CHANNEL == 0);

pub type BatteryPin = AdcPin<Pin<Gpio26, FunctionSioInput, PullNone>>;

/// Polls of the PWM counter before giving up on a phase (the counter
/// wraps every 5000 cycles; a poll takes about 10): a stopped counter must
/// not hang the main loop.
const MAX_POLLS: u32 = 20_000;
/// Polls of CS.READY before a conversion counts as failed (one takes 96
/// ADC clocks: 2 us at 48 MHz, 8 us on the 12 MHz crystal).
const MAX_READY_POLLS: u32 = 10_000;

/// ADC CS (RP2040 datasheet 4.9.6): enable, one conversion, ready, error.
const CS_EN: u32 = 1 << 0;
const CS_START_ONCE: u32 = 1 << 2;
const CS_READY: u32 = 1 << 8;
const CS_ERR: u32 = 1 << 9;
const CS_AINSEL_SHIFT: u32 = 12;

/// The ADC is owned (enabled, pin in analogue mode) by the HAL's types,
/// and driven through its registers: the start has to come from RAM.
pub struct BatterySense {
    _adc: Adc,
    _pin: BatteryPin,
}

impl BatterySense {
    pub fn new(adc: Adc, pin: BatteryPin) -> Self {
        Self {
            _adc: adc,
            _pin: pin,
        }
    }

    /// Raw 12-bit counts, converted in the middle of the on-pulse when the
    /// PWM (compare `counts`, wrap `top`) is switching. A failed conversion
    /// reads as 0, which the monitor classifies as a fault (motor off).
    pub fn read(&mut self, pwm: Option<(u16, u16)>) -> u16 {
        let target = match pwm {
            Some((counts, top)) if counts > 0 && u32::from(counts) <= u32::from(top) => {
                Some(counts / 2)
            }
            _ => None,
        };
        let cs = CS_EN | CS_START_ONCE | (u32::from(board::BATTERY_ADC_CHANNEL) << CS_AINSEL_SHIFT);
        // Interrupts wait at most one PWM period plus the conversion, once
        // every 20 ms: an IR edge's timestamp is then late by up to ~42 us,
        // well inside NEC's +-25 % of 562 us.
        critical_section::with(|_| {
            // SAFETY: RAM code touching only PWM CH0's counter (read) and
            // ADC CS (write), which this type owns.
            unsafe { start_at_phase(target.map_or(-1, i32::from), cs, MAX_POLLS) };
            // SAFETY: reads of the ADC this type owns.
            let adc = unsafe { &*pac::ADC::ptr() };
            for _ in 0..MAX_READY_POLLS {
                let status = adc.cs().read().bits();
                if status & CS_READY != 0 {
                    return if status & CS_ERR != 0 {
                        0
                    } else {
                        adc.result().read().result().bits()
                    };
                }
            }
            0
        })
    }
}

/// A conversion started at `target` as `read` starts it (`hil`'s check).
#[cfg(feature = "hil")]
pub fn start_at_phase_for_test(target: i32) {
    let cs = CS_EN | CS_START_ONCE | (u32::from(board::BATTERY_ADC_CHANNEL) << CS_AINSEL_SHIFT);
    // SAFETY: as in `read`.
    unsafe { start_at_phase(target, cs, MAX_POLLS) };
}

/// Write `cs` (a conversion's start) to ADC CS just after PWM slice 0's
/// counter reaches `target` in a fresh period (the wrap seen as the
/// counter going down, then the target); at once if `target` < 0; after
/// `max_polls` polls at the latest. In RAM (`.data`, copied at reset) and
/// with only volatile accesses, so no instruction or literal is fetched
/// through XIP while it waits (checked in the disassembly: no call out).
#[inline(never)]
#[link_section = ".data.ram_func"]
unsafe fn start_at_phase(target: i32, cs: u32, max_polls: u32) {
    const PWM_CH0_CTR: *const u32 = 0x4005_0008 as *const u32;
    const ADC_CS: *mut u32 = 0x4004_c000 as *mut u32;
    if target >= 0 {
        let mut prev = core::ptr::read_volatile(PWM_CH0_CTR) as i32;
        let mut wrapped = false;
        let mut polls = max_polls;
        while polls > 0 {
            let now = core::ptr::read_volatile(PWM_CH0_CTR) as i32;
            if wrapped && now >= target {
                break;
            }
            wrapped |= now < prev;
            prev = now;
            polls -= 1;
        }
    }
    core::ptr::write_volatile(ADC_CS, cs);
}
