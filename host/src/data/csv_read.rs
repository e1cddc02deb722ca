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
//! maps them to keys. A spreadsheet's export is read as it is: a UTF-8
//! BOM, CRLF line ends, `;` or tabs between cells and decimal commas
//! ([`super::csv_dialect`]). A column that is no dataset field is a
//! recorded variable if all its cells are numbers, a label if not
//! ([`super::recorded`]); the trial rows of a case carry the mean of a
//! recorded number. Rows are numbered as a spreadsheet shows them: the
//! file's line numbers, from 1.

use super::csv_columns::{Kind, CASE_ONLY_COLUMNS, TRIAL_COLUMNS, UNCERTAINTY_PREFIX};
use super::csv_dialect::{self, Dialect, ReadOptions};
use super::csv_header::{bare, classify, column_kinds, note, Column, LABELS, RECORDED};
use super::limits::{MAX_CASES, MAX_TRIALS};
use super::DataError;
use crate::provenance::Inputs;
use std::collections::HashMap;
use std::path::Path;

/// Where each case of a CSV dataset is written, for error messages.
pub struct Rows {
    file: String,
    cases: Vec<Vec<u64>>,
}

/// At most this many row ranges are listed for a case (`rows 3-9, 12`):
/// a case of 800 trial rows must not push its field and reason out of a
/// message.
const MAX_RANGES: usize = 4;

impl Rows {
    /// `FILE: row N` or `FILE: rows 3-9, 12` of case `i`.
    pub fn describe(&self, i: usize) -> String {
        match self.cases.get(i).map(Vec::as_slice) {
            Some([one]) => format!("{}: row {one}", self.file),
            Some(rows) if !rows.is_empty() => format!("{}: rows {}", self.file, ranges(rows)),
            _ => self.file.clone(),
        }
    }
}

/// `3-9, 12, 15-20`, cut after [`MAX_RANGES`] ranges with the count.
fn ranges(rows: &[u64]) -> String {
    let mut spans: Vec<(u64, u64)> = Vec::new();
    for &r in rows {
        match spans.last_mut() {
            Some((_, hi)) if *hi + 1 == r => *hi = r,
            _ => spans.push((r, r)),
        }
    }
    let shown: Vec<String> = spans
        .iter()
        .take(MAX_RANGES)
        .map(|&(lo, hi)| {
            if lo == hi {
                lo.to_string()
            } else {
                format!("{lo}-{hi}")
            }
        })
        .collect();
    let mut out = shown.join(", ");
    if spans.len() > MAX_RANGES {
        out.push_str(&format!(", ... ({} rows in all)", rows.len()));
    }
    out
}

/// An error at `at` (file and row), in a column if given.
fn fail(at: impl Into<String>, column: Option<&str>, message: impl Into<String>) -> DataError {
    let at = at.into();
    DataError {
        file: match column {
            Some(c) => format!("{at}: column `{}`", super::limits::echo(c)),
            None => at,
        },
        case: None,
        field: None,
        message: message.into(),
    }
}

/// A CSV dataset as the raw tables of the TOML format.
pub struct Read {
    pub table: toml::Table,
    pub rows: Rows,
    /// What was taken as what, when it was not the format's own
    /// (the dialect, recorded variables, labels): one line to show once.
    pub note: Option<String>,
}

