//! Board constants: every pin, clock and fixed electrical value of the
//! swimbot's RP2040 board in one place. The emulator tests (tests/emulator)
//! read the same numbers, so change them together.

/// Crystal on the board (Raspberry Pi Pico compatible).
pub const XOSC_HZ: u32 = 12_000_000;

/// Motor driver input (N-MOSFET gate through a 100 ohm resistor, 100 kohm pull-down):
/// GPIO16 = PWM slice 0, channel A.
pub const MOTOR_PWM_GPIO: u8 = 16;
/// IR receiver output (TSOP-style, active low, idle high with pull-up).
pub const IR_GPIO: u8 = 15;
/// Battery divider tap: GPIO26 = ADC input 0.
pub const BATTERY_ADC_GPIO: u8 = 26;
pub const BATTERY_ADC_CHANNEL: u8 = 0;
/// Status LED (active high).
pub const LED_GPIO: u8 = 25;

/// Motor PWM carrier; configurable 20-100 kHz (above hearing, below the
/// MOSFET's switching-loss knee).
pub const PWM_FREQ_HZ: u32 = 25_000;

/// Battery divider 100 kohm over 82 kohm: V_pin = V_bat * 82/182 = 0.4505 V_bat.
/// Over the cell's working range 3.0-4.2 V the ADC sees 1.35-1.89 V, codes
/// 1676-2346 of 4096 (3.3 V reference): clear of the RP2040 ADC's
/// differential-non-linearity spikes at codes 1536 and 2560.
pub const DIVIDER_TOP_OHM: u32 = 100_000;
pub const DIVIDER_BOTTOM_OHM: u32 = 82_000;
pub const ADC_REF_MV: u32 = 3_300;

/// The remote's NEC address accepted by this robot, and its command codes.
pub const NEC_ADDRESS: u8 = 0x00;
pub const NEC_CMD_ON: u8 = 0x45;
pub const NEC_CMD_OFF: u8 = 0x47;

/// Hardware watchdog period; fed only from the main loop.
pub const WATCHDOG_MS: u32 = 500;
