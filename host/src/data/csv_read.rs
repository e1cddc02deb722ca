//! A CSV dataset -> the raw tables of the TOML format, which the parser then
//! validates exactly as a TOML file (docs/data-format.md, "CSV datasets").
//!
//! The file is a `# key = value` header block (the `[setup]` defaults, plus
//! `name`, `source` and an optional `setup_file` = a TOML side file with a
//! `[setup]` table), a row of column names (the TOML keys, units in their
//! names) and one row per case or one row per trial: rows that share an
//! `id` are the trials of one case, their `u_mm_s` and `omega_body_hz`
//! become the raw trials that the parser turns into a mean and a Student-t
//! interval, and every other cell must agree between them.
//!
//! The `csv` crate reads the rows (quoting, line numbers); this module only
//! maps them to keys. Rows are numbered as a spreadsheet shows them: the
//! file's line numbers, from 1.

use super::csv_columns::{kind_of, Kind, CASE_ONLY_COLUMNS, TRIAL_COLUMNS, UNCERTAINTY_PREFIX};
use super::DataError;
use std::path::Path;

/// Where each case of a CSV dataset is written, for error messages.
pub struct Rows {
    file: String,
    cases: Vec<Vec<u64>>,
}

impl Rows {
    /// `FILE: row N` or `FILE: rows N, M, ...` of case `i`.
    pub fn describe(&self, i: usize) -> String {
        match self.cases.get(i).map(Vec::as_slice) {
            Some([one]) => format!("{}: row {one}", self.file),
            Some(rows) if !rows.is_empty() => {
                let list: Vec<String> = rows.iter().map(u64::to_string).collect();
                format!("{}: rows {}", self.file, list.join(", "))
            }
            _ => self.file.clone(),
        }
    }
}

/// An error at `at` (file and row), in a column if given.
fn fail(at: impl Into<String>, column: Option<&str>, message: impl Into<String>) -> DataError {
    let at = at.into();
    DataError {
        file: match column {
            Some(c) => format!("{at}: column `{c}`"),
            None => at,
        },
        case: None,
        field: None,
        message: message.into(),
    }
}

/// The raw tables of a CSV dataset and where each case is written. `dir`
/// is where a `setup_file` named in the header is looked for.
pub fn read(text: &str, file: &str, dir: &Path) -> Result<(toml::Table, Rows), DataError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let (mut top, skipped) = header(text, file, dir)?;
    // The rows start below the header block. No comment character is set
    // for them: an id may start with `#` (`#3`, the parser's name for an
    // unnamed case), and a spreadsheet does not quote it.
    let body: String = text.split_inclusive('\n').skip(skipped).collect();
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(body.as_bytes());
    let names: Vec<String> = reader
        .headers()
        .map_err(|e| csv_error(file, skipped, &e))?
        .iter()
        .map(str::to_string)
        .collect();
    let kinds = column_kinds(file, &names)?;
    let mut groups: Vec<Group> = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(file, skipped, &e))?;
        let line = record.position().map_or(0, |p| p.line()) + skipped as u64;
        let at = format!("{file}: row {line}");
        let mut row = toml::Table::new();
        for ((cell, name), kind) in record.iter().zip(&names).zip(&kinds) {
            if !cell.is_empty() {
                let value = kind.read(cell).map_err(|m| fail(&at, Some(name), m))?;
                insert(&mut row, name, value);
            }
        }
        // Spreadsheets leave rows of empty cells (`,,,`) at the end.
        if row.is_empty() {
            continue;
        }
        let id = row.get("id").and_then(|v| v.as_str()).map(str::to_string);
        match groups.iter_mut().find(|g| id.is_some() && g.id == id) {
            Some(g) => g.rows.push((line, row)),
            None => groups.push(Group {
                id,
                rows: vec![(line, row)],
            }),
        }
    }
    if groups.is_empty() {
        return Err(fail(
            file,
            None,
            "the CSV has no data rows under its header row",
        ));
    }
    let rows = Rows {
        file: file.to_string(),
        cases: groups
            .iter()
            .map(|g| g.rows.iter().map(|(l, _)| *l).collect())
            .collect(),
    };
    let cases = groups
        .into_iter()
        .map(|g| g.into_case(file))
        .collect::<Result<Vec<_>, _>>()?;
    top.insert(
        "case".into(),
        toml::Value::Array(cases.into_iter().map(toml::Value::Table).collect()),
    );
    Ok((top, rows))
}

