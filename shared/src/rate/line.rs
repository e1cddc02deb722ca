//! The motor line learned on the run, `V = V_0 + s g f`: the intercept
//! `V_0` (the motor's friction `R tau_c / k` plus the
//! freewheel diode's share of each PWM period) and the slope factor `g` on
//! the configured lightest-load slope `s` (the tail's viscous load, which
//! the firmware cannot know).
//!
//! Both are measured, because a fixed intercept biases the slope: a
//! window at a constant voltage gives one point `(V_1, f_1)` of the line,
//! and the slope through it depends on the intercept assumed. Started
//! below the set-point (`f_1 < f_ref`), an assumed intercept lower than
//! the true one asks too much voltage: the first start overshot 11 % in
//! the emulator, whose motor's intercept (0.25 V) is not the board's
//! nominal 0.175 V. So while the intercept is unknown the first point
//! assumes the highest plausible intercept (`RateConfig::intercept_max_mv`,
//! and never more than the lightest line through the point allows), which
//! lands below the set-point whatever the truth in that range; a second
//! point at the voltage that asks for then gives both by the secant.
//! Started above (`f_1 > f_ref`) the conservative assumption is the low
//! one, the nominal intercept.
//!
//! The secant is taken only when the two rates differ by at least a
//! factor of two, so that a few per cent of pole-pattern error in each
//! quarter-turn rate moves the slope by a few per cent, not tens; the
//! intercept then counts as known and is kept across Off/On, as `g` is.
//!
//! Fixed point: mV, mHz, `g` in 1/65536.

use super::control::RateConfig;

const ONE: i64 = 1 << 16;

/// One point of the line: the voltage held over a window and the rate it
/// gave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinePoint {
    pub mv: u32,
    pub rate_mhz: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LearnedLine {
    pub intercept_mv: u32,
    pub gain_q16: u32,
    /// The intercept has been measured (a secant), not assumed.
    pub intercept_known: bool,
}

impl LearnedLine {
    pub const fn new(cfg: &RateConfig) -> Self {
        Self {
            intercept_mv: cfg.line.intercept_mv as u32,
            gain_q16: 1 << 16,
            intercept_known: false,
        }
    }

    /// The voltage for a reference rate, with the proportional factor `p`
    /// (1/65536 units, 1 + k_p e); zero for a zero reference.
    pub fn voltage_mv(&self, cfg: &RateConfig, ref_mhz: u32, p_q16: i64) -> u32 {
        if ref_mhz == 0 {
            return 0;
        }
        let slope_part = i64::from(cfg.line.slope_mv_per_hz) * i64::from(ref_mhz) / 1_000
            * i64::from(self.gain_q16)
            / ONE
            * p_q16.max(0)
            / ONE;
        u32::try_from((i64::from(self.intercept_mv) + slope_part).max(0)).unwrap_or(u32::MAX)
    }

    /// The line through one point with the intercept kept, or, while the
    /// intercept is unknown, the conservative one for the side the point
    /// lies on.
    pub fn one_point(&mut self, cfg: &RateConfig, at: LinePoint, ref_mhz: u32) {
        if !self.intercept_known {
            self.intercept_mv = if at.rate_mhz < ref_mhz {
                // Highest plausible, and below the lightest line's through the point.
                let lightest = u64::from(cfg.line.slope_mv_per_hz) * u64::from(at.rate_mhz) / 1_000;
                u64::from(cfg.intercept_max_mv).min(u64::from(at.mv).saturating_sub(lightest))
                    as u32
            } else {
                u32::from(cfg.line.intercept_mv).min(at.mv)
            };
        }
        self.through(cfg, at);
    }

    /// The line through two points (`a` the earlier, lower one), if they
    /// are far enough apart to tell slope from intercept; else nothing.
    pub fn secant(&mut self, cfg: &RateConfig, a: LinePoint, b: LinePoint) -> bool {
        if b.mv <= a.mv || u64::from(a.rate_mhz) * 2 > u64::from(b.rate_mhz) {
            return false;
        }
        let slope_mv_per_hz =
            i64::from(b.mv - a.mv) * 1_000 / i64::from(b.rate_mhz - a.rate_mhz).max(1);
        let intercept = i64::from(b.mv) - slope_mv_per_hz * i64::from(b.rate_mhz) / 1_000;
        let intercept = intercept.clamp(0, i64::from(cfg.intercept_max_mv).min(i64::from(a.mv)));
        self.intercept_mv = intercept as u32;
        self.intercept_known = true;
        // The slope through `b` with the clamped intercept.
        self.through(cfg, b);
        true
    }

