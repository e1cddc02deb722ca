//! PWM carrier timing: the RP2040 slice's clock divider and TOP value for a
//! carrier frequency, computed from the actual system clock so a different
//! clock setup cannot silently shift the carrier or cut its resolution.
//!
//! Lives here rather than in the firmware so the arithmetic is unit-tested
//! on the host; the firmware only writes the result to the registers.

/// Divider and wrap value of a free-running PWM slice: the counter ticks at
/// `sys_hz / (div_int + div_frac/16)` and wraps after `top + 1` ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PwmTiming {
    pub div_int: u8,
    pub div_frac: u8,
    pub top: u16,
}

/// At least 10-bit duty resolution: 1024 steps, so the motor voltage moves
/// in steps of about 0.1 % of the cell's.
pub const MIN_PWM_STEPS: u32 = 1 << 10;

impl PwmTiming {
    /// The finest timing for a `pwm_hz` carrier: an integer divider (the
    /// smallest that fits the 16-bit counter, so resolution is maximal) and
    /// TOP from the remaining ratio. `None` if the carrier is out of reach
    /// (zero, faster than `sys_hz / MIN_PWM_STEPS`, or slower than the
    /// largest divider allows).
    pub const fn for_carrier(sys_hz: u32, pwm_hz: u32) -> Option<PwmTiming> {
        if pwm_hz == 0 {
            return None;
        }
        let counts = sys_hz / pwm_hz;
        if counts < MIN_PWM_STEPS {
            return None;
        }
        let div = counts.div_ceil(1 << 16);
        if div > 255 {
            return None;
        }
        let top = counts / div - 1;
        if top > u16::MAX as u32 {
            return None;
        }
        Some(PwmTiming {
            div_int: div as u8,
            div_frac: 0,
            top: top as u16,
        })
    }

    /// Duty steps per period (TOP + 1).
    pub const fn steps(&self) -> u32 {
        self.top as u32 + 1
    }

    /// The carrier this timing produces at `sys_hz`.
    pub const fn carrier_hz(&self, sys_hz: u32) -> u32 {
        let div16 = self.div_int as u32 * 16 + self.div_frac as u32;
        ((sys_hz as u64 * 16) / (div16 as u64 * self.steps() as u64)) as u32
    }
}

/// The IR receiver's pass band: a 38 kHz TSOP-type part, whose band-pass
/// filter passes about +-10 % (34-42 kHz). A motor carrier, or one of its
/// low harmonics (edge-aligned PWM has them all), radiated from the motor
/// leads into the receiver inside this band desensitises it or makes noise
/// edges.
pub const IR_BAND_HZ: (u32, u32) = (34_000, 42_000);

/// Allowed motor carrier: 20-100 kHz (above hearing, below the MOSFET's
/// switching-loss knee) and no harmonic up to the third inside
/// `IR_BAND_HZ`. 25 kHz passes; 20 kHz does not (its 2nd harmonic is
/// 40 kHz), nor does anything from 34 to 42 kHz.
pub const fn carrier_clear_of_ir(pwm_hz: u32) -> bool {
    if pwm_hz < 20_000 || pwm_hz > 100_000 {
        return false;
    }
    let mut n = 1;
    while n <= 3 {
        let h = pwm_hz * n;
        if h >= IR_BAND_HZ.0 && h <= IR_BAND_HZ.1 {
            return false;
        }
        n += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn board_default_is_5000_counts_without_divider() {
        let t = PwmTiming::for_carrier(125_000_000, 25_000);
        assert_eq!(
            t,
            Some(PwmTiming {
                div_int: 1,
                div_frac: 0,
                top: 4_999
            })
        );
    }

    #[test]
    fn out_of_range() {
        assert_eq!(PwmTiming::for_carrier(125_000_000, 0), None);
        // 125 MHz / 1024 = 122 kHz is the fastest 10-bit carrier.
        assert_eq!(PwmTiming::for_carrier(125_000_000, 123_000), None);
        assert!(PwmTiming::for_carrier(125_000_000, 122_000).is_some());
        // 125 MHz / (255 * 65536) = 7.5 Hz is the slowest.
        assert_eq!(PwmTiming::for_carrier(125_000_000, 7), None);
    }

    #[test]
    fn carrier_keeps_clear_of_the_ir_band() {
        assert!(carrier_clear_of_ir(25_000));
        assert!(!carrier_clear_of_ir(38_000), "the IR carrier itself");
        assert!(!carrier_clear_of_ir(20_000), "2nd harmonic 40 kHz");
        assert!(!carrier_clear_of_ir(13_000), "below 20 kHz, audible");
        assert!(!carrier_clear_of_ir(120_000));
        // Every allowed carrier, swept: no harmonic in the band.
        for hz in (20_000..=100_000).step_by(500) {
            if carrier_clear_of_ir(hz) {
                assert!((1..=3).all(|n| !(IR_BAND_HZ.0..=IR_BAND_HZ.1).contains(&(hz * n))));
            }
        }
    }

    proptest! {
        /// Over the 20-100 kHz range (before the IR-band rule) and system clocks from
        /// 103 MHz (the lowest giving 10 bits at 100 kHz) to the RP2040's
        /// 133 MHz maximum: >= 10 bits, the counter fits, carrier within 0.1 %.
        #[test]
        fn carrier_range(sys_mhz in 103u32..=133, pwm_hz in 20_000u32..=100_000) {
            let sys_hz = sys_mhz * 1_000_000;
            let t = PwmTiming::for_carrier(sys_hz, pwm_hz).expect("in range");
            prop_assert!(t.steps() >= MIN_PWM_STEPS);
            let f = t.carrier_hz(sys_hz);
            prop_assert!(f.abs_diff(pwm_hz) * 1_000 <= pwm_hz, "{} vs {}", f, pwm_hz);
        }

        #[test]
        fn never_panics(sys_hz: u32, pwm_hz: u32) {
            if let Some(t) = PwmTiming::for_carrier(sys_hz, pwm_hz) {
                prop_assert!(t.div_int >= 1 && t.steps() >= MIN_PWM_STEPS);
            }
        }
    }
}
