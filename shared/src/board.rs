//! Board constants: every pin, clock, timing and fixed electrical value of
//! the swimbot's RP2040 board, in one place. The firmware, the host
//! simulation (`tests/src/lib.rs`), the safety property tests and the
//! emulator all read these: the firmware exports them into its ELF
//! (`EXPORT`, symbol `SWIMBOT_BOARD`), and the emulator's board model reads
//! them from the very image it runs (`tests/emulator/lib/facts.js`).

use crate::battery::BatteryConfig;
use crate::command::KeyMap;
use crate::controller::ControllerConfig;
use crate::pwm;
use crate::rate::{HallConfig, RateConfig};
use crate::set_point::SetPointKeys;

/// Crystal on the board (Raspberry Pi Pico compatible).
pub const XOSC_HZ: u32 = 12_000_000;

/// Motor driver input (N-MOSFET gate through a 100 ohm resistor, 100 kohm
/// pull-down): GPIO16 = PWM slice 0, channel A.
pub const MOTOR_PWM_GPIO: u8 = 16;
/// IR receiver output (TSOP-style 38 kHz, active low, idle high with pull-up).
pub const IR_GPIO: u8 = 15;
/// Battery divider tap: GPIO26 = ADC input 0.
pub const BATTERY_ADC_GPIO: u8 = 26;
pub const BATTERY_ADC_CHANNEL: u8 = 0;
/// Status LED (active high).
pub const LED_GPIO: u8 = 25;

/// Two Hall latches in quadrature over an 8-pole ring magnet on the motor's
/// coupler (`docs/rate-sensing.md`): open-drain outputs with the internal
/// pull-ups, in bank 0 beside the IR input so one `IO_IRQ_BANK0` handler
/// serves all three, and A and B come from one read of `SIO.GPIO_IN`.
pub const HALL_A_GPIO: u8 = 13;
pub const HALL_B_GPIO: u8 = 14;
/// Powers both latches (a few mA each): high only while the motor may run,
/// so the idle and cut-off current budget does not carry them.
pub const HALL_POWER_GPIO: u8 = 12;
/// 4 pole pairs: 16 quadrature edges a turn.
pub const HALL: HallConfig = HallConfig::RING_8_POLE;
/// The latches' power-on time before their outputs are valid is tens of
/// microseconds (DRV5013-class parts); the soft start's first 250 ms
/// turn the rotor far less than one pole, so no edge is missed.
const _: () = assert!(HALL_A_GPIO / 8 == IR_GPIO / 8 && HALL_B_GPIO / 8 == IR_GPIO / 8);

/// Motor PWM carrier: above hearing, below the MOSFET's switching-loss
/// knee, and with no harmonic up to the third in the IR receiver's pass
/// band (`pwm::carrier_clear_of_ir`).
pub const PWM_FREQ_HZ: u32 = 25_000;
const _: () = assert!(pwm::carrier_clear_of_ir(PWM_FREQ_HZ));

/// Battery divider 100 kohm over 82 kohm: V_pin = V_bat * 82/182 = 0.4505 V_bat.
/// Over the cell's working range 3.0-4.2 V the ADC sees 1.35-1.89 V, codes
/// 1678-2349 of 4096 (3.3 V reference): clear of the RP2040 ADC's
/// differential-non-linearity spikes at codes 1536 and 2560.
pub const DIVIDER_TOP_OHM: u32 = 100_000;
pub const DIVIDER_BOTTOM_OHM: u32 = 82_000;
/// Nominal ADC reference: the 3V3 rail.
pub const ADC_REF_NOMINAL_MV: u32 = 3_300;
/// Calibration: the 3V3 rail as measured on this board with a multimeter
/// (the regulator's tolerance is +-2-3 %, which is +-0.1 V of cell voltage
/// at the 3.3 V cut-off). Enter the measured value; the nominal one is the
/// default until a board has been measured.
pub const ADC_REF_MEASURED_MV: u32 = ADC_REF_NOMINAL_MV;

/// The remote's NEC address accepted by this robot, and its command codes.
pub const NEC_ADDRESS: u8 = 0x00;
pub const NEC_CMD_ON: u8 = 0x45;
pub const NEC_CMD_OFF: u8 = 0x47;

pub const KEYS: KeyMap = KeyMap {
    address: NEC_ADDRESS,
    on: NEC_CMD_ON,
    off: NEC_CMD_OFF,
};
/// Keys 1-5 select 0.5-1.5 Hz, VOL+/VOL- step by 0.05 Hz (`set_point`).
pub const SET_POINT_KEYS: SetPointKeys = SetPointKeys::CAR_MP3;
pub const BATTERY: BatteryConfig =
    BatteryConfig::new(DIVIDER_TOP_OHM, DIVIDER_BOTTOM_OHM, ADC_REF_MEASURED_MV);
pub const CONTROLLER: ControllerConfig = ControllerConfig::DEFAULT;
/// The rate controller around `CONTROLLER`'s on/off state machine, soft
/// start and interlocks (`rate::control`).
pub const RATE: RateConfig = RateConfig {
    motor: CONTROLLER,
    ..RateConfig::DEFAULT
};
/// The set-point after power-up: 1 Hz, inside the paper's observed
/// 0.57-1.50 Hz (Table II). The remote's keys change it.
pub const DEFAULT_RATE_MHZ: u32 = 1_000;

/// Battery sampling period: 50 Hz, five times the minimum rate, so
/// the 8-sample average spans 160 ms, short against the 1 s cut-off debounce.
pub const BATTERY_SAMPLE_PERIOD_US: u64 = 20_000;

