//! Board constants: every pin, clock, timing and fixed electrical value of
//! the swimbot's RP2040 board, in one place. The firmware, the host
//! simulation (`tests/src/lib.rs`), the safety property tests and the
//! emulator all read these: the firmware exports them into its ELF
//! (`EXPORT`, symbol `SWIMBOT_BOARD`), and the emulator's board model reads
//! them from the very image it runs (`tests/emulator/lib/facts.js`).

use crate::battery::BatteryConfig;
use crate::command::KeyMap;
use crate::controller::ControllerConfig;
use crate::pairing::PairingConfig;
use crate::pwm;
use crate::rate::{HallConfig, RateConfig};
use crate::run_log::store::{StoreLayout, BLOCK_LEN};
use crate::set_point::SetPointKeys;
use crate::supervisor::{JamConfig, SupervisorConfig, ThermalConfig, ThermalNode};

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
/// coupler (`docs/rate-sensing.md`): open-drain outputs, in bank 0 beside
/// the IR input so one `IO_IRQ_BANK0` handler serves all three, and A and
/// B come from one read of `SIO.GPIO_IN`. The internal pull-ups (50-80
/// kohm, RP2040 datasheet 2.19.6.1: "Pad Control") are enabled as a
/// fallback only; the board fits 10 kohm pull-ups to the latches' supply
/// at the latches, with 100 nF across each latch's supply: a 60 kohm
/// pull-up beside the motor's 25 kHz PWM edges is a high-impedance node
/// that couples switching noise into false edges.
pub const HALL_A_GPIO: u8 = 13;
pub const HALL_B_GPIO: u8 = 14;
/// Powers both latches: high only while the motor may run, so the idle and
/// cut-off current budget does not carry them. DRV5013-class latches draw
/// about 3 mA each, about 6 mA for two plus 0.33 mA into the two 10 kohm
/// pull-ups when both pull low: past the pad's default 4 mA drive, the
/// current at which the RP2040's V_OH (IOVDD - 0.62 V, datasheet 5.5.3) is
/// specified. The pin is set to 12 mA drive (`firmware/src/main.rs`), so
/// the latches' supply stays within that V_OH, above their 2.5 V minimum.
/// A board with a 3.3 V rail switched by a transistor may use that instead.
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

/// Pairing (`pairing`): within 5 s of power-up, hold Off (CH+) for 1 s.
/// The key map's address above is the host simulation's remote; the
/// robot obeys the address kept in its pairing sector.
pub const PAIRING: PairingConfig = PairingConfig::hold(NEC_CMD_OFF, NEC_CMD_ON);

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
    max_motor_mv: MOTOR_RATED_MV,
    ..RateConfig::DEFAULT
};
/// The motor's rated voltage: a 6 mm coreless motor run from one Li-Po
/// cell is rated 3.7 V (the cell's nominal). Both the rate controller's
/// clamp and the supervisor's ceiling.
pub const MOTOR_RATED_MV: u16 = 3_700;

/// The motor supervisor (`supervisor`), independent of the controller.
///
/// Jam: 1.5 V moves the heaviest tail of the paper's (5.1 V/Hz over a
/// 0.175 V intercept, `rate::control`) at 0.26 Hz; fewer than 4 of the 16
/// quadrature steps a turn in 1.75 s is below 0.14 Hz (a rotor at 0.1 Hz
/// makes at most 3), while the lowest set-point, 0.2 Hz, makes at least 5
/// (4 if the window holds the first edge, whose step is unknown). A tail
/// jammed at full drive stops 1.75-2.0 s after the drive reached 1.5 V.
///
/// Heat: the motor (7 ohm, 6 x 11 mm, coreless) is in the class of
/// Faulhaber's 0615 and maxon's 6 mm motors, whose datasheets give
/// winding -> housing about 10 K/W with a 2-3 s time constant, housing ->
/// air about 75 K/W with about 100 s, and 85-125 C winding limits: class
/// values, not this motor's. At 1 Hz the direct-drive tail holds the motor
/// near stall, so a healthy run dissipates `V_motor V_cell / R`, about
/// 1.7-1.8 W at the 3.0 V target: in free air (75 K/W) its winding would
/// pass 150 C, yet the paper's robot ran 10-minute runs. Its housing sheds
/// heat into the seal, the coupler and the oil: 25 K/W is assumed (a
/// healthy 1.8 W run settles 63 K up), with 70 K allowed (105 C from a
/// 35 C sealed body). Fit the housing node on the bench from a slowed or
/// stalled run's log and the can's temperature (`swimbot log --thermal`,
/// docs/run-log.md) and build with the `thermal.toml` it writes (`HOUSING`). A
/// turning motor held at the 3.7 V ceiling from a 4.0 V cell (2.0 W)
/// passes the limit after 7.3 minutes (host test); a new start waits until
/// the winding is back under 35 K. The driver is
/// a SOT-23 N-MOSFET (about 50 mohm at 3.3 V gate drive) and a SOD-123
/// Schottky freewheel diode (0.3 V for about a quarter of each period:
/// about 100 mohm equivalent at 0.5 A), 250 K/W junction -> air, 1 s,
/// 80 K allowed (125 C junction from 45 C).
pub const SUPERVISOR: SupervisorConfig = SupervisorConfig {
    max_motor_mv: MOTOR_RATED_MV as u32,
    jam: JamConfig {
        drive_min_mv: 1_500,
        window_us: 1_750_000,
        min_steps: 4,
    },
    thermal: ThermalConfig {
        motor_resistance_mohm: 7_000,
        winding: ThermalNode {
            r_th_mk_per_w: 10_000,
            tau_ms: 2_500,
        },
        housing: HOUSING,
        winding_rise_max_mk: 70_000,
        winding_restart_mk: 35_000,
        driver_resistance_mohm: 150,
        driver: ThermalNode {
            r_th_mk_per_w: 250_000,
            tau_ms: 1_000,
        },
        driver_rise_max_mk: 80_000,
    },
    // Three trips in one power-up: the third start after a jam or a
    // cool-down is the last (a jam cleared by hand, a second look, then
    // the bench).
    lockout_trips: 3,
};

