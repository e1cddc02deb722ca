//! Motor drive: PWM slice 0 channel A on the MOSFET gate pin, carrier and
//! resolution from `board::PWM_FREQ_HZ` and the real system clock.

use crate::board;
use embedded_hal::pwm::SetDutyCycle;
use rp2040_hal::gpio::{
    bank0::Gpio16, FunctionPwm, FunctionSioOutput, OutputDriveStrength, OutputSlewRate, Pin,
    PullDown,
};
use rp2040_hal::pwm::{FreeRunning, Pwm0, Slice};
use swimbot_shared::{Duty, PwmTiming};

// The typed pin and slice below must be the ones board.rs names.
const _: () = assert!(board::MOTOR_PWM_GPIO == 16, "GPIO16 is PWM slice 0 A");
// At the nominal 125 MHz the carrier must be reachable with >= 10 bits.
const _: () = assert!(PwmTiming::for_carrier(125_000_000, board::PWM_FREQ_HZ).is_some());

pub type MotorPinLow = Pin<Gpio16, FunctionSioOutput, PullDown>;

pub enum Motor {
    Pwm {
        slice: Slice<Pwm0, FreeRunning>,
        _pin: Pin<Gpio16, FunctionPwm, PullDown>,
        top: u16,
        counts: u16,
    },
    /// No usable carrier at this system clock: the pin stays a plain
    /// output, low, and every duty is ignored. A 7.5 Hz "PWM" would jerk
    /// the motor; off is the only safe fallback.
    Disabled(MotorPinLow),
}

impl Motor {
    /// Take over the pin (already driven low) with the PWM at zero duty.
    /// The slice runs with CC = 0 before the pin is switched to it, so the
    /// gate never sees a pulse during the hand-over.
    pub fn new(mut slice: Slice<Pwm0, FreeRunning>, mut pin: MotorPinLow, sys_hz: u32) -> Self {
        // The gate: 100 ohm into a few nF of MOSFET input capacitance.
        // 12 mA and fast slew give edges of tens of ns instead of the
        // default 4 mA / slow slew's hundreds, which kept the MOSFET in its
        // linear region (and hot) for a sizeable part of each 40 us period.
        pin.set_drive_strength(OutputDriveStrength::TwelveMilliAmps);
        pin.set_slew_rate(OutputSlewRate::Fast);
        let Some(t) = PwmTiming::for_carrier(sys_hz, board::PWM_FREQ_HZ) else {
            defmt::error!("pwm: no carrier at sys {} Hz: motor disabled", sys_hz);
            return Motor::Disabled(pin);
        };
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
        Motor::Pwm {
            slice,
            _pin: pin,
            top: t.top,
            counts: 0,
        }
    }

    pub fn set(&mut self, duty: Duty) {
        if let Motor::Pwm {
            slice, top, counts, ..
        } = self
        {
            let c = duty.counts(*top);
            if c != *counts {
                *counts = c;
                // Infallible on the RP2040.
                let _ = slice.channel_a.set_duty_cycle(c);
            }
        }
    }

    /// Compare value and TOP of the running carrier (for phase-locked ADC
    /// readings); `None` when the motor is disabled.
    pub fn timing(&self) -> Option<(u16, u16)> {
        match self {
            Motor::Pwm { top, counts, .. } => Some((*counts, *top)),
            Motor::Disabled(_) => None,
        }
    }

    /// The level the gate pin drives now (GPIO16's OUTTOPAD, whatever
    /// function drives it): what the MOSFET sees, not what was asked.
    pub fn gate_high(&self) -> bool {
        // SAFETY: a read of a status register.
        let io = unsafe { &*rp2040_hal::pac::IO_BANK0::ptr() };
        io.gpio(usize::from(board::MOTOR_PWM_GPIO))
            .gpio_status()
            .read()
            .outtopad()
            .bit_is_set()
    }
}