    /// `g` for the line through `at` with the intercept in use.
    fn through(&mut self, cfg: &RateConfig, at: LinePoint) {
        let rise = i64::from(at.mv) - i64::from(self.intercept_mv);
        let g = rise * 1_000 * ONE
            / (i64::from(at.rate_mhz) * i64::from(cfg.line.slope_mv_per_hz)).max(1);
        self.set_gain(cfg, g);
    }

    /// The PI's integral action on `g`: `g <- g (1 + k_i e steps / E)`.
    pub fn integrate(&mut self, cfg: &RateConfig, rel_err_q16: i64, steps: i64, edges: i64) {
        let g = i64::from(self.gain_q16);
        let dg =
            g * i64::from(cfg.ki_per_turn_q16) / ONE * rel_err_q16 / ONE * steps / edges.max(1);
        self.set_gain(cfg, g + dg);
    }

    fn set_gain(&mut self, cfg: &RateConfig, g: i64) {
        let (lo, hi) = (
            i64::from(cfg.gain_min_q16),
            i64::from(cfg.gain_max_q16.max(cfg.gain_min_q16)),
        );
        self.gain_q16 = u32::try_from(g.clamp(lo, hi)).unwrap_or(cfg.gain_max_q16);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motor line `V = v0 + s f` (mV, mV/Hz): the rate at `mv`.
    fn rate_mhz(v0: u32, s: u32, mv: u32) -> u32 {
        (mv.saturating_sub(v0) as u64 * 1_000_000 / u64::from(s) / 1_000) as u32
    }

    #[test]
    fn the_secant_recovers_both_intercept_and_slope() {
        let cfg = RateConfig::DEFAULT;
        let mut line = LearnedLine::new(&cfg);
        // The emulator's rotor: 250 mV, 2.1 V/Hz; the set-point 1 Hz.
        let v1 = line.voltage_mv(&cfg, 1_000, ONE);
        let a = LinePoint {
            mv: v1,
            rate_mhz: rate_mhz(250, 2_100, v1),
        };
        line.one_point(&cfg, a, 1_000);
        let v2 = line.voltage_mv(&cfg, 1_000, ONE);
        let f2 = rate_mhz(250, 2_100, v2);
        assert!(
            f2 < 1_000,
            "the pessimistic first line lands below: {f2} mHz"
        );
        assert!(line.secant(
            &cfg,
            a,
            LinePoint {
                mv: v2,
                rate_mhz: f2
            }
        ));
        assert!(line.intercept_known);
        assert!(line.intercept_mv.abs_diff(250) <= 3, "{line:?}");
        let v3 = line.voltage_mv(&cfg, 1_000, ONE);
        assert!(rate_mhz(250, 2_100, v3).abs_diff(1_000) <= 3, "{v3} mV");
    }

    #[test]
    fn a_first_point_below_the_set_point_never_overshoots_within_the_bound() {
        let cfg = RateConfig::DEFAULT;
        for v0 in [0, 100, 175, 250, u32::from(cfg.intercept_max_mv)] {
            for s in [700, 1_500, 4_400, 5_600] {
                let mut line = LearnedLine::new(&cfg);
                let v1 = line.voltage_mv(&cfg, 500, ONE);
                let f1 = rate_mhz(v0, s, v1);
                if f1 == 0 || f1 >= 500 {
                    continue;
                }
                line.one_point(
                    &cfg,
                    LinePoint {
                        mv: v1,
                        rate_mhz: f1,
                    },
                    500,
                );
                let f2 = rate_mhz(v0, s, line.voltage_mv(&cfg, 500, ONE));
                // Within the rounding of f1 to whole mHz, which the jump
                // multiplies by 500 / f1.
                assert!(f2 <= 501 + 500 / f1, "v0 {v0} s {s}: {f1} -> {f2} mHz");
            }
        }
    }

    #[test]
    fn points_too_close_leave_the_intercept_alone() {
        let cfg = RateConfig::DEFAULT;
        let mut line = LearnedLine::new(&cfg);
        let a = LinePoint {
            mv: 1_000,
            rate_mhz: 600,
        };
        let b = LinePoint {
            mv: 1_200,
            rate_mhz: 700,
        };
        assert!(!line.secant(&cfg, a, b));
        assert!(!line.intercept_known);
        assert_eq!(line, LearnedLine::new(&cfg));
    }
}
