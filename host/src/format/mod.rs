//! Number formatting shared by every layer (tables, notes, figures, files):
//! the bottom of the import graph, so `effects` and `workbench` need not
//! reach up into `report`. One policy for every output:
//!
//! - **A value with its uncertainty** ([`fmt_value_unc`]): the uncertainty
//!   to 2 significant figures, the value rounded to the same decimal place
//!   (`0.2609 ± 0.0040`, `12.3 ± 1.5`, `0.0 ± 1.3`).
//! - **A bare value** ([`fmt_sig`]): the number of significant figures the
//!   caller states, trailing zeros kept (`0.2000` to 4 figures), because a
//!   dropped zero reads as a lost digit.
//! - **Magnitudes outside `1e-3 <= |v| < 1e5`** (after rounding) in one
//!   scientific style everywhere: Rust's `e` notation, mantissa to the
//!   stated figures, no `+` and no leading zeros in the exponent (`8.23e6`,
//!   `-1.62e-14`); a value with uncertainty shares one exponent:
//!   `(8.2286 ± 0.0030)e6`.
//! - **A parameter estimate** ([`fmt_estimate`]): as a value with its 95 %
//!   confidence half-width, and called `not identified` when that
//!   half-width exceeds ten times the value (the data do not fix even the
//!   order of magnitude).
//! - **Units** ([`with_unit`]): dimensionless quantities print no unit
//!   (never `1`).
//! - **Settings echoed back** ([`fmt_trim`]): parameter values inside model
//!   names or formulas, at most the stated figures with trailing zeros
//!   dropped, so that a user's `0.2` stays `0.2`.
//! - **Percentages**: `{:.1} %` at the call site (one decimal).
//! - **JSON**: full precision, serde's shortest round-trip representation;
//!   never rounded before serialising.
//! - **CSV** ([`csv_f64`]): Rust's `{}` for `f64` everywhere (plain decimal,
//!   shortest round-trip: `1.11026`, `0.000012`), never `{:e}`.
//! - **Non-finite**: `NaN`, `inf`, `-inf`; zero is `0`.

pub mod rounding;

/// Lowest magnitude written in plain decimal.
pub const PLAIN_MIN: f64 = 1e-3;
/// Magnitudes from this one up are written in scientific notation.
pub const PLAIN_MAX: f64 = 1e5;

/// Decimal exponent of `x` after rounding to `sig` significant figures,
/// and its mantissa as printed by `{:e}` (rounding-aware, so 9.996 to 3
/// figures has exponent 1).
fn sci_parts(x: f64, sig: usize) -> (String, i32) {
    let s = format!("{:.*e}", sig.max(1) - 1, x);
    let (m, e) = s.split_once('e').expect("`{:e}` always has an exponent");
    (m.to_string(), e.parse().expect("integer exponent"))
}

fn non_finite(v: f64) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

fn plain_exponent(e: i32) -> bool {
    // 1e-3 <= |v| < 1e5  <=>  -3 <= exponent <= 4.
    (-3..=4).contains(&e)
}

/// A bare value to `sig` significant figures, trailing zeros kept; plain
/// decimal for `1e-3 <= |v| < 1e5`, else `8.23e6` style.
pub fn fmt_sig(v: f64, sig: usize) -> String {
    let sig = sig.max(1);
    if !v.is_finite() {
        return non_finite(v);
    }
    if v == 0.0 {
        return "0".into();
    }
    let (mantissa, e) = sci_parts(v, sig);
    if !plain_exponent(e) {
        return format!("{mantissa}e{e}");
    }
    let decimals = sig as i32 - 1 - e;
    if decimals >= 0 {
        format!("{v:.*}", decimals as usize)
    } else {
        // More integer digits than figures: the rounded mantissa, scaled.
        let m: f64 = mantissa.parse().expect("mantissa");
        format!("{:.0}", m * 10f64.powi(e))
    }
}

/// At most `sig` significant figures with trailing zeros dropped, for
/// settings echoed back (a parameter in a model's name, a constant in a
/// formula), where extra zeros would claim a precision nobody measured.
pub fn fmt_trim(v: f64, sig: usize) -> String {
    let s = fmt_sig(v, sig);
    let (m, e) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), format!("e{e}")),
        None => (s.clone(), String::new()),
    };
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        m
    };
    format!("{m}{e}")
}

