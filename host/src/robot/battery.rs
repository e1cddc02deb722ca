//! The robot's 1-cell Li-Po (3.7 V nominal, 70 mAh; Table I: 5.5 x 14 x
//! 17 mm, a "551417" pouch cell): open-circuit voltage by state of charge,
//! an internal resistance, and coulomb counting.
//!
//! Deliberately simple (no RC polarisation branches): the controller
//! tests need the slow sag of the open-circuit voltage over a run and the
//! instant IR drop when the motor starts, and nothing between.

/// Rest (open-circuit) voltage against state of charge for a LiCoO2 pouch
/// cell at room temperature: the widely published hobby Li-Po table
/// (5 % steps), which agrees with generic cell-maker discharge curves at
/// low rates. Must be sorted by state of charge.
pub const LIPO_OCV_TABLE: [(f64, f64); 21] = [
    (0.00, 3.27),
    (0.05, 3.61),
    (0.10, 3.69),
    (0.15, 3.71),
    (0.20, 3.73),
    (0.25, 3.75),
    (0.30, 3.77),
    (0.35, 3.79),
    (0.40, 3.80),
    (0.45, 3.82),
    (0.50, 3.84),
    (0.55, 3.85),
    (0.60, 3.87),
    (0.65, 3.91),
    (0.70, 3.95),
    (0.75, 3.98),
    (0.80, 4.02),
    (0.85, 4.08),
    (0.90, 4.11),
    (0.95, 4.15),
    (1.00, 4.20),
];

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiPoParams {
    /// Rated capacity (Table I: 70 mAh).
    pub capacity_mah: f64,
    /// DC internal resistance. Small pouch cells of 50-100 mAh list
    /// 0.3-0.5 ohm AC impedance at 1 kHz; the DC resistance seen by a
    /// ~0.4 A load step is about twice that. 0.6 ohm is assumed (the
    /// expected range is 0.5-1 ohm).
    pub internal_resistance_ohm: f64,
}

impl LiPoParams {
    pub const CELL_70MAH: LiPoParams = LiPoParams {
        capacity_mah: 70.0,
        internal_resistance_ohm: 0.6,
    };
}

#[derive(Clone, Debug, PartialEq)]
pub struct LiPo {
    pub params: LiPoParams,
    /// Charge still in the cell, coulombs.
    charge_c: f64,
}

impl LiPo {
    /// A cell at `soc` (0..=1, clamped).
    pub fn with_soc(params: LiPoParams, soc: f64) -> Self {
        let full = params.capacity_mah * 3.6;
        Self {
            params,
            charge_c: soc.clamp(0.0, 1.0) * full,
        }
    }

    pub fn full(params: LiPoParams) -> Self {
        Self::with_soc(params, 1.0)
    }

    pub fn capacity_c(&self) -> f64 {
        self.params.capacity_mah * 3.6
    }

    pub fn soc(&self) -> f64 {
        self.charge_c / self.capacity_c()
    }

    /// Open-circuit voltage, linear between table points.
    pub fn ocv_v(&self) -> f64 {
        ocv_at(self.soc())
    }

    /// Terminal voltage while `current_a` flows out of the cell.
    pub fn terminal_v(&self, current_a: f64) -> f64 {
        self.ocv_v() - self.params.internal_resistance_ohm * current_a
    }

    /// Draw `current_a` for `dt_s` (coulomb counting; negative charges).
    /// The charge stops at empty and full.
    pub fn draw(&mut self, current_a: f64, dt_s: f64) {
        self.charge_c = (self.charge_c - current_a * dt_s).clamp(0.0, self.capacity_c());
    }
}

/// Open-circuit voltage at state of charge `soc` (clamped to 0..=1).
pub fn ocv_at(soc: f64) -> f64 {
    let soc = soc.clamp(0.0, 1.0);
    let upper = LIPO_OCV_TABLE
        .iter()
        .position(|&(s, _)| s >= soc)
        .unwrap_or(LIPO_OCV_TABLE.len() - 1)
        .max(1);
    let (s0, v0) = LIPO_OCV_TABLE[upper - 1];
    let (s1, v1) = LIPO_OCV_TABLE[upper];
    v0 + (v1 - v0) * (soc - s0) / (s1 - s0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    #[test]
    fn table_ends_and_interpolation() {
        assert_relative_eq!(ocv_at(1.0), 4.20);
        assert_relative_eq!(ocv_at(0.0), 3.27);
        assert_relative_eq!(ocv_at(0.475), 3.83, epsilon = 1e-12);
        assert_relative_eq!(ocv_at(2.0), 4.20);
        assert_relative_eq!(ocv_at(-1.0), 3.27);
    }

    #[test]
    fn coulomb_counting_matches_the_paper_runtime() {
        // ~0.42 A (70 mAh / 10 min) empties the cell in 10 minutes.
        let mut cell = LiPo::full(LiPoParams::CELL_70MAH);
        let i = 0.070 / (10.0 / 60.0);
        for _ in 0..600 {
            cell.draw(i, 1.0);
        }
        assert!(cell.soc() < 1e-9, "{}", cell.soc());
        cell.draw(1.0, 10.0);
        assert_eq!(cell.soc(), 0.0, "never below empty");
    }

    #[test]
    fn internal_resistance_sags_the_terminal() {
        let cell = LiPo::with_soc(LiPoParams::CELL_70MAH, 0.5);
        assert_relative_eq!(
            cell.terminal_v(0.0) - cell.terminal_v(0.4),
            0.24,
            epsilon = 1e-12
        );
    }

    proptest! {
        #[test]
        fn ocv_is_monotonic(a in 0.0f64..=1.0, b in 0.0f64..=1.0) {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prop_assert!(ocv_at(lo) <= ocv_at(hi));
            prop_assert!((3.27..=4.2).contains(&ocv_at(a)));
        }
    }
}
