//! Reading a dataset file: CSV or TOML by its extension, the file recorded
//! in the caller's inputs ([`crate::provenance::Inputs`]), and the conversion
//! between the two formats (`swimbot convert`).

use super::csv_dialect::ReadOptions;
use super::parse::{err, parse_str, parse_table, Written, CSV_MISSING};
use super::{csv_read, csv_write, DataError, Dataset};
use crate::provenance::Inputs;
use std::path::Path;

/// A dataset as read, with what the reader took as what when it was not
/// the format's own (a spreadsheet's dialect, recorded variables): one
/// line for the user to see once.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub dataset: Dataset,
    pub note: Option<String>,
}

/// Read and validate a dataset file: CSV (`.csv`, docs/data-format.md)
/// or TOML (any other name). What it reads is recorded nowhere: a caller
/// whose output carries its provenance reads with [`read_file`] or
/// [`load_recorded`].
pub fn load_file(path: &Path) -> Result<Dataset, DataError> {
    load_recorded(path, &Inputs::new())
}

/// [`load_file`], the file's path and SHA-256 recorded in `inputs`
/// ([`crate::provenance`]), with a CSV's setup file.
pub fn load_recorded(path: &Path, inputs: &Inputs) -> Result<Dataset, DataError> {
    read_file(path, &ReadOptions::default(), inputs).map(|l| l.dataset)
}

/// [`load_file`] with what the caller knows of a CSV's dialect, and the
/// note on what was taken as what.
pub fn read_file(path: &Path, options: &ReadOptions, inputs: &Inputs) -> Result<Loaded, DataError> {
    let file = path.display().to_string();
    let bytes = crate::input_file::read(path, crate::input_file::cap::DATASET, "a dataset")
        .map_err(|e| err(&file, None, None, e.to_string()))?;
    inputs.record(path, &bytes);
    let text = String::from_utf8(bytes)
        .map_err(|e| err(&file, None, None, format!("not UTF-8 text: {e}")))?;
    if is_csv(path) {
        let dir = path.parent().unwrap_or(Path::new("."));
        read_csv_str(&text, &file, dir, options, inputs)
    } else {
        let dataset = parse_str(text.strip_prefix('\u{feff}').unwrap_or(&text), &file)?;
        Ok(Loaded {
            dataset,
            note: None,
        })
    }
}

/// CSV text -> dataset; `file` names it in messages, `dir` is where a
/// `setup_file` is looked for (recorded in `inputs` when there is one).
pub fn read_csv_str(
    text: &str,
    file: &str,
    dir: &Path,
    options: &ReadOptions,
    inputs: &Inputs,
) -> Result<Loaded, DataError> {
    let read = csv_read::read(text, file, dir, options, inputs)?;
    let rows = read.rows;
    let written = Written {
        locate: &|i| rows.describe(i),
        missing: CSV_MISSING,
    };
    let dataset = parse_table(read.table, file, &written)?;
    Ok(Loaded {
        dataset,
        note: read.note,
    })
}

/// A `.csv` name (any case) is a CSV dataset; anything else is TOML.
pub fn is_csv(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// The two file formats of a dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileFormat {
    Toml,
    Csv,
}

impl FileFormat {
    /// By the file's extension: `.csv` (any case) is CSV, the rest TOML.
    pub fn of(path: &Path) -> FileFormat {
        if is_csv(path) {
            FileFormat::Csv
        } else {
            FileFormat::Toml
        }
    }
}

/// A dataset file, validated, rewritten in `to`: the raw tables (setup
/// block, raw trials, uncertainties as written) carried over unchanged,
/// so that reading the result gives the same [`Dataset`].
pub fn convert_file(path: &Path, to: FileFormat) -> Result<String, DataError> {
    convert_file_with(path, to, &ReadOptions::default(), &Inputs::new())
}

/// [`convert_file`] with what the caller knows of a CSV's dialect, the
/// files read recorded in `inputs`.
pub fn convert_file_with(
    path: &Path,
    to: FileFormat,
    options: &ReadOptions,
    inputs: &Inputs,
) -> Result<String, DataError> {
    read_file(path, options, inputs)?;
    let file = path.display().to_string();
    let text = crate::input_file::read_text(path, crate::input_file::cap::DATASET, "a dataset")
        .map_err(|e| err(&file, None, None, e.to_string()))?;
    let raw = match FileFormat::of(path) {
        FileFormat::Csv => {
            let dir = path.parent().unwrap_or(Path::new("."));
            csv_read::read(&text, &file, dir, options, inputs)?.table
        }
        FileFormat::Toml => toml::from_str(text.strip_prefix('\u{feff}').unwrap_or(&text))
            .map_err(|e| err(&file, None, None, format!("not a valid dataset: {e}")))?,
    };
    match to {
        FileFormat::Toml => Ok(csv_write::to_toml(&raw)),
        FileFormat::Csv => {
            csv_write::to_csv(&raw).map_err(|m| err(&file, None, None, m.to_string()))
        }
    }
}