/// `v` rounded to the decimal place `10^place` (exact powers of ten for
/// the divisions, so 1e-3 stays 1e-3).
fn round_at(v: f64, place: i32) -> f64 {
    if place < 0 {
        let k = 10f64.powi(-place);
        (v * k).round() / k
    } else {
        let k = 10f64.powi(place);
        (v / k).round() * k
    }
}

/// A value with its uncertainty: the uncertainty to 2 significant figures,
/// the value to the same decimal place (`0.2609 ± 0.0040`); one shared
/// exponent outside the plain range (`(8.2286 ± 0.0030)e6`). A zero
/// uncertainty prints the value to 4 figures and `± 0`; a negative one is
/// taken by magnitude; non-finite parts print as `NaN`/`inf`.
pub fn fmt_value_unc(value: f64, unc: f64) -> String {
    let u = unc.abs();
    if !u.is_finite() || u == 0.0 {
        let shown_u = if u == 0.0 { "0".into() } else { non_finite(u) };
        return format!("{} ± {shown_u}", fmt_sig(value, 4));
    }
    let (_, e_u) = sci_parts(u, 2);
    // The place of the uncertainty's second figure.
    let place = e_u - 1;
    if !value.is_finite() {
        return format!("{} ± {}", non_finite(value), fmt_sig(u, 2));
    }
    let v_r = round_at(value, place);
    let u_r = round_at(u, place);
    let top = v_r.abs().max(u_r);
    let (_, e_top) = sci_parts(top, 17);
    if plain_exponent(e_top) {
        let decimals = (-place).max(0) as usize;
        format!("{:.*} ± {:.*}", decimals, v_r, decimals, u_r)
    } else {
        let scale = 10f64.powi(e_top);
        let decimals = (e_top - place).max(0) as usize;
        format!(
            "({:.*} ± {:.*})e{e_top}",
            decimals,
            v_r / scale,
            decimals,
            u_r / scale
        )
    }
}

/// How many times the value the 95 % half-width may be before the
/// estimate is reported as not identified.
pub const NOT_IDENTIFIED_RATIO: f64 = 10.0;

/// A fitted parameter with its 95 % confidence half-width: `1.23 ± 0.45`;
/// `not identified (0.0 ± 1.3)` when the half-width exceeds
/// [`NOT_IDENTIFIED_RATIO`] times the value; `1.234 (±?)` without one.
pub fn fmt_estimate(value: f64, ci95: Option<f64>) -> String {
    match ci95 {
        None => format!("{} (±?)", fmt_sig(value, 4)),
        Some(ci) if !ci.is_finite() => format!(
            "not identified ({} ± {})",
            fmt_sig(value, 4),
            non_finite(ci.abs())
        ),
        Some(ci) if ci.abs() > NOT_IDENTIFIED_RATIO * value.abs() => {
            format!("not identified ({})", fmt_value_unc(value, ci))
        }
        Some(ci) => fmt_value_unc(value, ci),
    }
}

/// `text unit`, or `text` alone for a dimensionless quantity (unit `1`,
/// `-` or empty).
pub fn with_unit(text: &str, unit: &str) -> String {
    match unit.trim() {
        "" | "1" | "-" | "dimensionless" => text.to_string(),
        u => format!("{text} {u}"),
    }
}

/// A CSV cell: Rust's `{}` for `f64` (plain decimal, shortest round-trip).
pub fn csv_f64(v: f64) -> String {
    format!("{v}")
}

