//! Axes: the range a chart shows (padded, flat data given a sensible
//! minimum span so float noise is never magnified into spikes), linear or
//! log mapping, and tick positions with labels a reader expects (1-2-5
//! steps, no "360.0", powers of ten on log axes).

use super::svg_text::power_of_ten;
use crate::format::fmt_trim;

/// One axis: the shown range of data values and its scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
}

/// A flat series is shown over at least this fraction of its magnitude, so
/// float noise (1e-9 of the value) is not drawn as a sawtooth.
const MIN_REL_SPAN: f64 = 0.1;
/// Padding on each side, as a fraction of the span.
const PAD: f64 = 0.06;
/// The widest axis drawn, in the scale's own units (decades on a log
/// axis): beyond it `10^x` or the span overflows, and the ticks counted
/// across it are unbounded (a stored prediction of 1e308 asked for
/// gigabytes of them).
const LOG_LIMIT: f64 = 300.0;
const LINEAR_LIMIT: f64 = 1e300;
/// More ticks than a chart could ever draw: none are drawn instead.
const MAX_TICKS: i64 = 10_000;

impl Axis {
    /// The axis that shows `values` (non-finite ones ignored; non-positive
    /// ones ignored on a log axis).
    pub fn fit(values: impl Iterator<Item = f64>, log: bool, include_zero: bool) -> Self {
        let t = |v: f64| if log { v.log10() } else { v };
        let (mut lo, mut hi) = values
            .filter(|v| v.is_finite() && (!log || *v > 0.0))
            .map(t)
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
        if lo > hi {
            (lo, hi) = (0.0, 1.0);
        }
        let limit = if log { LOG_LIMIT } else { LINEAR_LIMIT };
        (lo, hi) = (lo.clamp(-limit, limit), hi.clamp(-limit, limit));
        if include_zero && !log {
            lo = lo.min(0.0);
            hi = hi.max(0.0);
        }
        let mid = 0.5 * (lo + hi);
        let min_span = if log {
            0.5
        } else if mid == 0.0 {
            1.0
        } else {
            MIN_REL_SPAN * mid.abs()
        };
        if hi - lo < min_span {
            lo = mid - 0.5 * min_span;
            hi = mid + 0.5 * min_span;
        }
        // Bars of values of one sign stand on the zero line: no padding
        // past it (a MARE axis does not run to -20 %).
        let zeroed = include_zero && !log;
        let (floor, ceiling) = (zeroed && lo == 0.0, zeroed && hi == 0.0);
        let pad = PAD * (hi - lo);
        let lo = if floor { lo } else { lo - pad }.clamp(-limit, limit);
        let hi = if ceiling { hi } else { hi + pad }.clamp(-limit, limit);
        let back = |v: f64| if log { 10f64.powf(v) } else { v };
        Self {
            lo: back(lo),
            hi: back(hi),
            log,
        }
    }

    /// Whether values spanning `lo..hi` (both > 0) deserve a log axis.
    pub fn spans_decade(values: impl Iterator<Item = f64>) -> bool {
        let (lo, hi) = values
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
        lo < hi && hi / lo > 10.0
    }

    fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// Position of `v` along the axis, 0 at `lo` and 1 at `hi`; `None` for
    /// values the axis cannot show (non-finite, or <= 0 on a log axis).
    pub fn frac(&self, v: f64) -> Option<f64> {
        if !v.is_finite() || (self.log && v <= 0.0) {
            return None;
        }
        Some((self.t(v) - self.t(self.lo)) / (self.t(self.hi) - self.t(self.lo)))
    }

    /// Labelled ticks inside the range, about `target` of them.
    pub fn ticks(&self, target: f64) -> Vec<(f64, String)> {
        if !self.drawable() {
            return Vec::new();
        }
        if self.log {
            return self.log_ticks();
        }
        let step = nice_step((self.hi - self.lo) / target.max(2.0));
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        if last.saturating_sub(first) > MAX_TICKS {
            return Vec::new();
        }
        (first..=last)
            .map(|i| {
                let v = i as f64 * step;
                (v, linear_label(v, step))
            })
            .collect()
    }

