//! Battery monitor for the robot's 1-cell Li-Po: ADC counts to cell
//! millivolts through the board's divider, a moving average, a warning
//! level, and a debounced, latched under-voltage cut-off.
//!
//! The divider (100k over 82k on the board) maps the cell's 3.0-4.2 V to
//! ADC codes 1678-2349, clear of the RP2040 ADC's differential
//! non-linearity spikes at codes 512/1536/2560/3584, so the thresholds
//! below never sit on a mis-sized code. The 3.3 V reference is assumed to
//! come from a Pico-style buck-boost that stays regulated below 3.3 V of
//! cell voltage (with a plain LDO the readings would turn ratiometric there).
//!
//! Hysteresis, so that neither a motor start nor a noisy reading trips or
//! releases anything by accident:
//! - the cut-off needs the *averaged* voltage below `cutoff_mv` for
//!   `cutoff_debounce_us` without interruption: a start sag or a short load
//!   peak recovers before that and resets the timer;
//! - once tripped the cut-off is latched until the cell reads above
//!   `recharged_mv` at rest (motor off), i.e. it has been recharged: a
//!   depleted cell's rest voltage recovers by 0.1-0.2 V when the load goes,
//!   which must not re-enable the motor;
//! - the warning sets below `warn_mv` and clears only above
//!   `warn_mv + warn_hysteresis_mv`, so the LED does not flicker.

/// Samples in the moving average. At the firmware's 50 Hz sampling this is
/// 160 ms: long enough to smooth PWM ripple and ADC noise (a few LSB), short
/// against the 1 s cut-off debounce.
pub const AVERAGE_SAMPLES: usize = 8;

/// Full scale of the RP2040's 12-bit ADC.
pub const ADC_FULL_SCALE: u32 = 4096;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BatteryConfig {
    pub divider_top_ohm: u32,
    pub divider_bottom_ohm: u32,
    pub adc_ref_mv: u32,
    pub warn_mv: u16,
    pub warn_hysteresis_mv: u16,
    pub cutoff_mv: u16,
    pub cutoff_debounce_us: u64,
    pub recharged_mv: u16,
    /// Readings outside this window cannot come from a connected Li-Po
    /// cell (open or shorted divider): report a fault, never run on them.
    pub plausible_min_mv: u16,
    pub plausible_max_mv: u16,
}

impl BatteryConfig {
    /// The board's divider and reference, with the required thresholds: warn
    /// at 3.5 V, cut off at 3.3 V under load for 1 s, release at 3.9 V rest.
    pub const fn new(divider_top_ohm: u32, divider_bottom_ohm: u32, adc_ref_mv: u32) -> Self {
        Self {
            divider_top_ohm,
            divider_bottom_ohm,
            adc_ref_mv,
            warn_mv: 3_500,
            warn_hysteresis_mv: 50,
            cutoff_mv: 3_300,
            cutoff_debounce_us: 1_000_000,
            recharged_mv: 3_900,
            plausible_min_mv: 2_500,
            plausible_max_mv: 4_600,
        }
    }

    /// Cell millivolts for one ADC reading (codes above 4095 saturate).
    pub fn counts_to_mv(&self, counts: u16) -> u32 {
        let counts = u64::from(counts).min(u64::from(ADC_FULL_SCALE - 1));
        let top = u64::from(self.divider_top_ohm);
        let bottom = u64::from(self.divider_bottom_ohm).max(1);
        let num = counts * u64::from(self.adc_ref_mv) * (top + bottom);
        let den = u64::from(ADC_FULL_SCALE) * bottom;
        // At most 4095 * ref * (1 + top/bottom): fits u32 for any sane divider.
        u32::try_from(num / den).unwrap_or(u32::MAX)
    }