/// Appends [`csv_f64`]'s text for `v` to `out`, byte for byte, several
/// times faster: the shortest round-trip digits from Ryū laid out as `{}`
/// lays them out, in plain decimal without a trailing `.0`. Both write the
/// shortest digits that read back as `v`, the closest to it among those;
/// they differ only at an exact tie between two such (`2^-25`, exactly
/// `2.98023223876953125e-8`: Ryū rounds the tie to even, `{}` up), which
/// is recognised and left to `{}`. For writers of millions of cells
/// (`sweep`), where `{}` cost more than the model itself.
pub fn push_csv_f64(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        out.extend_from_slice(csv_f64(v).as_bytes());
        return;
    }
    let mut buffer = ryu::Buffer::new();
    let text = buffer.format_finite(v).as_bytes();
    let (negative, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    // The significant digits and how many of them precede the point:
    // `1.234e-7` and `0.001234` and `12340.0` alike.
    let (mantissa, exponent) = match text.iter().position(|&b| b == b'e') {
        Some(e) => {
            let exponent: i64 = std::str::from_utf8(&text[e + 1..])
                .ok()
                .and_then(|x| x.parse().ok())
                .expect("Ryū writes an integer exponent");
            (&text[..e], exponent)
        }
        None => (text.strip_suffix(b".0").unwrap_or(text), 0),
    };
    let int_len = mantissa
        .iter()
        .position(|&b| b == b'.')
        .unwrap_or(mantissa.len());
    let mut digits = [0u8; 32];
    let mut n = 0;
    for &b in mantissa.iter().filter(|b| b.is_ascii_digit()) {
        digits[n] = b;
        n += 1;
    }
    let mut point = int_len as i64 + exponent;
    // Leading zeros (`0.00` of `0.001234`) are no significant digits.
    let zeros = digits[..n].iter().take_while(|&&b| b == b'0').count();
    let digits: &[u8] = if zeros == n {
        point = 1;
        b"0"
    } else {
        point -= zeros as i64;
        &digits[zeros..n]
    };
    // A tie: `v` is an odd multiple of 2^q, q < 0, with exactly one digit
    // more after the point than the digits written. Rare; `{}` decides it.
    let bits = v.to_bits();
    let (raw_exp, raw_mantissa) = ((bits >> 52) & 0x7ff, bits & ((1u64 << 52) - 1));
    let (m, e2) = if raw_exp == 0 {
        (raw_mantissa, -1074i64)
    } else {
        (raw_mantissa | 1u64 << 52, raw_exp as i64 - 1075)
    };
    if m != 0 {
        let q = e2 + i64::from(m.trailing_zeros());
        if q < 0 && q == point - digits.len() as i64 - 1 {
            out.extend_from_slice(csv_f64(v).as_bytes());
            return;
        }
    }
    if negative {
        out.push(b'-');
    }
    if point <= 0 {
        out.extend_from_slice(b"0.");
        out.resize(out.len() + (-point) as usize, b'0');
        out.extend_from_slice(digits);
    } else if point as usize >= digits.len() {
        out.extend_from_slice(digits);
        out.resize(out.len() + point as usize - digits.len(), b'0');
    } else {
        let (int, frac) = digits.split_at(point as usize);
        out.extend_from_slice(int);
        out.push(b'.');
        out.extend_from_slice(frac);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_values_keep_their_figures() {
        assert_eq!(fmt_sig(0.2, 4), "0.2000");
        assert_eq!(fmt_sig(0.26094, 4), "0.2609");
        assert_eq!(fmt_sig(912373.0, 5), "9.1237e5");
        assert_eq!(fmt_sig(5664700.0, 5), "5.6647e6");
        assert_eq!(fmt_sig(8228626.1208, 4), "8.229e6");
        assert_eq!(fmt_sig(12345.6, 3), "12300");
        assert_eq!(fmt_sig(99999.7, 3), "1.00e5", "rounding crosses 1e5");
        assert_eq!(
            fmt_sig(0.00099996, 3),
            "0.00100",
            "rounds up into the plain range"
        );
        assert_eq!(fmt_sig(0.0012345, 3), "0.00123");
        assert_eq!(fmt_sig(0.000999, 3), "9.99e-4");
        assert_eq!(fmt_sig(-1.623e-14, 4), "-1.623e-14");
        assert_eq!(fmt_sig(0.99996, 4), "1.000");
        assert_eq!(fmt_sig(360.0, 3), "360");
        assert_eq!(fmt_sig(0.0, 3), "0");
        assert_eq!(fmt_sig(-0.0, 3), "0");
        assert_eq!(fmt_sig(f64::NAN, 3), "NaN");
        assert_eq!(fmt_sig(f64::INFINITY, 3), "inf");
        assert_eq!(fmt_sig(f64::NEG_INFINITY, 3), "-inf");
        assert_eq!(fmt_sig(-2.5, 2), "-2.5");
        assert_eq!(fmt_sig(7.0, 0), "7", "zero figures means one");
    }

    #[test]
    fn trimmed_settings_drop_zeros_only() {
        assert_eq!(fmt_trim(0.2, 4), "0.2");
        assert_eq!(fmt_trim(360.0, 4), "360");
        assert_eq!(fmt_trim(1.5e6, 4), "1.5e6");
        assert_eq!(fmt_trim(0.123456, 4), "0.1235");
    }

    #[test]
    fn value_and_uncertainty_share_a_decimal_place() {
        assert_eq!(fmt_value_unc(0.26094, 0.004), "0.2609 ± 0.0040");
        assert_eq!(fmt_value_unc(12.34, 1.46), "12.3 ± 1.5");
        assert_eq!(fmt_value_unc(-12.34, 1.46), "-12.3 ± 1.5");
        assert_eq!(fmt_value_unc(1234.0, 56.0), "1234 ± 56");
        assert_eq!(fmt_value_unc(12345.0, 3000.0), "12300 ± 3000");
        // Uncertainty larger than the value: the value goes to its place.
        assert_eq!(fmt_value_unc(1.623e-14, 1.3), "0.0 ± 1.3");
        assert_eq!(fmt_value_unc(0.01, 25.0), "0 ± 25");
        // Zero value, negative uncertainty (taken by magnitude).
        assert_eq!(fmt_value_unc(0.0, 0.004), "0.0000 ± 0.0040");
        assert_eq!(fmt_value_unc(0.5, -0.25), "0.50 ± 0.25");
        // Outside the plain range: one shared exponent.
        assert_eq!(fmt_value_unc(8228626.12, 3000.0), "(8.2286 ± 0.0030)e6");
        assert_eq!(fmt_value_unc(2.0e-5, 3.0e-6), "(2.00 ± 0.30)e-5");
        assert_eq!(fmt_value_unc(-2.0e-5, 3.0e-6), "(-2.00 ± 0.30)e-5");
        // Rounding of the uncertainty to 2 figures moves its place.
        assert_eq!(fmt_value_unc(1.0, 0.0996), "1.00 ± 0.10");
        // Degenerate uncertainties and values.
        assert_eq!(fmt_value_unc(0.26094, 0.0), "0.2609 ± 0");
        assert_eq!(fmt_value_unc(0.26094, f64::NAN), "0.2609 ± NaN");
        assert_eq!(fmt_value_unc(0.26094, f64::INFINITY), "0.2609 ± inf");
        assert_eq!(fmt_value_unc(f64::NAN, 0.004), "NaN ± 0.0040");
        assert_eq!(fmt_value_unc(f64::NEG_INFINITY, 0.004), "-inf ± 0.0040");
    }

    #[test]
    fn estimates_say_when_they_mean_nothing() {
        assert_eq!(fmt_estimate(0.52, Some(0.13)), "0.52 ± 0.13");
        assert_eq!(
            fmt_estimate(1.623e-14, Some(1.3)),
            "not identified (0.0 ± 1.3)"
        );
        assert_eq!(
            fmt_estimate(0.1, Some(0.9)),
            "0.10 ± 0.90",
            "wide but within 10x"
        );
        assert_eq!(fmt_estimate(0.25, None), "0.2500 (±?)");
        assert_eq!(
            fmt_estimate(0.25, Some(f64::INFINITY)),
            "not identified (0.2500 ± inf)"
        );
    }

    #[test]
    fn units_and_csv_cells() {
        assert_eq!(with_unit("0.25", "1"), "0.25");
        assert_eq!(with_unit("0.25", ""), "0.25");
        assert_eq!(with_unit("0.25", "mN"), "0.25 mN");
        assert_eq!(csv_f64(1.11026), "1.11026");
        assert_eq!(csv_f64(1.2e-5), "0.000012");
        assert_eq!(csv_f64(2.0), "2");
        assert!(!csv_f64(1e-20).contains('e'));
    }

    /// `push_csv_f64` writes what `csv_f64` writes: at the edges of Ryū's
    /// layouts, at every binary exponent, and at random bit patterns.
    #[test]
    fn fast_csv_cells_are_the_display_text() {
        let same = |v: f64| {
            let mut out = Vec::new();
            push_csv_f64(&mut out, v);
            assert_eq!(String::from_utf8(out).unwrap(), csv_f64(v), "{v:e}");
        };
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            2.0,
            0.1,
            0.5,
            1.5,
            12.0,
            1e15,
            1e16,
            1e17,
            1.5e16,
            123e15,
            9007199254740993.0,
            1e-4,
            1e-5,
            1.234e-5,
            1e-7,
            5e-324,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1e300,
            1.7e-300,
            0.06661809541624704,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            same(v);
            same(-v);
        }
        for exp in 0..2047u64 {
            for mantissa in [0u64, 1, 0x8_0000_0000_0000, 0xf_ffff_ffff_ffff] {
                same(f64::from_bits(exp << 52 | mantissa));
            }
        }
        // A fixed xorshift sequence: the same bit patterns every run.
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            same(f64::from_bits(x));
            // Values of the magnitudes a sweep writes.
            same(f64::from_bits(x >> 12 | 0x3f00_0000_0000_0000));
        }
    }
}
