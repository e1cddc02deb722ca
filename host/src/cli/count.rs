//! The value of a count flag (`--runs`, `--mc-draws`, `--trials`, a seed):
//! a whole number, said why not when it is none. Flags using it also take
//! values that start with `-` (`allow_negative_numbers`), so that `--runs
//! -1` reaches this check and is refused by name instead of reading as an
//! unknown flag `-1` (clap's own message then names no flag).

/// `text` as a whole number of type `T`: a negative number, a fraction,
/// an exponent or a number too large for `T` each get their own reason
/// (clap prefixes the flag and the value).
pub fn whole<T: TryFrom<u128>>(text: &str) -> Result<T, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("empty; give a whole number".into());
    }
    if t.bytes().all(|b| b.is_ascii_digit()) {
        return t
            .parse::<u128>()
            .ok()
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| "too large".into());
    }
    if t.starts_with('-') && t[1..].parse::<f64>().is_ok() {
        return Err("cannot be negative; give a whole number, 0 or more".into());
    }
    if t.parse::<f64>().is_ok() {
        return Err(
            "not a whole number; give one without a fraction or an exponent, e.g. 6".into(),
        );
    }
    Err("not a number; give a whole number, e.g. 6".into())
}

#[cfg(test)]
mod tests {
    use super::whole;

    #[test]
    fn whole_numbers_pass_and_each_other_value_gets_its_reason() {
        assert_eq!(whole::<usize>("6"), Ok(6));
        assert_eq!(whole::<u64>(" 12 "), Ok(12));
        assert!(whole::<usize>("-1").unwrap_err().contains("negative"));
        assert!(whole::<usize>("-0.5").unwrap_err().contains("negative"));
        assert!(whole::<usize>("2.5").unwrap_err().contains("whole"));
        assert!(whole::<usize>("1e3").unwrap_err().contains("exponent"));
        assert!(whole::<u32>("99999999999")
            .unwrap_err()
            .contains("too large"));
        let huge = "9".repeat(60);
        assert!(whole::<u64>(&huge).unwrap_err().contains("too large"));
        assert!(whole::<usize>("x").unwrap_err().contains("not a number"));
        assert!(whole::<usize>("").unwrap_err().contains("empty"));
    }
}
