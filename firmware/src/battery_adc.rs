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

use crate::board;
use crate::motor;
use embedded_hal_0_2::adc::OneShot;
use rp2040_hal::adc::{Adc, AdcPin};
use rp2040_hal::gpio::{bank0::Gpio26, FunctionSioInput, Pin, PullNone};

const _: () = assert!(board::BATTERY_ADC_GPIO == 26 && board::BATTERY_ADC_CHANNEL == 0);

pub type BatteryPin = AdcPin<Pin<Gpio26, FunctionSioInput, PullNone>>;

/// Polls of the PWM counter before giving up on a phase (the counter
/// wraps every 5000 cycles; a poll takes several): a stopped counter must
/// not hang the main loop.
const MAX_POLLS: u32 = 20_000;

pub struct BatterySense {
    adc: Adc,
    pin: BatteryPin,
}

impl BatterySense {
    pub fn new(adc: Adc, pin: BatteryPin) -> Self {
        Self { adc, pin }
    }

    /// Raw 12-bit counts, converted in the middle of the on-pulse when the
    /// PWM (compare `counts`, wrap `top`) is switching. A failed conversion
    /// reads as 0, which the monitor classifies as a fault (motor off).
    pub fn read(&mut self, pwm: Option<(u16, u16)>) -> u16 {
        // Interrupts wait at most one PWM period plus the 2 us conversion,
        // once every 20 ms: an IR edge's timestamp is then late by up to
        // ~42 us, well inside NEC's +-25 % of 562 us.
        critical_section::with(|_| {
            if let Some((counts, top)) = pwm {
                if counts > 0 && u32::from(counts) <= u32::from(top) {
                    wait_for_phase(counts / 2);
                }
            }
            OneShot::<Adc, u16, BatteryPin>::read(&mut self.adc, &mut self.pin).unwrap_or(0)
        })
    }
}

/// Return just after the PWM counter reaches `target` in a fresh period:
/// wait for the wrap (the counter going down), then for the target.
fn wait_for_phase(target: u16) {
    let mut prev = motor::counter();
    let mut wrapped = false;
    for _ in 0..MAX_POLLS {
        let now = motor::counter();
        if wrapped && now >= target {
            return;
        }
        wrapped |= now < prev;
        prev = now;
    }
}