    /// Unlabelled minor ticks (log axes: 2..9 times each power of ten).
    pub fn minor_ticks(&self) -> Vec<f64> {
        if !self.log || !self.drawable() {
            return Vec::new();
        }
        let (e0, e1) = (
            decade(self.lo.log10().floor()),
            decade(self.hi.log10().ceil()),
        );
        if e1 - e0 > 8 {
            // Many decades: the unlabelled powers of ten only.
            return (e0..=e1)
                .map(|e| 10f64.powi(e))
                .filter(|v| *v >= self.lo && *v <= self.hi)
                .collect();
        }
        (e0..=e1)
            .flat_map(|e| (2..10).map(move |m| m as f64 * 10f64.powi(e)))
            .filter(|v| *v >= self.lo && *v <= self.hi)
            .collect()
    }

    fn log_ticks(&self) -> Vec<(f64, String)> {
        let (e0, e1) = (
            decade(self.lo.log10().ceil()),
            decade(self.hi.log10().floor()),
        );
        if e1 - e0 < 1 {
            // Less than a decade shown: 1-2-5 ticks, written plainly.
            return (e0 - 1..=e1)
                .flat_map(|e| [1.0, 2.0, 5.0].map(|m| (m, e)))
                .map(|(m, e)| (m * 10f64.powi(e), e))
                .filter(|(v, _)| *v >= self.lo && *v <= self.hi)
                .map(|(v, e)| (v, linear_label(v, 10f64.powi(e))))
                .collect();
        }
        let every = (e1 - e0) / 8 + 1;
        (e0..=e1)
            .filter(|e| e.rem_euclid(every) == 0)
            .map(|e| (10f64.powi(e), power_of_ten(e)))
            .collect()
    }
}

impl Axis {
    /// Finite ends in order (positive on a log axis): an axis made by hand
    /// or from a corrupt file may be neither, and then has no ticks.
    fn drawable(&self) -> bool {
        self.lo.is_finite()
            && self.hi.is_finite()
            && self.lo <= self.hi
            && (!self.log || self.lo > 0.0)
    }
}

/// A power of ten's exponent, within what an `f64` holds.
fn decade(e: f64) -> i32 {
    e.clamp(-330.0, 330.0) as i32
}

/// The 1, 2 or 5 times a power of ten closest (in ratio) to `raw`.
fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .min_by(|a, b| (a / raw).ln().abs().total_cmp(&(b / raw).ln().abs()))
        .unwrap_or(p)
}