    /// The ADC code a cell voltage produces (inverse of `counts_to_mv`,
    /// rounded to nearest): for simulations and tests.
    pub fn mv_to_counts(&self, cell_mv: u32) -> u16 {
        let top = u64::from(self.divider_top_ohm);
        let bottom = u64::from(self.divider_bottom_ohm);
        let num = u64::from(cell_mv) * u64::from(ADC_FULL_SCALE) * bottom;
        let den = (u64::from(self.adc_ref_mv) * (top + bottom)).max(1);
        let counts = (num + den / 2) / den;
        u16::try_from(counts.min(u64::from(ADC_FULL_SCALE - 1))).unwrap_or(0)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BatteryLevel {
    Ok,
    /// Below the warning level: still allowed to run.
    Low,
    /// Latched cut-off: the motor must stay off until the cell is recharged.
    Cutoff,
    /// No reading yet, or an implausible one: the motor must stay off.
    Fault,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BatteryStatus {
    /// Averaged cell voltage (0 before the first sample).
    pub mv: u16,
    pub level: BatteryLevel,
}

impl BatteryStatus {
    /// May the motor run?
    pub fn allows_motor(&self) -> bool {
        matches!(self.level, BatteryLevel::Ok | BatteryLevel::Low)
    }
}

#[derive(Clone, Debug)]
pub struct BatteryMonitor {
    cfg: BatteryConfig,
    window: [u16; AVERAGE_SAMPLES],
    next: usize,
    filled: usize,
    /// When the average first fell below the cut-off, if it is still there.
    below_since_us: Option<u64>,
    latched: bool,
    warn: bool,
    status: BatteryStatus,
}

impl BatteryMonitor {
    pub const fn new(cfg: BatteryConfig) -> Self {
        Self {
            cfg,
            window: [0; AVERAGE_SAMPLES],
            next: 0,
            filled: 0,
            below_since_us: None,
            latched: false,
            warn: false,
            status: BatteryStatus {
                mv: 0,
                level: BatteryLevel::Fault,
            },
        }
    }

    pub fn config(&self) -> &BatteryConfig {
        &self.cfg
    }

    /// The status after the last sample.
    pub fn status(&self) -> BatteryStatus {
        self.status
    }

    /// Is the cut-off latched (tripped and not yet released by a recharge)?
    /// The firmware keeps this across resets (`reset_memory`).
    pub fn cutoff_latched(&self) -> bool {
        self.latched
    }

    /// Re-arm a cut-off remembered from before a reset: the cell stays
    /// locked out until it reads recharged at rest, exactly as if the
    /// monitor had never restarted.
    pub fn restore_cutoff_latch(&mut self) {
        self.latched = true;
    }

    /// Feed one ADC reading taken at `now_us`; `motor_on` says whether the
    /// cell was under load (the latch only releases at rest).
    pub fn sample(&mut self, counts: u16, now_us: u64, motor_on: bool) -> BatteryStatus {
        let mv = u16::try_from(self.cfg.counts_to_mv(counts)).unwrap_or(u16::MAX);
        if mv < self.cfg.plausible_min_mv || mv > self.cfg.plausible_max_mv {
            // A broken reading is a fault now, and stays out of the average:
            // mixed with others (0 V and full scale from a loose divider) it
            // could average into a plausible voltage, even a recharged one,
            // and release a cut-off latch (found by the safety properties,
            // tests/tests/firmware_safety.rs, property 4).
            self.status = BatteryStatus {
                mv,
                level: BatteryLevel::Fault,
            };
            return self.status;
        }
        if let Some(slot) = self.window.get_mut(self.next) {
            *slot = mv;
        }
        self.next = (self.next + 1) % AVERAGE_SAMPLES;
        self.filled = (self.filled + 1).min(AVERAGE_SAMPLES);
        let sum: u32 = self
            .window
            .iter()
            .take(self.filled)
            .map(|&v| u32::from(v))
            .sum();
        let avg_mv = u16::try_from(sum / self.filled.max(1) as u32).unwrap_or(u16::MAX);
        self.status = BatteryStatus {
            mv: avg_mv,
            level: self.classify(avg_mv, now_us, motor_on),
        };
        self.status
    }

    fn classify(&mut self, mv: u16, now_us: u64, motor_on: bool) -> BatteryLevel {
        let c = &self.cfg;
        if mv < c.plausible_min_mv || mv > c.plausible_max_mv {
            // A broken measurement says nothing about the cell: keep the
            // latch and debounce as they are.
            return BatteryLevel::Fault;
        }
        if mv < c.cutoff_mv {
            let since = *self.below_since_us.get_or_insert(now_us);
            if now_us.saturating_sub(since) >= c.cutoff_debounce_us {
                self.latched = true;
            }
        } else {
            self.below_since_us = None;
        }
        if self.latched && !motor_on && mv >= c.recharged_mv {
            self.latched = false;
            self.warn = false;
        }
        if mv < c.warn_mv {
            self.warn = true;
        } else if mv >= c.warn_mv.saturating_add(c.warn_hysteresis_mv) {
            self.warn = false;
        }
        if self.latched {
            BatteryLevel::Cutoff
        } else if self.warn {
            BatteryLevel::Low
        } else {
            BatteryLevel::Ok
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const CFG: BatteryConfig = BatteryConfig::new(100_000, 82_000, 3_300);

    /// Feed `mv` every 20 ms from `t0` for `dur_us`; returns the end time.
    fn hold(m: &mut BatteryMonitor, mv: u32, t0: u64, dur_us: u64, motor_on: bool) -> u64 {
        let mut t = t0;
        while t < t0 + dur_us {
            m.sample(CFG.mv_to_counts(mv), t, motor_on);
            t += 20_000;
        }
        t
    }

    #[test]
    fn divider_conversion_matches_the_board_comment() {
        // board.rs: 3.0-4.2 V gives codes 1678-2349.
        assert_eq!(CFG.mv_to_counts(3_000), 1_678);
        assert_eq!(CFG.mv_to_counts(4_200), 2_349);
        // One code is 1.8 mV of cell voltage.
        assert!(CFG.counts_to_mv(CFG.mv_to_counts(4_200)).abs_diff(4_200) <= 2);
        // The working range 3.0-4.2 V, and with it every threshold, sits
        // between the DNL spikes at codes 1536 (2.75 V) and 2560 (4.58 V).
        assert!(CFG.mv_to_counts(3_000) > 1_536 + 100);
        assert!(CFG.mv_to_counts(4_200) < 2_560 - 100);
        assert_eq!(CFG.counts_to_mv(u16::MAX), CFG.counts_to_mv(4_095));
    }

    #[test]
    fn no_reading_is_a_fault_and_averaging_smooths() {
        let mut m = BatteryMonitor::new(CFG);
        assert_eq!(m.status().level, BatteryLevel::Fault);
        let c = CFG.mv_to_counts(3_800);
        for i in 0..AVERAGE_SAMPLES as u64 {
            // +-20 counts (~45 mV) of alternating noise.
            let counts = if i % 2 == 0 { c + 20 } else { c - 20 };
            m.sample(counts, i * 20_000, false);
        }
        let s = m.status();
        assert_eq!(s.level, BatteryLevel::Ok);
        assert!((i32::from(s.mv) - 3_800).abs() <= 3, "{s:?}");
    }

    #[test]
    fn warning_has_hysteresis() {
        let mut m = BatteryMonitor::new(CFG);
        let t = hold(&mut m, 3_480, 0, 400_000, true);
        assert_eq!(m.status().level, BatteryLevel::Low);
        let t = hold(&mut m, 3_530, t, 400_000, true);
        assert_eq!(m.status().level, BatteryLevel::Low, "inside the band");
        hold(&mut m, 3_560, t, 400_000, true);
        assert_eq!(m.status().level, BatteryLevel::Ok);
    }

    #[test]
    fn start_sag_shorter_than_debounce_does_not_trip() {
        let mut m = BatteryMonitor::new(CFG);
        let mut t = hold(&mut m, 3_700, 0, 500_000, false);
        for _ in 0..5 {
            t = hold(&mut m, 3_100, t, 800_000, true);
            t = hold(&mut m, 3_450, t, 300_000, true);
            assert_ne!(m.status().level, BatteryLevel::Cutoff);
        }
    }

    #[test]
    fn sustained_low_trips_and_latches_until_recharged() {
        let mut m = BatteryMonitor::new(CFG);
        let t = hold(&mut m, 3_250, 0, 900_000, true);
        assert_ne!(m.status().level, BatteryLevel::Cutoff);
        let t = hold(&mut m, 3_250, t, 400_000, true);
        assert_eq!(m.status().level, BatteryLevel::Cutoff);
        // Load removed: rest voltage recovers, but not to a charged cell.
        let t = hold(&mut m, 3_700, t, 5_000_000, false);
        assert_eq!(m.status().level, BatteryLevel::Cutoff);
        // A charged-looking voltage under load does not release either.
        let t = hold(&mut m, 4_000, t, 1_000_000, true);
        assert_eq!(m.status().level, BatteryLevel::Cutoff);
        hold(&mut m, 4_100, t, 1_000_000, false);
        assert_eq!(m.status().level, BatteryLevel::Ok);
    }

    #[test]
    fn broken_readings_never_average_into_a_release() {
        let mut m = BatteryMonitor::new(CFG);
        m.restore_cutoff_latch();
        // A loose divider: 0 V and full scale alternately (average 3.7 V,
        // or 4.6 V+ with more full-scale readings).
        for i in 0..40u64 {
            let counts = if i % 3 == 0 { 0 } else { 4_095 };
            m.sample(counts, i * 20_000, false);
            assert_eq!(m.status().level, BatteryLevel::Fault);
        }
        let t = hold(&mut m, 3_600, 800_000, 400_000, false);
        assert_eq!(m.status().level, BatteryLevel::Cutoff);
        hold(&mut m, 4_000, t, 400_000, false);
        assert_eq!(m.status().level, BatteryLevel::Ok);
    }

    #[test]
    fn implausible_readings_are_faults() {
        let mut m = BatteryMonitor::new(CFG);
        let t = hold(&mut m, 3_800, 0, 200_000, false);
        hold(&mut m, 0, t, 400_000, false);
        assert_eq!(m.status().level, BatteryLevel::Fault);
        let mut m = BatteryMonitor::new(CFG);
        m.sample(4_095, 0, false);
        assert_eq!(m.status().level, BatteryLevel::Fault);
        assert!(!m.status().allows_motor());
    }

    #[test]
    fn a_restored_latch_holds_until_recharged() {
        let mut m = BatteryMonitor::new(CFG);
        m.restore_cutoff_latch();
        // A depleted cell recovered at rest reads 3.6 V: still cut off.
        let t = hold(&mut m, 3_600, 0, 2_000_000, false);
        assert_eq!(m.status().level, BatteryLevel::Cutoff);
        hold(&mut m, 4_000, t, 400_000, false);
        assert_eq!(m.status().level, BatteryLevel::Ok);
        assert!(!m.cutoff_latched());
    }

    #[test]
    fn reference_tolerance_moves_the_reading_by_a_tenth_of_a_volt() {
        // A rail 3 % low reads the cell 3 % high, 0.1 V at the cut-off (it
        // would trip 0.1 V late): why board.rs has a calibration constant.
        let low_ref = BatteryConfig::new(100_000, 82_000, 3_201);
        let counts = low_ref.mv_to_counts(3_300);
        let read_nominal = CFG.counts_to_mv(counts);
        assert!((3_380..3_420).contains(&read_nominal), "{read_nominal}");
        let calibrated = low_ref.counts_to_mv(counts);
        assert!(calibrated.abs_diff(3_300) <= 2, "{calibrated}");
    }

    proptest! {
        /// Whatever the readings and timestamps (even going backwards), no
        /// panic, the average stays within the samples' range, and the
        /// latch never releases under load.
        #[test]
        fn never_panics_and_latch_holds_under_load(
            samples in proptest::collection::vec((any::<u16>(), any::<u64>(), any::<bool>()), 1..200),
        ) {
            let mut m = BatteryMonitor::new(CFG);
            let mut was_cut = false;
            for (counts, t, motor_on) in samples {
                let s = m.sample(counts, t, motor_on);
                prop_assert!(u32::from(s.mv) <= CFG.counts_to_mv(4_095));
                if was_cut && motor_on {
                    prop_assert!(matches!(s.level, BatteryLevel::Cutoff | BatteryLevel::Fault));
                }
                was_cut = m.latched;
            }
        }

        /// Counts -> mV -> counts round-trips within one code.
        #[test]
        fn conversion_round_trips(counts in 0u16..4096) {
            let back = CFG.mv_to_counts(CFG.counts_to_mv(counts));
            prop_assert!((i32::from(back) - i32::from(counts)).abs() <= 1);
        }
    }
}
