//! Recorded variables: what a lab wrote down beside each case that the
//! model does not read (the oil's temperature, a date, the robot's id).
//!
//! A lab records such things because they matter: a temperature drift of
//! the oil's viscosity is exactly the kind of effect a model misses. So
//! they are carried through (`convert`, `compare`'s per-case output) and
//! the numeric ones are offered to `diagnose` as features beside the
//! quantity library ([`super::quantities`]). In TOML a case gives them as
//! `recorded = { temperature_c = 21.4 }` (numbers) and
//! `labels = { date = "2024-05-02" }` (text); in a CSV they are columns
//! whose names are not dataset fields (docs/data-format.md).

use serde::ser::{Serialize, SerializeMap, Serializer};

/// A case's recorded variables, each kind sorted by name (as TOML tables
/// keep their keys).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Recorded {
    /// Numeric variables (`temperature_c = 21.4`).
    pub values: Vec<(String, f64)>,
    /// Text variables (`date = "2024-05-02"`).
    pub labels: Vec<(String, String)>,
}

impl Recorded {
    pub fn is_empty(&self) -> bool {
        self.values.is_empty() && self.labels.is_empty()
    }

    /// The numeric variable `name`, if the case recorded it.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.values.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// The text variable `name`, if the case recorded it.
    pub fn label(&self, name: &str) -> Option<&str> {
        self.labels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The case's `recorded` and `labels` tables over the setup's
    /// (the case's own entries win); `Err((field, message))` for a value
    /// of the wrong type or a name that is a dataset field.
    pub fn from_tables(
        setup: (Option<&toml::Table>, Option<&toml::Table>),
        case: (Option<&toml::Table>, Option<&toml::Table>),
    ) -> Result<Recorded, (String, String)> {
        let mut out = Recorded::default();
        for table in [setup.0, case.0].into_iter().flatten() {
            for (name, v) in table {
                check_name("recorded", name)?;
                let x = match v {
                    toml::Value::Float(x) => *x,
                    toml::Value::Integer(i) => *i as f64,
                    _ => {
                        return Err((
                            format!("recorded.{name}"),
                            "must be a number (text goes in `labels`)".into(),
                        ))
                    }
                };
                if !x.is_finite() {
                    return Err((
                        format!("recorded.{name}"),
                        format!("must be a finite number, got {x}"),
                    ));
                }
                set(&mut out.values, name, x);
            }
        }
        for table in [setup.1, case.1].into_iter().flatten() {
            for (name, v) in table {
                check_name("labels", name)?;
                let toml::Value::String(s) = v else {
                    return Err((format!("labels.{name}"), "must be text in quotes".into()));
                };
                set(&mut out.labels, name, s.clone());
            }
        }
        Ok(out)
    }
}

/// The recorded numbers that every case of `data` gives, each with its
/// value per case, in the order of the first case; a variable missing from
/// a case cannot be a feature (no value to correlate) and is left out.
pub fn features(data: &super::Dataset) -> Vec<(String, Vec<f64>)> {
    let Some(first) = data.cases.first() else {
        return Vec::new();
    };
    first
        .recorded
        .values
        .iter()
        .filter_map(|(name, _)| {
            let xs: Option<Vec<f64>> = data.cases.iter().map(|c| c.recorded.value(name)).collect();
            xs.map(|xs| (name.clone(), xs))
        })
        .collect()
}

fn set<T>(list: &mut Vec<(String, T)>, name: &str, value: T) {
    match list.iter_mut().find(|(n, _)| n == name) {
        Some(slot) => slot.1 = value,
        None => list.push((name.to_string(), value)),
    }
}

/// A recorded variable may not shadow a dataset field: the model would
/// silently not read it.
fn check_name(table: &str, name: &str) -> Result<(), (String, String)> {
    if super::csv_columns::kind_of(name).is_some() {
        return Err((
            format!("{table}.{name}"),
            format!("`{name}` is a dataset field: give it as a field, not a recorded variable"),
        ));
    }
    if name.trim().is_empty() {
        return Err((table.to_string(), "a recorded variable needs a name".into()));
    }
    Ok(())
}

/// One JSON object, the numbers then the text:
/// `{"temperature_c": 21.4, "date": "2024-05-02"}`.
impl Serialize for Recorded {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.values.len() + self.labels.len()))?;
        for (k, v) in &self.values {
            map.serialize_entry(k, v)?;
        }
        for (k, v) in &self.labels {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn the_case_overrides_the_setup_and_types_are_checked() {
        let s = table("temperature_c = 20\nrig = 1.5");
        let c = table("temperature_c = 21.5");
        let l = table("date = \"2024-05-02\"");
        let r = Recorded::from_tables((Some(&s), None), (Some(&c), Some(&l))).unwrap();
        assert_eq!(r.value("temperature_c"), Some(21.5));
        assert_eq!(r.value("rig"), Some(1.5));
        assert_eq!(r.label("date"), Some("2024-05-02"));
        let json = serde_json::to_string(&r).unwrap();
        assert_eq!(
            json,
            r#"{"rig":1.5,"temperature_c":21.5,"date":"2024-05-02"}"#
        );

        let text = table("t = \"warm\"");
        let e = Recorded::from_tables((None, None), (Some(&text), None)).unwrap_err();
        assert_eq!(e.0, "recorded.t");
        let field = table("viscosity_pa_s = 3.0");
        let e = Recorded::from_tables((None, None), (Some(&field), None)).unwrap_err();
        assert!(e.1.contains("dataset field"), "{e:?}");
        let number = table("date = 3");
        assert!(Recorded::from_tables((None, None), (None, Some(&number))).is_err());
    }
}
