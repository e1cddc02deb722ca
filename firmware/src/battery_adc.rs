//! Battery voltage sensing: one ADC0 conversion of the divider tap per call.
//! The main loop calls it at `SAMPLE_PERIOD_US`; averaging and thresholds
//! are the shared `BatteryMonitor`'s job.

use crate::board;
use embedded_hal_0_2::adc::OneShot;
use rp2040_hal::adc::{Adc, AdcPin};
use rp2040_hal::gpio::{bank0::Gpio26, FunctionSioInput, Pin, PullNone};

const _: () = assert!(board::BATTERY_ADC_GPIO == 26 && board::BATTERY_ADC_CHANNEL == 0);

/// 50 Hz: five times the minimum rate, so the 8-sample average
/// spans 160 ms, short against the 1 s cut-off debounce.
pub const SAMPLE_PERIOD_US: u64 = 20_000;

pub type BatteryPin = AdcPin<Pin<Gpio26, FunctionSioInput, PullNone>>;

pub struct BatterySense {
    adc: Adc,
    pin: BatteryPin,
}

impl BatterySense {
    pub fn new(adc: Adc, pin: BatteryPin) -> Self {
        Self { adc, pin }
    }

    /// Raw 12-bit counts; a failed conversion reads as 0, which the monitor
    /// classifies as a fault (motor off) rather than as a voltage.
    pub fn read(&mut self) -> u16 {
        OneShot::<Adc, u16, BatteryPin>::read(&mut self.adc, &mut self.pin).unwrap_or(0)
    }
}