/// A tick value with the digits its step needs and no trailing zeros
/// ("1", "1.5", never "360.0"), or as `m×10ⁿ` for magnitudes a reader
/// should not count zeros in.
fn linear_label(v: f64, step: f64) -> String {
    if v.abs() < 1e-9 * step {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    let step_mag = (step.log10() + 1e-9).floor() as i32;
    if mag >= 5 || mag <= -4 {
        let decimals = (mag - step_mag).clamp(0, 3) as usize;
        let m = format!("{:.decimals$}", v / 10f64.powi(mag));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m
        };
        return if m == "1" {
            power_of_ten(mag)
        } else {
            format!("{m}×{}", power_of_ten(mag))
        };
    }
    fmt_trim(v, (mag - step_mag + 1).max(1) as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(a: Axis) -> Vec<String> {
        a.ticks(6.0).into_iter().map(|t| t.1).collect()
    }

    #[test]
    fn bars_of_one_sign_stand_on_zero() {
        let up = Axis::fit([5.0, 8.0, 10.0].into_iter(), false, true);
        assert_eq!(up.lo, 0.0);
        assert!(up.hi > 10.0);
        assert!(labels(up).iter().all(|l| !l.starts_with('-')));
        let down = Axis::fit([-5.0, -8.0].into_iter(), false, true);
        assert_eq!(down.hi, 0.0);
        assert!(down.lo < -8.0);
        // Without the zero line both ends are padded.
        let free = Axis::fit([5.0, 8.0, 10.0].into_iter(), false, false);
        assert!(free.lo < 5.0 && free.lo > 0.0);
    }

    #[test]
    fn integer_steps_have_no_decimals() {
        let a = Axis::fit([0.0, 360.0].into_iter(), false, false);
        let l = labels(a);
        assert!(l.contains(&"100".to_string()), "{l:?}");
        assert!(l.iter().all(|s| !s.contains('.')), "{l:?}");
        let b = Axis::fit([0.1, 0.45].into_iter(), false, false);
        assert!(labels(b).contains(&"0.2".to_string()), "{:?}", labels(b));
        let c = Axis::fit([0.4, 2.1].into_iter(), false, false);
        assert!(labels(c).contains(&"1".to_string()), "{:?}", labels(c));
    }

    #[test]
    fn large_linear_values_are_not_written_out() {
        let a = Axis::fit([0.0, 1e7].into_iter(), false, false);
        let l = labels(a);
        assert!(l.iter().all(|s| s.len() < 9), "{l:?}");
        assert!(l.iter().any(|s| s.contains('⁶')), "{l:?}");
    }

    #[test]
    fn log_axes_are_labelled_with_powers_of_ten() {
        let a = Axis::fit([0.03, 2e6].into_iter(), true, false);
        let l = labels(a);
        assert!(l.contains(&"10⁰".to_string()), "{l:?}");
        assert!(l.contains(&"10⁻¹".to_string()), "{l:?}");
        assert!(!a.minor_ticks().is_empty() || l.len() > 7);
    }

    #[test]
    fn flat_data_gets_a_minimum_span() {
        let a = Axis::fit([4.0, 4.0 + 1e-9, 4.0 - 1e-9].into_iter(), false, false);
        assert!(a.hi - a.lo >= 0.4 - 1e-12, "{a:?}");
        let z = Axis::fit([0.0, 0.0].into_iter(), false, false);
        assert!(z.hi - z.lo >= 1.0);
        // Real variation is untouched.
        let v = Axis::fit([3.75, 4.2].into_iter(), false, false);
        assert!(v.hi - v.lo < 0.6);
    }

    #[test]
    fn extreme_values_give_a_bounded_finite_axis() {
        for (values, log) in [
            (vec![1.0, 1e308], true),
            (vec![1e-320, 1.0], true),
            (vec![f64::MIN_POSITIVE, f64::MAX], true),
            (vec![-1e308, 1e308], false),
            (vec![f64::MAX, f64::MAX], false),
        ] {
            let a = Axis::fit(values.into_iter(), log, false);
            assert!(a.lo.is_finite() && a.hi.is_finite() && a.lo < a.hi, "{a:?}");
            let (t, m) = (a.ticks(6.0), a.minor_ticks());
            assert!(
                t.len() < 100 && m.len() < 1000,
                "{a:?}: {} {}",
                t.len(),
                m.len()
            );
            assert!(t.iter().all(|(v, _)| v.is_finite()), "{a:?}");
        }
        // An axis no fit makes (a corrupt file's numbers) has no ticks.
        for a in [
            Axis {
                lo: 0.0,
                hi: f64::INFINITY,
                log: true,
            },
            Axis {
                lo: f64::NEG_INFINITY,
                hi: 1.0,
                log: false,
            },
            Axis {
                lo: -1e308,
                hi: 1e308,
                log: false,
            },
        ] {
            assert!(a.ticks(6.0).len() <= MAX_TICKS as usize + 1, "{a:?}");
            assert!(a.minor_ticks().len() < 10_000, "{a:?}");
        }
    }

    #[test]
    fn mapping_and_decade_test() {
        let a = Axis {
            lo: 1.0,
            hi: 100.0,
            log: true,
        };
        assert!((a.frac(10.0).unwrap() - 0.5).abs() < 1e-12);
        assert_eq!(a.frac(0.0), None);
        assert!(Axis::spans_decade([0.2, 2.5].into_iter()));
        assert!(!Axis::spans_decade([0.2, 1.5].into_iter()));
    }
}
