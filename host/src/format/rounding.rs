//! Values with their standard uncertainty as JCGM 100 (the GUM) sec. 7.2.6
//! asks them printed: the uncertainty to two significant digits, the value
//! to the same decimal place, so that no digit is quoted that the
//! uncertainty does not support.

use crate::format::fmt_sig;

/// `value ± u`, both rounded at the uncertainty's second significant digit
/// (`0.8146 ± 0.0227` -> `0.815 ± 0.023`); very large or small numbers
/// share one power of ten (`(1.23 ± 0.45)e-7`). Without a finite positive
/// `u`, the value to four significant digits.
pub fn value_pm(value: f64, u: Option<f64>) -> String {
    let Some(u) = u.filter(|u| u.is_finite() && *u > 0.0) else {
        return fmt_sig(value, 4);
    };
    let scale = value.abs().max(u);
    let e = scale.log10().floor() as i32;
    if !(-3..6).contains(&e) {
        let p = 10f64.powi(e);
        let (v, w) = (value / p, u / p);
        return format!("({} ± {})e{e}", fixed(v, w), fixed(w, w));
    }
    format!("{} ± {}", fixed(value, u), fixed(u, u))
}

/// `x` at the decimal place of `u`'s second significant digit.
fn fixed(x: f64, u: f64) -> String {
    let decimals = 1 - u.log10().floor() as i32;
    if decimals >= 0 {
        format!("{:.*}", decimals as usize, x)
    } else {
        let step = 10f64.powi(-decimals);
        format!("{:.0}", (x / step).round() * step)
    }
}

/// A relative uncertainty in % to two significant digits (`4.3 %`, a
/// no-break space before the sign so that a wrapped line never starts
/// with it).
pub fn percent(p: f64) -> String {
    format!("{}\u{a0}%", fmt_sig(p, 2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uncertainty_keeps_two_digits_and_the_value_its_decimal_place() {
        assert_eq!(value_pm(0.8145555, Some(0.02266)), "0.815 ± 0.023");
        assert_eq!(value_pm(2.325668, Some(0.2266)), "2.33 ± 0.23");
        assert_eq!(value_pm(25.72, Some(27.0)), "26 ± 27");
        assert_eq!(value_pm(1234.5, Some(123.0)), "1230 ± 120");
    }

    #[test]
    fn far_from_one_the_pair_shares_a_power_of_ten() {
        assert_eq!(value_pm(1.234e-7, Some(4.5e-9)), "(1.234 ± 0.045)e-7");
        assert_eq!(value_pm(9.1e7, Some(2.0e6)), "(9.10 ± 0.20)e7");
    }

    #[test]
    fn without_an_uncertainty_the_value_has_four_digits() {
        assert_eq!(value_pm(0.8145555, None), "0.8146");
        assert_eq!(value_pm(0.8145555, Some(f64::NAN)), "0.8146");
        assert_eq!(percent(9.7432), "9.7\u{a0}%");
    }
}
