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
        let cooled_us = u64::from(cfg.housing.tau_ms) * 1_000 * COOLED_AFTER_TAUS;
        if duty_q16 == 0 && dt_us >= cooled_us {
            *self = Heating::default();
            return;
        }
        let (p_motor, p_driver) = powers_uw(cfg, duty_q16, cell_mv);
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

/// Mean copper losses (uW) of the motor and the driver: the on-pulse
/// current `V_cell / (R_motor + R_driver)` flowing `duty` of the time.
pub fn powers_uw(cfg: &ThermalConfig, duty_q16: u32, cell_mv: u32) -> (i64, i64) {
    let r_total = i64::from(cfg.motor_resistance_mohm) + i64::from(cfg.driver_resistance_mohm);
    if r_total == 0 {
        return (0, 0);
    }
    let duty = i64::from(duty_q16.min(1 << 16));
    let v = i64::from(cell_mv.min(10_000));
    // I [uA] = V [mV] * 1e6 / R [mohm], at most 100 A so that nothing
    // below overflows whatever the configuration; P [uW] = I^2 R.
    let i_ua = (v * 1_000_000 / r_total).min(100_000_000);
    let on = |r_mohm: u32| {
        let p = i_ua * i_ua / 1_000 * i64::from(r_mohm.min(1_000_000)) / 1_000_000;
        p.min(MAX_POWER_UW)
    };
    let mean = |p_on: i64| p_on * duty >> 16;
    (
        mean(on(cfg.motor_resistance_mohm)),
        mean(on(cfg.driver_resistance_mohm)),
    )
}