/// The kind of every column; an unknown or repeated name is an error.
fn column_kinds(file: &str, names: &[String]) -> Result<Vec<Kind>, DataError> {
    let at = format!("{file}: header row");
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            if names[..i].contains(name) {
                return Err(fail(&at, Some(name), "the column is given twice"));
            }
            kind_of(name).ok_or_else(|| {
                let known: Vec<&str> = super::csv_columns::COLUMNS.iter().map(|c| c.0).collect();
                let why = if name.is_empty() {
                    "a column without a name".to_string()
                } else {
                    format!(
                        "`{name}` is not a dataset field; columns are {} and uncertainty.KEY (one row per trial replaces u_trials_mm_s and omega_body_trials_hz)",
                        known.join(", ")
                    )
                };
                fail(&at, Some(name), why)
            })
        })
        .collect()
}

/// `uncertainty.KEY` goes into the case's `uncertainty` table.
fn insert(row: &mut toml::Table, name: &str, value: toml::Value) {
    match name.strip_prefix(UNCERTAINTY_PREFIX) {
        Some(key) => {
            let table = row
                .entry("uncertainty")
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let toml::Value::Table(t) = table {
                t.insert(key.to_string(), value);
            }
        }
        None => {
            row.insert(name.to_string(), value);
        }
    }
}

/// The rows of one case: one, or one per trial.
struct Group {
    id: Option<String>,
    rows: Vec<(u64, toml::Table)>,
}

impl Group {
    fn into_case(self, file: &str) -> Result<toml::Table, DataError> {
        let n = self.rows.len();
        let mut rows = self.rows.into_iter();
        let (first_line, mut case) = rows.next().expect("a group has a row");
        if n == 1 {
            return Ok(case);
        }
        let id = self.id.unwrap_or_default();
        let mut trials: Vec<Vec<toml::Value>> = vec![Vec::new(); TRIAL_COLUMNS.len()];
        let mut take_trials = |line: u64, row: &mut toml::Table| -> Result<(), DataError> {
            for column in CASE_ONLY_COLUMNS {
                if row.contains_key(column) {
                    return Err(fail(
                        format!("{file}: row {line}"),
                        Some(column),
                        format!("case `{id}` is written as one row per trial ({n} rows), so it takes no `{column}`: the interval and the count follow from the trials"),
                    ));
                }
            }
            for (slot, (column, _)) in trials.iter_mut().zip(TRIAL_COLUMNS) {
                slot.extend(row.remove(column));
            }
            Ok(())
        };
        take_trials(first_line, &mut case)?;
        for (line, mut row) in rows {
            take_trials(line, &mut row)?;
            if let Some(column) = first_difference(&case, &row) {
                return Err(fail(
                    format!("{file}: row {line}"),
                    Some(&column),
                    format!("differs from row {first_line}, the first trial of case `{id}` (rows with one id are the trials of one case: only u_mm_s and omega_body_hz may differ)"),
                ));
            }
        }
        for (values, (_, key)) in trials.into_iter().zip(TRIAL_COLUMNS) {
            if !values.is_empty() {
                case.insert(key.to_string(), toml::Value::Array(values));
            }
        }
        Ok(case)
    }
}