/// The motor housing's node: 25 K/W and 100 s (the assumption above),
/// unless the firmware is built from a bench fit (`cargo xtask fw|uf2
/// --thermal thermal.toml`, which sets `SWIMBOT_HOUSING_R_TH_MK_PER_W` and
/// `SWIMBOT_HOUSING_TAU_MS` for that build only; firmware/README.md,
/// "Heat limits from the bench"). The ranges are xtask's, checked again
/// here so that a hand-set variable cannot build an image either.
pub const HOUSING: ThermalNode = ThermalNode {
    r_th_mk_per_w: env_u32(option_env!("SWIMBOT_HOUSING_R_TH_MK_PER_W"), 25_000),
    tau_ms: env_u32(option_env!("SWIMBOT_HOUSING_TAU_MS"), 100_000),
};
/// Accepted housing thermal resistance, mK/W: from a heat-sunk can (2 K/W)
/// to twice the free-air class value (150 K/W); outside, the fit is wrong.
pub const HOUSING_R_TH_RANGE_MK_PER_W: (u32, u32) = (2_000, 150_000);
/// Accepted housing time constant, ms: 10 s (four times the winding's
/// 2.5 s, so the two nodes stay apart) to 1 000 s (ten times the class
/// value).
pub const HOUSING_TAU_RANGE_MS: (u32, u32) = (10_000, 1_000_000);
const _: () = assert!(
    HOUSING.r_th_mk_per_w >= HOUSING_R_TH_RANGE_MK_PER_W.0
        && HOUSING.r_th_mk_per_w <= HOUSING_R_TH_RANGE_MK_PER_W.1,
    "SWIMBOT_HOUSING_R_TH_MK_PER_W outside 2 000-150 000 mK/W"
);
const _: () = assert!(
    HOUSING.tau_ms >= HOUSING_TAU_RANGE_MS.0 && HOUSING.tau_ms <= HOUSING_TAU_RANGE_MS.1,
    "SWIMBOT_HOUSING_TAU_MS outside 10 000-1 000 000 ms"
);

/// A build-time variable's decimal digits, or `default` when it is unset;
/// anything else stops the build.
const fn env_u32(value: Option<&str>, default: u32) -> u32 {
    let Some(text) = value else {
        return default;
    };
    let bytes = text.as_bytes();
    assert!(!bytes.is_empty(), "a SWIMBOT_HOUSING_* variable is empty");
    let mut n: u32 = 0;
    let mut i = 0;
    while i < bytes.len() {
        let d = bytes[i];
        assert!(
            d.is_ascii_digit(),
            "a SWIMBOT_HOUSING_* variable is not decimal digits"
        );
        n = match n.checked_mul(10) {
            Some(v) => match v.checked_add((d - b'0') as u32) {
                Some(v) => v,
                None => panic!("a SWIMBOT_HOUSING_* variable overflows u32"),
            },
            None => panic!("a SWIMBOT_HOUSING_* variable overflows u32"),
        };
        i += 1;
    }
    n
}

/// The set-point after power-up: 1 Hz, inside the paper's observed
/// 0.57-1.50 Hz (Table II). The remote's keys change it.
pub const DEFAULT_RATE_MHZ: u32 = 1_000;

/// Battery sampling period: 50 Hz, five times a minimum rate of 10 Hz, so
/// the 8-sample average spans 160 ms, short against the 1 s cut-off debounce.
pub const BATTERY_SAMPLE_PERIOD_US: u64 = 20_000;

/// Run log: one record every 100 ms (10 Hz, the minimum rate) while
/// the motor may run: 6001 records of 16 bytes for a 10-minute run
/// (`run_log`).
pub const LOG_PERIOD_US: u32 = 100_000;

