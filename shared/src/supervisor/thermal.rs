//! The motor's and the driver's heating from their `I^2 t`: a lumped
//! thermal network per part, integrated by forward Euler in integer units.
//!
//! The motor is the two-node network of coreless-motor datasheets (winding
//! -> housing through `R_th1`, housing -> ambient through `R_th2`, each
//! node a heat capacity `C = tau / R_th`):
//!
//! ```text
//! C_1 dT_1/dt = P - (T_1 - T_2) / R_th1
//! C_2 dT_2/dt = (T_1 - T_2) / R_th1 - T_2 / R_th2
//! ```
//!
//! with `T` the rise above ambient; the driver (MOSFET and freewheel
//! diode) is one node, `C dT/dt = P - T / R_thJA`. The heat is the copper
//! loss: a coreless motor's electrical time constant `L / R` (a few
//! microseconds) is far below the 40 us PWM period, so the current follows
//! each on-pulse, `I = (V_cell - E) / R`, and the mean loss is
//! `duty (V_cell - E)^2 / R`. The back-EMF `E` (5 mV per Hz of this
//! motor) is left out: below 1 % of the drive at the tail's rates, and
//! leaving it out overestimates the heat, never the reverse.
//!
//! Units: rises in microkelvin, powers in microwatts, times in
//! microseconds, heat capacities in microjoules per kelvin
//! (`uW * us / (uJ/K) = uK`). Euler steps are at most `tau_1 / 8`, stable
//! and within a few per cent of the exact exponential at that step.

/// One lumped thermal node: thermal resistance to the next node (or the
/// ambient) and time constant, both from a datasheet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ThermalNode {
    pub r_th_mk_per_w: u32,
    pub tau_ms: u32,
}

impl ThermalNode {
    /// `C = tau / R_th` in uJ/K (at least 1).
    const fn capacity_uj_per_k(self) -> i64 {
        let r = if self.r_th_mk_per_w == 0 {
            1
        } else {
            self.r_th_mk_per_w as i64
        };
        let c = self.tau_ms as i64 * 1_000_000 / r;
        if c < 1 {
            1
        } else {
            c
        }
    }

    /// Heat flow in uW through this node's resistance across `dt_uk`.
    fn flow_uw(self, dt_uk: i64) -> i64 {
        dt_uk * 1_000 / i64::from(self.r_th_mk_per_w.max(1))
    }
}

/// The parts' thermal data and the rises they may reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ThermalConfig {
    /// Motor terminal resistance (copper, at 25 C).
    pub motor_resistance_mohm: u32,
    pub winding: ThermalNode,
    pub housing: ThermalNode,
    /// The winding's allowed rise above the ambient (mK).
    pub winding_rise_max_mk: u32,
    /// After an overheat a new start waits until the winding is back
    /// below this rise (mK).
    pub winding_restart_mk: u32,
    /// The driver's on-resistance plus the freewheel diode's share,
    /// as one equivalent resistance (mohm), and its junction node.
    pub driver_resistance_mohm: u32,
    pub driver: ThermalNode,
    pub driver_rise_max_mk: u32,
}

/// The estimated rises above ambient (uK).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Heating {
    pub winding_uk: i64,
    pub housing_uk: i64,
    pub driver_uk: i64,
}

/// A pause this long (off) is taken as cooled down: five of the housing's
/// time constants leave under 1 % of any rise.
const COOLED_AFTER_TAUS: u64 = 5;

impl Heating {
    /// Advance by `dt_us` at `duty_q16` (1/65536) of a cell at `cell_mv`.
    pub fn advance(&mut self, cfg: &ThermalConfig, dt_us: u64, duty_q16: u32, cell_mv: u32) {
        self.advance_mean(cfg, dt_us, duty_v2(duty_q16, cell_mv));
    }

