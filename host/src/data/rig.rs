//! What the rig can run: the feasible range of the fields a new experiment
//! may change (rates the firmware holds, tails the lab can bend, the tubes
//! it has), read from a dataset's optional `[rig]` block (TOML) or its
//! `# rig.key = ...` header lines (CSV).
//!
//! A field the block leaves out is not limited here: the workbench falls
//! back to the dataset's own range of it (`workbench::experiments::rig`),
//! the only range a lab has shown it can run.

use super::parse::err;
use super::DataError;

/// The stated limits; every one optional.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigLimits {
    /// Motor rates the firmware holds, `[min, max]` (Hz).
    pub frequency_hz: Option<(f64, f64)>,
    /// Helix amplitudes the lab can bend, `[min, max]` (mm).
    pub amplitude_mm: Option<(f64, f64)>,
    /// Helix wavelengths the lab can bend, `[min, max]` (mm).
    pub wavelength_mm: Option<(f64, f64)>,
    /// Tail lengths the lab can make, `[min, max]` (mm).
    pub tail_length_mm: Option<(f64, f64)>,
    /// Inner diameters of the tubes the lab has (mm).
    pub channel_diameter_mm: Option<Vec<f64>>,
}

/// The keys of a `[rig]` block, for its error message.
pub const RIG_KEYS: [&str; 5] = [
    "frequency_hz",
    "amplitude_mm",
    "wavelength_mm",
    "tail_length_mm",
    "channel_diameter_mm",
];

/// Read a `[rig]` table; `file` names it in error messages.
pub fn parse(table: Option<toml::Table>, file: &str) -> Result<RigLimits, DataError> {
    let Some(table) = table else {
        return Ok(RigLimits::default());
    };
    let mut rig = RigLimits::default();
    for (key, value) in table {
        let field = format!("rig.{key}");
        let fail = |m: String| err(file, None, Some(&field), m);
        let numbers = numbers(&value).map_err(|e| fail(e.to_string()))?;
        match key.as_str() {
            "channel_diameter_mm" => {
                if numbers.is_empty() {
                    return Err(fail(
                        "lists no tube: give at least one inner diameter".into(),
                    ));
                }
                rig.channel_diameter_mm = Some(numbers);
            }
            "frequency_hz" | "amplitude_mm" | "wavelength_mm" | "tail_length_mm" => {
                let range = match numbers[..] {
                    [lo, hi] if lo <= hi => (lo, hi),
                    [lo, hi] => {
                        return Err(fail(format!(
                            "[{lo}, {hi}]: the minimum exceeds the maximum"
                        )))
                    }
                    _ => return Err(fail("must be `[min, max]`, two numbers".into())),
                };
                match key.as_str() {
                    "frequency_hz" => rig.frequency_hz = Some(range),
                    "amplitude_mm" => rig.amplitude_mm = Some(range),
                    "wavelength_mm" => rig.wavelength_mm = Some(range),
                    _ => rig.tail_length_mm = Some(range),
                }
            }
            _ => {
                return Err(fail(format!(
                    "unknown rig key; the rig block takes {}",
                    RIG_KEYS.join(", ")
                )))
            }
        }
    }
    Ok(rig)
}

/// A `[rig]` value that is no list of positive numbers: the value as
/// written (or the number) as data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RigValueError {
    #[error("{0} is not a list of numbers")]
    NotAList(String),
    #[error("{0} is not a number")]
    NotANumber(String),
    #[error("{0} must be positive and finite")]
    NotPositive(f64),
}

/// An array of positive finite numbers (integers accepted).
fn numbers(value: &toml::Value) -> Result<Vec<f64>, RigValueError> {
    let Some(items) = value.as_array() else {
        return Err(RigValueError::NotAList(value.to_string()));
    };
    items
        .iter()
        .map(|v| {
            let x = v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .ok_or_else(|| RigValueError::NotANumber(v.to_string()))?;
            if x.is_finite() && x > 0.0 {
                Ok(x)
            } else {
                Err(RigValueError::NotPositive(x))
            }
        })
        .collect()
}

/// The block as TOML, for a written dataset (empty when nothing is stated).
pub fn to_toml(rig: &RigLimits) -> String {
    let mut out = String::new();
    let pair = |k: &str, r: Option<(f64, f64)>| r.map(|(a, b)| format!("{k} = [{a:?}, {b:?}]\n"));
    for line in [
        pair("frequency_hz", rig.frequency_hz),
        pair("amplitude_mm", rig.amplitude_mm),
        pair("wavelength_mm", rig.wavelength_mm),
        pair("tail_length_mm", rig.tail_length_mm),
        rig.channel_diameter_mm.as_ref().map(|d| {
            let v: Vec<String> = d.iter().map(|x| format!("{x:?}")).collect();
            format!("channel_diameter_mm = [{}]\n", v.join(", "))
        }),
    ]
    .into_iter()
    .flatten()
    {
        out.push_str(&line);
    }
    if out.is_empty() {
        out
    } else {
        format!("\n[rig]\n{out}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Option<toml::Table> {
        Some(toml::from_str(text).unwrap())
    }

    #[test]
    fn a_block_is_read_and_written_back() {
        let rig = parse(
            table("frequency_hz = [0.5, 2]\nchannel_diameter_mm = [28.0, 34.0]"),
            "f.toml",
        )
        .unwrap();
        assert_eq!(rig.frequency_hz, Some((0.5, 2.0)));
        assert_eq!(rig.channel_diameter_mm, Some(vec![28.0, 34.0]));
        let again: toml::Table = toml::from_str(&to_toml(&rig)).unwrap();
        let back = parse(again["rig"].as_table().cloned(), "f.toml").unwrap();
        assert_eq!(back, rig);
        assert_eq!(to_toml(&RigLimits::default()), "");
    }

    #[test]
    fn bad_blocks_name_the_field() {
        for (text, says) in [
            ("frequency_hz = [2.0, 0.5]", "exceeds"),
            ("frequency_hz = [1.0]", "two numbers"),
            ("amplitude_mm = [-1.0, 2.0]", "positive"),
            ("channel_diameter_mm = []", "no tube"),
            ("tubes = [1.0]", "unknown rig key"),
            ("wavelength_mm = 3.0", "not a list"),
        ] {
            let e = parse(table(text), "f.toml").unwrap_err().to_string();
            assert!(e.contains("rig.") && e.contains(says), "{text}: {e}");
        }
    }
}