/// Run log: one record every 100 ms (10 Hz, the minimum) while
/// the motor may run: 6001 records of 16 bytes for a 10-minute run
/// (`run_log`).
pub const LOG_PERIOD_US: u32 = 100_000;

/// Longest sleep between main-loop passes: a pass runs at least this often
/// (1 kHz) plus the pass's own few microseconds.
pub const WAKE_PERIOD_US: u32 = 1_000;

/// Hardware watchdog period, fed once per pass. 100 passes would fit in it;
/// a hang leaves the motor running at most this long before the reset.
pub const WATCHDOG_MS: u32 = 80;
const _: () = assert!(WATCHDOG_MS >= 50 && WATCHDOG_MS <= 100);
const _: () = assert!(
    WAKE_PERIOD_US * 10 < WATCHDOG_MS * 1_000,
    "the watchdog is fed every pass: a pass must come well within its period"
);

/// Idle this long (motor off, no IR edge) and the chip goes DORMANT until
/// the next IR edge. Also what follows a cut-off, once its LED pattern has
/// shown for this long.
pub const DORMANT_AFTER_IDLE_US: u64 = 10_000_000;

/// Tags of the exported facts (four ASCII bytes, big-endian), in the order
/// of `EXPORT`.
const fn tag(t: &[u8; 4]) -> u32 {
    u32::from_be_bytes(*t)
}

/// Every fact the emulator needs, as (tag, value) pairs after a header
/// (`SWBD`, pair count). Self-describing, so the reader checks names, not
/// positions.
pub const EXPORT: [u32; 2 + 2 * EXPORT_PAIRS] = {
    let pairs: [(u32, u32); EXPORT_PAIRS] = [
        (tag(b"MOTR"), MOTOR_PWM_GPIO as u32),
        (tag(b"IRIN"), IR_GPIO as u32),
        (tag(b"ADCC"), BATTERY_ADC_CHANNEL as u32),
        (tag(b"LED "), LED_GPIO as u32),
        (tag(b"PWMF"), PWM_FREQ_HZ),
        (tag(b"DVTP"), DIVIDER_TOP_OHM),
        (tag(b"DVBT"), DIVIDER_BOTTOM_OHM),
        (tag(b"VREF"), ADC_REF_MEASURED_MV),
        (tag(b"NADR"), NEC_ADDRESS as u32),
        (tag(b"NON "), NEC_CMD_ON as u32),
        (tag(b"NOFF"), NEC_CMD_OFF as u32),
        (tag(b"WDMS"), WATCHDOG_MS),
        (tag(b"WAKE"), WAKE_PERIOD_US),
        (tag(b"SMPL"), BATTERY_SAMPLE_PERIOD_US as u32),
        (tag(b"CUTM"), BATTERY.cutoff_mv as u32),
        (tag(b"CUTD"), BATTERY.cutoff_debounce_us as u32),
        (tag(b"RCHM"), BATTERY.recharged_mv as u32),
        (tag(b"MOTM"), CONTROLLER.target_motor_mv as u32),
        (tag(b"RAMP"), CONTROLLER.ramp_us),
        (tag(b"DORM"), (DORMANT_AFTER_IDLE_US / 1_000) as u32),
        (tag(b"HALA"), HALL_A_GPIO as u32),
        (tag(b"HALB"), HALL_B_GPIO as u32),
        (tag(b"HALP"), HALL_POWER_GPIO as u32),
        (tag(b"POLE"), HALL.pole_pairs as u32),
        (tag(b"RATE"), DEFAULT_RATE_MHZ),
        (tag(b"STAL"), RATE.stall_us / 1_000),
        (tag(b"LNV0"), RATE.line.intercept_mv as u32),
        (tag(b"LNSL"), RATE.line.slope_mv_per_hz as u32),
        (tag(b"KP1 "), SET_POINT_KEYS.presets[0].0 as u32),
        (tag(b"KP5 "), SET_POINT_KEYS.presets[4].0 as u32),
        (tag(b"KUP "), SET_POINT_KEYS.faster as u32),
        (tag(b"KDN "), SET_POINT_KEYS.slower as u32),
    ];
    let mut out = [0u32; 2 + 2 * EXPORT_PAIRS];
    out[0] = tag(b"SWBD");
    out[1] = EXPORT_PAIRS as u32;
    let mut i = 0;
    while i < EXPORT_PAIRS {
        out[2 + 2 * i] = pairs[i].0;
        out[3 + 2 * i] = pairs[i].1;
        i += 1;
    }
    out
};
pub const EXPORT_PAIRS: usize = 32;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn export_is_tagged_and_unique() {
        assert_eq!(EXPORT[0], tag(b"SWBD"));
        assert_eq!(EXPORT[1] as usize, EXPORT_PAIRS);
        let tags: [u32; EXPORT_PAIRS] = core::array::from_fn(|i| EXPORT[2 + 2 * i]);
        for (i, a) in tags.iter().enumerate() {
            let printable = |b: &u8| b.is_ascii_graphic() || *b == b' ';
            assert!(a.to_be_bytes().iter().all(printable), "tag {a:#x}");
            assert!(!tags[i + 1..].contains(a), "duplicate tag {a:#x}");
        }
        let at = |t: &[u8; 4]| {
            let i = tags.iter().position(|x| *x == tag(t)).unwrap_or(usize::MAX);
            EXPORT.get(3 + 2 * i).copied()
        };
        assert_eq!(at(b"MOTR"), Some(16));
        assert_eq!(at(b"WDMS"), Some(WATCHDOG_MS));
    }
}