/// The raw tables of a CSV dataset and where each case is written. `dir`
/// is where a `setup_file` named in the header is looked for; that file is
/// recorded in `inputs`.
pub fn read(
    text: &str,
    file: &str,
    dir: &Path,
    options: &ReadOptions,
    inputs: &Inputs,
) -> Result<Read, DataError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Classic Mac OS (and its Excel) ends each line with a lone CR: read
    // as LF, one line each, so rows are numbered as the file shows them.
    let lf;
    let text = if text.contains('\r') && !text.contains('\n') {
        lf = text.replace('\r', "\n");
        lf.as_str()
    } else {
        text
    };
    // Excel's `sep=;` first line names the separator; it is no header line.
    let declared = declared_separator(text.lines().next().unwrap_or(""));
    let skipped = text
        .lines()
        .enumerate()
        .take_while(|(i, l)| is_header_line(l) || (*i == 0 && declared.is_some()))
        .count();
    // The rows start below the header block. No comment character is set
    // for them: an id may start with `#` (`#3`, the parser's name for an
    // unnamed case), and a spreadsheet does not quote it.
    // A slice, not a copy: a file of a million rows is refused after its
    // first 10 001 cases, so the rest must not be touched.
    let body_start: usize = text.split_inclusive('\n').take(skipped).map(str::len).sum();
    let body = &text[body_start..];
    let separator =
        declared.unwrap_or_else(|| csv_dialect::separator(body.lines().next().unwrap_or("")));
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(separator)
        .trim(csv::Trim::All)
        .from_reader(body.as_bytes());
    let names: Vec<String> = reader
        .headers()
        .map_err(|e| csv_error(file, skipped, &e, separator))?
        .iter()
        .map(str::to_string)
        .collect();
    let mut columns = column_kinds(&names).map_err(|e| {
        fail(
            format!("{file}: header row"),
            e.column.as_deref(),
            e.message,
        )
    })?;
    let records = records(file, skipped, &mut reader, &names, separator)?;
    let numeric = |k: &Column| matches!(k, Column::Field(Kind::Number | Kind::Uncertainty));
    let known = cells(&records, &columns, numeric);
    let decimal = if known.is_empty() {
        // No number field in the rows: the recorded columns tell.
        let unknown = cells(&records, &columns, |k| *k == Column::Unknown);
        csv_dialect::decimal_comma(unknown.into_iter(), options)
    } else {
        csv_dialect::decimal_comma(known.into_iter(), options)
    };
    let dialect = Dialect {
        separator,
        decimal_comma: decimal.map_err(|m| fail(file, None, m.to_string()))?,
    };
    classify(&mut columns, &records, dialect.decimal_comma);
    unnamed_with_cells(file, &names, &columns, &records)?;
    let (mut top, _) = header(
        text,
        skipped,
        declared.is_some(),
        file,
        (dir, inputs),
        &dialect,
    )?;
    let mut groups: Vec<Group> = Vec::new();
    let mut by_id: HashMap<String, usize> = HashMap::new();
    for (line, record) in &records {
        let row = row_table(file, *line, record, &names, &columns, dialect.decimal_comma)?;
        // Spreadsheets leave rows of empty cells (`,,,`) at the end.
        if row.is_empty() {
            continue;
        }
        let id = row.get("id").and_then(|v| v.as_str()).map(str::to_string);
        match id.as_ref().and_then(|id| by_id.get(id)) {
            Some(&g) => groups[g].rows.push((*line, row)),
            None => {
                if let Some(id) = &id {
                    by_id.insert(id.clone(), groups.len());
                }
                groups.push(Group {
                    id,
                    rows: vec![(*line, row)],
                });
            }
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
    let note = note(file, &dialect, &names, &columns);
    Ok(Read {
        table: top,
        rows,
        note,
    })
}

/// The non-empty cells `(row, cell)` of the columns that `pick` takes.
fn cells<'a>(
    records: &'a [(u64, csv::StringRecord)],
    columns: &[Column],
    pick: impl Fn(&Column) -> bool,
) -> Vec<(u64, &'a str)> {
    records
        .iter()
        .flat_map(|(line, r)| {
            r.iter()
                .zip(columns)
                .filter(|(c, k)| !c.is_empty() && pick(k))
                .map(|(c, _)| (*line, c))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The separator a `sep=;` line declares (Excel writes and reads it).
fn declared_separator(line: &str) -> Option<u8> {
    let rest = line.trim_end_matches(['\r', '\n']);
    let rest = rest
        .strip_prefix("sep=")
        .or_else(|| rest.strip_prefix("SEP="))?;
    match rest.as_bytes() {
        [s @ (b',' | b';' | b'\t' | b'|')] => Some(*s),
        _ => None,
    }
}

/// A column without a name is a spreadsheet's padding (`;` at the end of
/// every row) while its cells are empty, and left out; one with cells
/// holds data nobody named.
fn unnamed_with_cells(
    file: &str,
    names: &[String],
    columns: &[Column],
    records: &[(u64, csv::StringRecord)],
) -> Result<(), DataError> {
    for (i, (name, column)) in names.iter().zip(columns).enumerate() {
        if !name.is_empty() || *column == Column::Unknown {
            continue;
        }
        let (row, cell) = records
            .iter()
            .find_map(|(l, r)| r.get(i).filter(|c| !c.is_empty()).map(|c| (*l, c)))
            .unwrap_or((0, ""));
        return Err(fail(
            format!("{file}: row {row}"),
            None,
            format!(
                "column {} has no name in the header row but holds `{}`; name it there (any name that is no dataset field is kept as a recorded variable)",
                i + 1,
                super::limits::echo(cell)
            ),
        ));
    }
    Ok(())
}

/// A line of the `# key = value` block (a spreadsheet may quote it).
fn is_header_line(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#') || t.starts_with("\"#")
}

/// The data rows with their line numbers, refused as soon as they hold
/// more cases than a dataset may have: a file of a million rows is
/// refused in milliseconds, not after reading it all.
fn records(
    file: &str,
    skipped: usize,
    reader: &mut csv::Reader<&[u8]>,
    names: &[String],
    separator: u8,
) -> Result<Vec<(u64, csv::StringRecord)>, DataError> {
    let id_column = names.iter().position(|n| n == "id");
    let mut ids: HashMap<String, u32> = HashMap::new();
    let mut cases = 0usize;
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(file, skipped, &e, separator))?;
        let line = record.position().map_or(0, |p| p.line()) + skipped as u64;
        if record.iter().all(str::is_empty) {
            continue;
        }
        let id = id_column
            .and_then(|i| record.get(i))
            .filter(|s| !s.is_empty());
        let trials = match id {
            Some(id) => {
                let n = ids.entry(id.to_string()).or_insert(0);
                *n += 1;
                *n
            }
            None => 1,
        };
        if trials == 1 {
            cases += 1;
        }
        if cases > MAX_CASES {
            return Err(fail(
                format!("{file}: row {line}"),
                None,
                format!("more than {MAX_CASES} cases (this row starts case {cases}); at most {MAX_CASES} are allowed: split the file"),
            ));
        }
        if trials > MAX_TRIALS {
            return Err(fail(
                format!("{file}: row {line}"),
                Some("id"),
                format!("more than {MAX_TRIALS} trial rows of case `{}`; at most {MAX_TRIALS} are allowed", super::limits::echo(id.unwrap_or_default())),
            ));
        }
        out.push((line, record));
    }
    Ok(out)
}

/// One row's cells as raw TOML values (empty cells left out).
fn row_table(
    file: &str,
    line: u64,
    record: &csv::StringRecord,
    names: &[String],
    columns: &[Column],
    decimal_comma: bool,
) -> Result<toml::Table, DataError> {
    let at = format!("{file}: row {line}");
    let id = names
        .iter()
        .position(|n| n == "id")
        .and_then(|i| record.get(i))
        .filter(|s| !s.is_empty());
    let mut row = toml::Table::new();
    for ((cell, name), column) in record.iter().zip(names).zip(columns) {
        if cell.is_empty() {
            continue;
        }
        let (kind, name) = match column {
            Column::Field(kind) => (*kind, name.as_str()),
            Column::Recorded => (Kind::Number, name.as_str()),
            Column::Label => (Kind::Text, name.as_str()),
            Column::Unknown => continue,
        };
        let value = kind.read(cell, decimal_comma).map_err(|m| DataError {
            case: id.map(super::limits::echo),
            ..fail(&at, Some(name), m.to_string())
        })?;
        match column {
            Column::Recorded => insert_in(&mut row, RECORDED, bare(name, RECORDED), value),
            Column::Label => insert_in(&mut row, LABELS, bare(name, LABELS), value),
            _ => insert(&mut row, name, value),
        }
    }
    Ok(row)
}

/// `uncertainty.KEY` goes into the case's `uncertainty` table.
fn insert(row: &mut toml::Table, name: &str, value: toml::Value) {
    match name.strip_prefix(UNCERTAINTY_PREFIX) {
        Some(key) => insert_in(row, "uncertainty", key, value),
        None => {
            row.insert(name.to_string(), value);
        }
    }
}

/// `value` as `key` of the row's sub-table `table`.
fn insert_in(row: &mut toml::Table, table: &str, key: &str, value: toml::Value) {
    let t = row
        .entry(table)
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if let toml::Value::Table(t) = t {
        t.insert(key.to_string(), value);
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
        // A recorded number may change from trial to trial (the oil warms
        // up): the case carries its mean.
        let mut recorded: Vec<(String, f64, u32)> = Vec::new();
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
            if let Some(toml::Value::Table(t)) = row.remove(RECORDED) {
                for (k, v) in t {
                    let x = v.as_float().unwrap_or(f64::NAN);
                    match recorded.iter_mut().find(|(n, _, _)| *n == k) {
                        Some((_, sum, count)) => (*sum, *count) = (*sum + x, *count + 1),
                        None => recorded.push((k, x, 1)),
                    }
                }
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
        for (k, sum, count) in recorded {
            insert_in(
                &mut case,
                RECORDED,
                &k,
                toml::Value::Float(sum / f64::from(count)),
            );
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

fn csv_error(file: &str, skipped: usize, e: &csv::Error, separator: u8) -> DataError {
    let line = e.position().map(|p| p.line() + skipped as u64);
    let at = line.map_or(file.to_string(), |l| format!("{file}: row {l}"));
    // A decimal comma in an unquoted cell splits it in two under `,`.
    let hint = if separator == b',' {
        " (a decimal comma in a cell that is not in quotes splits it in two: quote it, \"0,586\", or write the file with `;` between cells)"
    } else {
        ""
    };
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} cells where the header row has {expected_len} columns{hint}"),
        _ => format!("not a readable CSV: {e}"),
    };
    fail(at, None, message)
}

/// The `# key = value` block above the header row, line numbers kept, as
/// the dataset's top-level table with its `setup`, and its number of lines.
fn header(
    text: &str,
    skipped: usize,
    sep_line: bool,
    file: &str,
    (dir, inputs): (&Path, &Inputs),
    dialect: &Dialect,
) -> Result<(toml::Table, usize), DataError> {
    let mut block = String::new();
    let mut lines = 0;
    for (i, line) in text.lines().take(skipped).enumerate() {
        lines += 1;
        if i == 0 && sep_line {
            block.push('\n');
            continue;
        }
        let line = csv_dialect::header_line(line, dialect);
        let body = line.trim_start_matches('#').trim();
        // Other `#` lines (notes, the provenance of a written file) are comments.
        if is_key_value(body) {
            block.push_str(body);
        }
        block.push('\n');
    }
    let mut setup: toml::Table = toml::from_str(&block).map_err(|e| {
        let why = e.message().trim_end().to_string();
        let line = e
            .span()
            .map(|s| block[..s.start].matches('\n').count() + 1);
        let at = line.map_or(file.to_string(), |l| format!("{file}: line {l}"));
        // The line is a `key = value` (only those reach the block): what
        // is wrong is its value, so the key is named.
        let key = line
            .and_then(|l| block.lines().nth(l - 1))
            .and_then(|l| l.split_once('='))
            .map(|(k, _)| k.trim());
        match key {
            Some(k) => fail(
                at,
                None,
                format!(
                    "`# {} = ...`: the value of `{}` is not a TOML value (a number, a quoted text, true/false or a list): {why}",
                    super::limits::echo(k),
                    super::limits::echo(k)
                ),
            ),
            None => fail(
                at,
                None,
                format!("not a `# key = value` header line: {why}"),
            ),
        }
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
        top = side_file(&dir.join(name), top, &mut setup, inputs)?;
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
    inputs: &Inputs,
) -> Result<toml::Table, DataError> {
    let shown = path.display().to_string();
    let bytes = crate::input_file::read(path, crate::input_file::cap::SETUP_FILE, "a setup file")
        .map_err(|e| fail(&shown, None, format!("the setup file: {e}")))?;
    inputs.record(path, &bytes);
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