/// The first column whose cell differs between two rows (absent included).
fn first_difference(a: &toml::Table, b: &toml::Table) -> Option<String> {
    a.keys()
        .chain(b.keys())
        .find(|k| a.get(*k) != b.get(*k))
        .map(|k| match (a.get(k), b.get(k)) {
            (Some(toml::Value::Table(x)), Some(toml::Value::Table(y))) => {
                let inner = x.keys().chain(y.keys()).find(|j| x.get(*j) != y.get(*j));
                format!("{k}.{}", inner.map_or("", |j| j.as_str()))
            }
            _ => k.clone(),
        })
}

fn csv_error(file: &str, skipped: usize, e: &csv::Error) -> DataError {
    let line = e.position().map(|p| p.line() + skipped as u64);
    let at = line.map_or(file.to_string(), |l| format!("{file}: row {l}"));
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} cells where the header row has {expected_len} columns"),
        _ => format!("not a readable CSV: {e}"),
    };
    fail(at, None, message)
}

/// The `# key = value` block above the header row, line numbers kept, as
/// the dataset's top-level table with its `setup`, and its number of lines.
fn header(text: &str, file: &str, dir: &Path) -> Result<(toml::Table, usize), DataError> {
    let mut block = String::new();
    let mut lines = 0;
    for line in text.lines() {
        let trimmed = line.trim();
        if !(trimmed.is_empty() || trimmed.starts_with('#')) {
            break;
        }
        lines += 1;
        let body = trimmed.trim_start_matches('#').trim();
        // Other `#` lines (notes, the provenance of a written file) are comments.
        if is_key_value(body) {
            block.push_str(body);
        }
        block.push('\n');
    }
    let mut setup: toml::Table = toml::from_str(&block).map_err(|e| {
        let why = e.message().trim_end().to_string();
        let at = e
            .span()
            .map(|s| block[..s.start].matches('\n').count() + 1)
            .map_or(file.to_string(), |l| format!("{file}: line {l}"));
        fail(
            at,
            None,
            format!("not a `# key = value` header line: {why}"),
        )
    })?;
    let mut top = toml::Table::new();
    for key in ["name", "source", "rig"] {
        if let Some(v) = setup.remove(key) {
            top.insert(key.into(), v);
        }
    }
    if let Some(side) = setup.remove("setup_file") {
        let Some(name) = side.as_str() else {
            return Err(fail(
                file,
                None,
                "header: `setup_file` must be a quoted file name",
            ));
        };
        top = side_file(&dir.join(name), top, &mut setup)?;
    }
    top.insert("setup".into(), toml::Value::Table(setup));
    Ok((top, lines))
}

/// A header line that sets a key: `key = ...`, `uncertainty.key = ...`.
fn is_key_value(line: &str) -> bool {
    let key_end = line
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.' || c == '-'))
        .unwrap_or(line.len());
    key_end > 0 && line[key_end..].trim_start().starts_with('=')
}

/// A TOML side file's `name`, `source` and `[setup]`, under the header's
/// own keys (which win).
fn side_file(
    path: &Path,
    mut top: toml::Table,
    setup: &mut toml::Table,
) -> Result<toml::Table, DataError> {
    let shown = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| fail(&shown, None, format!("cannot read the setup file: {e}")))?;
    crate::provenance::record_input(path, &bytes);
    let text = String::from_utf8_lossy(&bytes);
    let mut side: toml::Table = toml::from_str(&text).map_err(|e| {
        fail(
            &shown,
            None,
            format!("not a valid setup file: {}", e.to_string().trim_end()),
        )
    })?;
    if let Some(toml::Value::Table(s)) = side.remove("setup") {
        for (k, v) in s {
            setup.entry(k).or_insert(v);
        }
    }
    for key in ["name", "source"] {
        if let Some(v) = side.remove(key) {
            top.entry(key).or_insert(v);
        }
    }
    if let Some(key) = side.keys().next() {
        return Err(fail(
            &shown,
            None,
            format!("`{key}`: a setup file takes only name, source and a [setup] table (the cases are the CSV's rows)"),
        ));
    }
    Ok(top)
}
