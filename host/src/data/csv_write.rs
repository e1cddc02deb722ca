//! The raw tables of a dataset -> CSV or TOML text (`swimbot convert`).
//!
//! Both directions work on the raw tables, before `[setup]` is merged, so
//! that a converted file keeps its setup block, its raw trials and its
//! relative uncertainties as written; numbers are written in Rust's
//! shortest round-trip form, so they read back bit for bit. A case that
//! gives raw trials for one quantity and a mean with its interval for the
//! other has no CSV form (a row is a case or a trial, not both) and is an
//! error rather than a silent change.

use super::csv_columns::{order_of, CASE_ONLY_COLUMNS, TRIAL_COLUMNS, UNCERTAINTY_PREFIX};
use std::fmt::Write;

/// A raw dataset (validated) as CSV: a `# key = value` header block for
/// `name`, `source` and `[setup]`, then one row per case or per trial.
pub fn to_csv(raw: &toml::Table) -> Result<String, CsvFormError> {
    let mut out = String::new();
    for (key, value) in top_and_setup(raw) {
        let _ = writeln!(out, "# {key} = {}", inline(&value));
    }
    let rows = raw
        .get("case")
        .and_then(toml::Value::as_array)
        .into_iter()
        .flatten()
        .enumerate()
        .map(|(i, c)| case_rows(i, c.as_table().unwrap_or(&toml::Table::new())))
        .collect::<Result<Vec<_>, _>>()?
        .concat();
    let mut columns: Vec<String> = Vec::new();
    for row in &rows {
        for k in row.keys() {
            if !columns.contains(k) {
                columns.push(k.clone());
            }
        }
    }
    columns.sort_by_key(|c| order_of(c));
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = |e: csv::Error| CsvFormError::Write(e.to_string());
    w.write_record(&columns).map_err(fail)?;
    for row in &rows {
        w.write_record(
            columns
                .iter()
                .map(|c| row.get(c).map(cell).unwrap_or_default()),
        )
        .map_err(fail)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| CsvFormError::Write(e.to_string()))?;
    out.push_str(&String::from_utf8_lossy(&bytes));
    Ok(out)
}

/// A dataset that has no CSV form, or a CSV that could not be written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CsvFormError {
    /// Case `case` gives raw trials and `key` (a mean or a case-only
    /// column): a CSV row is a case or a trial, not both.
    #[error(
        "case `{case}`: raw trials and `{key}` in one case have no CSV form (a CSV row is either a case or a trial); keep this dataset in TOML, or give both quantities the same way"
    )]
    TrialsBesideCaseValue { case: String, key: &'static str },
    /// The csv crate's writer failed (its message).
    #[error("writing CSV: {0}")]
    Write(String),
}

/// A raw dataset (validated) as TOML: `name`, `source`, `[setup]`, then a
/// `[[case]]` per case, keys in the documented order.
pub fn to_toml(raw: &toml::Table) -> String {
    let mut out = String::new();
    for key in ["name", "source"] {
        if let Some(v) = raw.get(key) {
            let _ = writeln!(out, "{key} = {}", inline(v));
        }
    }
    if let Some(toml::Value::Table(setup)) = raw.get("setup") {
        if !setup.is_empty() {
            let _ = writeln!(out, "\n[setup]");
            write_keys(&mut out, setup);
        }
    }
    for case in raw
        .get("case")
        .and_then(toml::Value::as_array)
        .into_iter()
        .flatten()
    {
        let _ = writeln!(out, "\n[[case]]");
        if let Some(t) = case.as_table() {
            write_keys(&mut out, t);
        }
    }
    if let Some(toml::Value::Table(rig)) = raw.get("rig") {
        let _ = writeln!(out, "\n[rig]");
        write_keys(&mut out, rig);
    }
    out
}

fn write_keys(out: &mut String, table: &toml::Table) {
    let mut keys: Vec<&String> = table.keys().collect();
    keys.sort_by_key(|k| order_of(k));
    for k in keys {
        let _ = writeln!(out, "{} = {}", key(k), inline(&table[k]));
    }
}

/// `name`, `source`, then the setup's keys (an uncertainty table as dotted
/// keys, `uncertainty.amplitude_mm`), in the documented order.
fn top_and_setup(raw: &toml::Table) -> Vec<(String, toml::Value)> {
    let mut out: Vec<(String, toml::Value)> = ["name", "source"]
        .iter()
        .filter_map(|k| raw.get(*k).map(|v| (k.to_string(), v.clone())))
        .collect();
    if let Some(toml::Value::Table(setup)) = raw.get("setup") {
        // The setup's recorded variables stay tables (`# recorded = { .. }`):
        // a header line is a key of the setup, not a column.
        let (tables, rest): (toml::Table, toml::Table) = setup
            .clone()
            .into_iter()
            .partition(|(k, _)| k == "recorded" || k == "labels");
        let mut keys: Vec<(String, toml::Value)> =
            flatten(&rest).into_iter().chain(tables).collect();
        keys.sort_by_key(|(k, _)| order_of(k));
        out.extend(keys);
    }
    // What the rig can run, as `rig.KEY` header lines.
    if let Some(toml::Value::Table(rig)) = raw.get("rig") {
        out.extend(rig.iter().map(|(k, v)| (format!("rig.{k}"), v.clone())));
    }
    out
}

