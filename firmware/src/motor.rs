//! Motor drive: PWM slice 0 channel A on the MOSFET gate pin, carrier and
//! resolution from `board::PWM_FREQ_HZ` and the real system clock.

use crate::board;
use embedded_hal::pwm::SetDutyCycle;
use rp2040_hal::gpio::{bank0::Gpio16, FunctionPwm, FunctionSioOutput, Pin, PullDown};
use rp2040_hal::pwm::{FreeRunning, Pwm0, Slice};
use swimbot_shared::{Duty, PwmTiming};

// The typed pin and slice below must be the ones board.rs names.
const _: () = assert!(board::MOTOR_PWM_GPIO == 16, "GPIO16 is PWM slice 0 A");
// At the nominal 125 MHz the carrier must be reachable with >= 10 bits.
const _: () = assert!(PwmTiming::for_carrier(125_000_000, board::PWM_FREQ_HZ).is_some());

pub type MotorPinLow = Pin<Gpio16, FunctionSioOutput, PullDown>;

pub struct Motor {
    slice: Slice<Pwm0, FreeRunning>,
    _pin: Pin<Gpio16, FunctionPwm, PullDown>,
    top: u16,
    counts: u16,
}

impl Motor {
    /// Take over the pin (already driven low) with the PWM at zero duty.
    /// The slice runs with CC = 0 before the pin is switched to it, so the
    /// gate never sees a pulse during the hand-over.
    pub fn new(mut slice: Slice<Pwm0, FreeRunning>, pin: MotorPinLow, sys_hz: u32) -> Self {
        // Fall back to the slowest carrier the counter allows rather than
        // panic: a wrong clock must not keep the board from booting with
        // the motor safely off.
        let t = PwmTiming::for_carrier(sys_hz, board::PWM_FREQ_HZ).unwrap_or(PwmTiming {
            div_int: 255,
            div_frac: 0,
            top: u16::MAX,
        });
        slice.default_config();
        slice.set_div_int(t.div_int);
        slice.set_div_frac(t.div_frac);
        slice.set_top(t.top);
        let _ = slice.channel_a.set_duty_cycle(0);
        slice.enable();
        let pin = slice.channel_a.output_to(pin);
        defmt::info!(
            "pwm: sys {} Hz, div {}, top {} -> {} Hz, {} steps",
            sys_hz,
            t.div_int,
            t.top,
            t.carrier_hz(sys_hz),
            t.steps()
        );
        Self {
            slice,
            _pin: pin,
            top: t.top,
            counts: 0,
        }
    }

    pub fn set(&mut self, duty: Duty) {
        let counts = duty.counts(self.top);
        if counts != self.counts {
            self.counts = counts;
            // Infallible on the RP2040.
            let _ = self.slice.channel_a.set_duty_cycle(counts);
        }
    }

    pub fn is_on(&self) -> bool {
        self.counts != 0
    }
}