/// Flash: 2 MiB (W25Q16JV on Pico-compatible boards). `memory.x` gives
/// the first 1 MiB to boot2 and code (128 KiB budget) and reserves the rest:
/// the run log's slots from 1 MiB, the pairing sector at the very top.
/// Offsets from the start of flash, as the boot ROM's flash functions
/// take them; keep `memory.x`'s RUNLOG and PAIRING regions equal
/// (`cargo xtask size` checks the linked image against these).
pub const FLASH_BYTES: u32 = 2 * 1024 * 1024;
pub const LOG_FLASH_OFFSET: u32 = 1024 * 1024;
/// Three 256 KiB slots (`run_log::store`): 16 368 records each, 27 min of
/// running at 10 Hz per power-up; a 10-minute run is 6001 records, 96 kB.
pub const LOG_LAYOUT: StoreLayout = StoreLayout {
    slots: 3,
    slot_len: 256 * 1024,
};
pub const PAIRING_FLASH_OFFSET: u32 = FLASH_BYTES - 4_096;
const _: () = assert!(LOG_FLASH_OFFSET + LOG_LAYOUT.region_len() <= PAIRING_FLASH_OFFSET);
const fn whole_blocks(n: u32) -> bool {
    n / BLOCK_LEN * BLOCK_LEN == n
}
const _: () = assert!(whole_blocks(LOG_LAYOUT.slot_len) && whole_blocks(LOG_FLASH_OFFSET));

/// USB VBUS sense: the Pico's GPIO24 reads VBUS through a divider (high
/// while a USB cable powers the board). USB connected = the motor off.
pub const VBUS_SENSE_GPIO: u8 = 24;
/// Power hold: driven high from the first instruction of `main`, it keeps
/// the board's load switch closed (a P-channel MOSFET or a TPS22917-class
/// switch between the cell and the regulator, its enable pulled down, a
/// push-button or the charger's 5 V in parallel with this pin to turn it
/// on). Driven low once the cut-off has latched and the robot is idle: the
/// switch opens and the cell feeds only the switch's leakage (about 1 uA)
/// and the divider's 23 uA (4.2 V over 100 + 82 kohm) if it sits before the switch (it should sit
/// after it). A Pico without the switch ignores the pin and goes DORMANT
/// as before. GPIO22: free on the Pico's header.
pub const POWER_HOLD_GPIO: u8 = 22;

/// USB IDs of the readout port: Objective Development's (obdev.at)
/// shared CDC-ACM pair 0x16C0/0x27DD from VOTI's VID. Its licence
/// (obdev's USB-IDs-for-free.txt) is for devices told apart by their
/// serial number string, which must begin with the maker's internet
/// domain or e-mail address, then a colon: `USB_SERIAL_DOMAIN`, then
/// the flash chip's unique ID. The host finds the port by the product
/// string.
pub const USB_VID: u16 = 0x16c0;
pub const USB_PID: u16 = 0x27dd;
pub const USB_PRODUCT: &str = "swimbot run log";
/// The lab's domain (or e-mail address) at the start of the USB serial
/// number. `swimbot.invalid` (a reserved name, RFC 2606) marks the value
/// as not yet set: a lab sets its own before it ships a robot beyond its
/// own benches.
pub const USB_SERIAL_DOMAIN: &str = "swimbot.invalid";

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
        (tag(b"LOGA"), LOG_FLASH_OFFSET),
        (tag(b"LOGS"), LOG_LAYOUT.slot_len),
        (tag(b"LOGN"), LOG_LAYOUT.slots as u32),
        (tag(b"LOGP"), LOG_PERIOD_US / 1_000),
        (tag(b"PAIR"), PAIRING_FLASH_OFFSET),
        (tag(b"PWIN"), (PAIRING.window_us / 1_000) as u32),
        (tag(b"PHLD"), (PAIRING.hold_us / 1_000) as u32),
        (tag(b"VBUS"), VBUS_SENSE_GPIO as u32),
        (tag(b"VMAX"), SUPERVISOR.max_motor_mv),
        (tag(b"JAMW"), SUPERVISOR.jam.window_us / 1_000),
        (tag(b"PHGP"), POWER_HOLD_GPIO as u32),
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
pub const EXPORT_PAIRS: usize = 43;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn build_time_housing_digits_or_the_default() {
        assert_eq!(env_u32(None, 25_000), 25_000);
        assert_eq!(env_u32(Some("31250"), 25_000), 31_250);
        assert_eq!(env_u32(Some("0"), 7), 0);
        // Without the variables (a plain build) the assumed node is built in.
        if option_env!("SWIMBOT_HOUSING_R_TH_MK_PER_W").is_none() {
            assert_eq!(HOUSING.r_th_mk_per_w, 25_000);
        }
        if option_env!("SWIMBOT_HOUSING_TAU_MS").is_none() {
            assert_eq!(HOUSING.tau_ms, 100_000);
        }
        assert_eq!(SUPERVISOR.thermal.housing, HOUSING);
    }

    #[test]
    #[should_panic(expected = "not decimal digits")]
    fn build_time_housing_refuses_other_text() {
        extern crate std;
        // At run time here; in the const above the same panic stops the build.
        let text = std::string::String::from("25.5");
        env_u32(Some(&text), 25_000);
    }

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