    /// Advance by `dt_us` at a mean `duty V_cell^2` (1/65536 mV^2, as
    /// [`duty_v2`] gives it): the on-pulse loss's mean over the interval.
    pub fn advance_mean(&mut self, cfg: &ThermalConfig, dt_us: u64, mean_duty_v2: u64) {
        let cooled_us = u64::from(cfg.housing.tau_ms) * 1_000 * COOLED_AFTER_TAUS;
        if mean_duty_v2 == 0 && dt_us >= cooled_us {
            *self = Heating::default();
            return;
        }
        let (p_motor, p_driver) = powers_of(cfg, mean_duty_v2);
        let max_step = (u64::from(cfg.winding.tau_ms) * 1_000 / 8).clamp(1_000, 1_000_000);
        // A long pause with the motor on cannot happen (the pass runs every
        // millisecond); bound the loop anyway (ten minutes at most).
        let mut left = dt_us.min(cooled_us).min(600_000_000);
        while left > 0 {
            let step = left.min(max_step);
            left -= step;
            self.euler(cfg, step as i64, p_motor, p_driver);
        }
    }

    fn euler(&mut self, cfg: &ThermalConfig, dt_us: i64, p_motor: i64, p_driver: i64) {
        let q12 = cfg.winding.flow_uw(self.winding_uk - self.housing_uk);
        let q2a = cfg.housing.flow_uw(self.housing_uk);
        let qd = cfg.driver.flow_uw(self.driver_uk);
        self.winding_uk += (p_motor - q12) * dt_us / cfg.winding.capacity_uj_per_k();
        self.housing_uk += (q12 - q2a) * dt_us / cfg.housing.capacity_uj_per_k();
        self.driver_uk += (p_driver - qd) * dt_us / cfg.driver.capacity_uj_per_k();
        // Cooling never undershoots the ambient.
        self.winding_uk = self.winding_uk.clamp(0, MAX_RISE_UK);
        self.housing_uk = self.housing_uk.clamp(0, MAX_RISE_UK);
        self.driver_uk = self.driver_uk.clamp(0, MAX_RISE_UK);
    }

    /// A part is past its allowed rise.
    pub fn overheated(&self, cfg: &ThermalConfig) -> bool {
        self.winding_uk > i64::from(cfg.winding_rise_max_mk) * 1_000
            || self.driver_uk > i64::from(cfg.driver_rise_max_mk) * 1_000
    }

    /// Cool enough for a new start after an overheat.
    pub fn may_restart(&self, cfg: &ThermalConfig) -> bool {
        self.winding_uk <= i64::from(cfg.winding_restart_mk) * 1_000
            && self.driver_uk <= i64::from(cfg.driver_rise_max_mk) * 500
    }
}

/// Powers are bounded (1 kW) so that the integration cannot overflow.
const MAX_POWER_UW: i64 = 1_000_000_000;
/// Rises are bounded (1000 K): far past any trip, and no overflow.
const MAX_RISE_UK: i64 = 1_000_000_000;

/// `duty V_cell^2` in 1/65536 mV^2 (the cell taken at most 10 V): what the
/// supervisor sums each pass, with multiplications only (a 64-bit
/// division is hundreds of cycles on the Cortex-M0+).
pub fn duty_v2(duty_q16: u32, cell_mv: u32) -> u64 {
    let v = u64::from(cell_mv.min(10_000));
    u64::from(duty_q16.min(1 << 16)) * v * v
}

/// Mean copper losses (uW) of the motor and the driver: the on-pulse
/// current `V_cell / (R_motor + R_driver)` flowing `duty` of the time.
pub fn powers_uw(cfg: &ThermalConfig, duty_q16: u32, cell_mv: u32) -> (i64, i64) {
    powers_of(cfg, duty_v2(duty_q16, cell_mv))
}

/// The losses at a mean `duty V_cell^2`: `P_x = duty V^2 R_x / R_total^2`
/// (mV^2 / mohm = mW), bounded so that nothing overflows whatever the
/// configuration.
fn powers_of(cfg: &ThermalConfig, mean_duty_v2: u64) -> (i64, i64) {
    let r_total = u64::from(cfg.motor_resistance_mohm) + u64::from(cfg.driver_resistance_mohm);
    if r_total == 0 {
        return (0, 0);
    }
    let v2_mv2 = (mean_duty_v2 >> 16).min(100_000_000);
    let r2 = r_total * r_total;
    let of = |r_mohm: u32| {
        let p = v2_mv2 * u64::from(r_mohm.min(1_000_000)) * 1_000 / r2;
        i64::try_from(p).unwrap_or(MAX_POWER_UW).min(MAX_POWER_UW)
    };
    (
        of(cfg.motor_resistance_mohm),
        of(cfg.driver_resistance_mohm),
    )
}