/// A case's keys with its uncertainty table spread over `uncertainty.KEY`.
fn flatten(case: &toml::Table) -> toml::Table {
    let mut flat = toml::Table::new();
    for (k, v) in case {
        match v {
            toml::Value::Table(t) if k == "uncertainty" => {
                for (u, x) in t {
                    flat.insert(format!("{UNCERTAINTY_PREFIX}{u}"), x.clone());
                }
            }
            toml::Value::Table(t) if k == "recorded" => {
                for (u, x) in t {
                    flat.insert(u.clone(), x.clone());
                }
            }
            // A label that reads as a number (a robot `7`) keeps its
            // prefix, which makes the reader take it as text again.
            toml::Value::Table(t) if k == "labels" => {
                for (u, x) in t {
                    let numeric = x.as_str().is_some_and(|s| s.trim().parse::<f64>().is_ok());
                    let name = if numeric {
                        format!("labels.{u}")
                    } else {
                        u.clone()
                    };
                    flat.insert(name, x.clone());
                }
            }
            _ => {
                flat.insert(k.clone(), v.clone());
            }
        }
    }
    flat
}

/// One row for a case with means, one per trial for a case with raw
/// trials (then it needs an id to tie its rows together: `#n`, the name
/// the parser would give it).
fn case_rows(index: usize, case: &toml::Table) -> Result<Vec<toml::Table>, CsvFormError> {
    let mut flat = flatten(case);
    let trials: Vec<Vec<toml::Value>> = TRIAL_COLUMNS
        .iter()
        .map(|(_, key)| match flat.remove(*key) {
            Some(toml::Value::Array(values)) => values,
            _ => Vec::new(),
        })
        .collect();
    let n = trials.iter().map(Vec::len).max().unwrap_or(0);
    if n == 0 {
        return Ok(vec![flat]);
    }
    let id = flat
        .entry("id")
        .or_insert_with(|| toml::Value::String(format!("#{}", index + 1)))
        .as_str()
        .unwrap_or_default()
        .to_string();
    let mixed = TRIAL_COLUMNS
        .iter()
        .map(|(mean, _)| *mean)
        .chain(CASE_ONLY_COLUMNS)
        .find(|k| flat.contains_key(*k));
    if let Some(k) = mixed {
        return Err(CsvFormError::TrialsBesideCaseValue { case: id, key: k });
    }
    Ok((0..n)
        .map(|i| {
            let mut row = flat.clone();
            for (values, (mean, _)) in trials.iter().zip(TRIAL_COLUMNS) {
                if let Some(v) = values.get(i) {
                    row.insert(mean.to_string(), v.clone());
                }
            }
            row
        })
        .collect())
}

/// A value as a spreadsheet cell: strings bare, numbers plain decimals.
fn cell(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Float(x) => crate::format::csv_f64(*x),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        other => inline(other),
    }
}

/// A key as TOML reads it back: bare when TOML allows (`A-Za-z0-9_-`),
/// else quoted with escapes: a CSV column `room temp (C)` or `Opérateur`
/// written bare does not parse, and `temp.c` reads back as a table `temp`.
fn key(k: &str) -> String {
    let bare = !k.is_empty()
        && k.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
    if bare {
        k.to_string()
    } else {
        toml::Value::String(k.to_string()).to_string()
    }
}

/// A value as TOML on one line (tables inline).
fn inline(v: &toml::Value) -> String {
    match v {
        toml::Value::Table(t) => {
            let mut keys: Vec<&String> = t.keys().collect();
            keys.sort_by_key(|k| order_of(k));
            let kv: Vec<String> = keys
                .iter()
                .map(|k| format!("{} = {}", key(k), inline(&t[*k])))
                .collect();
            format!("{{ {} }}", kv.join(", "))
        }
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(inline).collect();
            format!("[{}]", items.join(", "))
        }
        toml::Value::Float(x) => float(*x),
        other => other.to_string(),
    }
}

/// A TOML float in the shortest form that reads back exactly (`{:?}`
/// keeps the `.0` TOML needs; `nan` and `inf` are TOML's spellings).
fn float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:?}")
    }
}
