//! Numbers and changes as the page writes them. Numbers: percentages to
//! one decimal, reduced chi-square to 3 significant figures (`8.23e6`), a
//! value with its uncertainty as the uncertainty to 2 significant figures
//! and the value to the same decimal place (the project's number policy,
//! `crate::format`). Changes: a step
//! is called a fall or a rise only when it is larger than the noise and
//! than a few per cent of the value it starts from; a rise is never
//! worded as progress.

use crate::format::fmt_sig;

/// A change smaller than this share of the starting value is no change.
pub const FLAT_SHARE: f64 = 0.03;

/// `12.3 %` from a fraction.
pub fn pct(fraction: f64) -> String {
    if fraction.is_finite() {
        format!("{:.1} %", 100.0 * fraction)
    } else {
        "n/a".into()
    }
}

/// `+12.3 %` from a signed fraction.
pub fn signed_pct(fraction: Option<f64>) -> String {
    fraction.map_or("-".into(), |f| format!("{:+.1} %", 100.0 * f))
}

/// A statistic (MARE, reduced chi-square) to 3 significant figures in the
/// project's number policy (`8.23e6`), or "n/a".
pub fn stat(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite())
        .map_or_else(|| "n/a".into(), |v| fmt_sig(v, 3))
}

/// `0.2609 ± 0.0040`, by the project's policy ([`crate::format::fmt_value_unc`]).
pub fn value_unc(value: f64, unc: f64) -> String {
    crate::format::fmt_value_unc(value, unc)
}

/// Which way a quantity moved from one step to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Change {
    Falls,
    Rises,
    /// Within the noise or within [`FLAT_SHARE`] of the starting value.
    Flat,
}

impl Change {
    /// Classify `from -> to`; `noise` is the smallest change that counts.
    pub fn of(from: f64, to: f64, noise: f64) -> Change {
        let d = to - from;
        if !(from.is_finite() && to.is_finite())
            || d.abs() <= (FLAT_SHARE * from.abs()).max(noise.abs())
        {
            Change::Flat
        } else if d < 0.0 {
            Change::Falls
        } else {
            Change::Rises
        }
    }

    pub fn word(self) -> &'static str {
        match self {
            Change::Falls => "falls",
            Change::Rises => "rises",
            Change::Flat => "no real change",
        }
    }
}

/// "falls from 294.6 % to 33.3 %", "rises from 45.3 % to 90.2 %", "stays
/// at 45.3 % (45.1 %: within the noise)", with the numbers as `show` writes them.
pub fn describe(from: f64, to: f64, noise: f64, show: impl Fn(f64) -> String) -> String {
    match Change::of(from, to, noise) {
        Change::Flat => format!(
            "stays at {} ({} after the step: within the noise or {:.0} %)",
            show(from),
            show(to),
            100.0 * FLAT_SHARE
        ),
        c => format!("{} from {} to {}", c.word(), show(from), show(to)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rise_is_worded_as_a_rise_and_a_small_change_as_none() {
        let mare = |x: f64| pct(x);
        let up = describe(0.453, 0.901, 0.01, mare);
        assert!(up.starts_with("rises from 45.3 % to 90.1 %"), "{up}");
        let down = describe(2.946, 0.333, 0.01, mare);
        assert!(down.starts_with("falls from 294.6 % to 33.3 %"), "{down}");
        // 2 % relative, or below the noise: no progress claimed
        assert_eq!(Change::of(0.30, 0.294, 0.001), Change::Flat);
        assert_eq!(Change::of(0.30, 0.25, 0.08), Change::Flat);
        assert!(describe(0.30, 0.294, 0.001, mare).starts_with("stays at 30.0 %"));
    }

    #[test]
    fn values_with_uncertainty_follow_the_uncertainty_s_two_figures() {
        assert_eq!(value_unc(0.2609, 0.0040), "0.2609 ± 0.0040");
        assert_eq!(value_unc(0.5860, 0.0640), "0.586 ± 0.064");
        assert_eq!(value_unc(0.0998, 0.0006), "0.09980 ± 0.00060");
        assert_eq!(value_unc(123.4, 15.0), "123 ± 15");
        assert_eq!(stat(Some(8228626.1208)), "8.23e6");
        assert_eq!(stat(Some(786720.3)), "7.87e5");
        assert_eq!(stat(Some(4.678)), "4.68");
    }
}
