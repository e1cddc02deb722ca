//! Reading a dataset file: CSV or TOML by its extension, the file recorded
//! as an input of the run ([`crate::provenance`]), and the conversion
//! between the two formats (`swimbot convert`).

use super::parse::{err, parse_str, parse_table};
use super::{csv_read, csv_write, DataError, Dataset};
use std::path::Path;

/// Read and validate a dataset file: CSV (`.csv`, docs/data-format.md)
/// or TOML (any other name). The file's path and SHA-256 are recorded as
/// an input of this run ([`crate::provenance`]).
pub fn load_file(path: &Path) -> Result<Dataset, DataError> {
    let file = path.display().to_string();
    let bytes = crate::input_file::read(path, crate::input_file::cap::DATASET, "a dataset")
        .map_err(|e| err(&file, None, None, e.to_string()))?;
    crate::provenance::record_input(path, &bytes);
    let text = String::from_utf8(bytes)
        .map_err(|e| err(&file, None, None, format!("not UTF-8 text: {e}")))?;
    if is_csv(path) {
        let dir = path.parent().unwrap_or(Path::new("."));
        let (table, rows) = csv_read::read(&text, &file, dir)?;
        parse_table(table, &file, &|i| rows.describe(i)).map_err(|mut e| {
            // The TOML wording of where a missing key may go, for a CSV.
            e.message = e.message.replace(
                "(set it in the case or in [setup])",
                "(give it a column, or a `# key = value` line above the column names)",
            );
            e
        })
    } else {
        parse_str(&text, &file)
    }
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
    load_file(path)?;
    let file = path.display().to_string();
    let text = crate::input_file::read_text(path, crate::input_file::cap::DATASET, "a dataset")
        .map_err(|e| err(&file, None, None, e.to_string()))?;
    let raw = match FileFormat::of(path) {
        FileFormat::Csv => {
            let dir = path.parent().unwrap_or(Path::new("."));
            csv_read::read(&text, &file, dir)?.0
        }
        FileFormat::Toml => toml::from_str(&text)
            .map_err(|e| err(&file, None, None, format!("not a valid dataset: {e}")))?,
    };
    match to {
        FileFormat::Toml => Ok(csv_write::to_toml(&raw)),
        FileFormat::Csv => csv_write::to_csv(&raw).map_err(|m| err(&file, None, None, m)),
    }
}
