//! The header row of a CSV dataset: what each column is (a dataset field, a
//! recorded number the model does not read, or a text label), the names
//! refused (a repeat, a near miss of a field's name, a row no separator
//! split), and the one line that tells the user what was taken as what.

use super::csv_columns::{kind_of, Kind};
use super::csv_dialect::{self, Dialect};
use super::limits::MAX_COLUMNS;

/// Why the header row is refused: in one column, or as a whole.
#[derive(Debug)]
pub(super) struct HeaderError {
    pub column: Option<String>,
    pub message: String,
}

impl HeaderError {
    fn whole(message: impl Into<String>) -> Self {
        HeaderError {
            column: None,
            message: message.into(),
        }
    }
    fn at(column: &str, message: impl Into<String>) -> Self {
        HeaderError {
            column: Some(column.to_string()),
            message: message.into(),
        }
    }
}

/// What a column is: a dataset field, or a recorded variable (numbers,
/// offered to `diagnose`) or a label (text, carried) that the model does
/// not read. `Unknown` until the cells have been seen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Column {
    Field(Kind),
    Recorded,
    Label,
    Unknown,
}

/// The table of recorded numbers, and its column prefix that forces it.
pub(super) const RECORDED: &str = "recorded";
/// The table of labels, and its column prefix that forces it.
pub(super) const LABELS: &str = "labels";

/// `recorded.x` -> `x` (the prefix only forces the kind).
pub(super) fn bare<'a>(name: &'a str, table: &str) -> &'a str {
    name.strip_prefix(table)
        .and_then(|n| n.strip_prefix('.'))
        .unwrap_or(name)
}

/// An unknown column whose every cell is a number is recorded, any other
/// a label; a column with no cells is left out.
pub(super) fn classify(
    columns: &mut [Column],
    records: &[(u64, csv::StringRecord)],
    decimal_comma: bool,
) {
    for (i, column) in columns.iter_mut().enumerate() {
        if *column != Column::Unknown {
            continue;
        }
        let mut cells = records
            .iter()
            .filter_map(|(_, r)| r.get(i))
            .filter(|c| !c.is_empty())
            .peekable();
        if cells.peek().is_none() {
            continue;
        }
        let numeric = cells.all(|c| {
            csv_dialect::number_text(c, decimal_comma)
                .parse::<f64>()
                .is_ok()
        });
        *column = if numeric {
            Column::Recorded
        } else {
            Column::Label
        };
    }
}

/// The one line that says what was taken as what, if anything was not
/// the format's own.
pub(super) fn note(
    file: &str,
    dialect: &Dialect,
    names: &[String],
    columns: &[Column],
) -> Option<String> {
    let list = |want: Column| -> Vec<String> {
        names
            .iter()
            .zip(columns)
            .filter(|(_, c)| **c == want)
            .map(|(n, _)| match n.is_empty() {
                true => "(unnamed)".to_string(),
                false => super::limits::echo(n),
            })
            .collect()
    };
    let mut parts = Vec::new();
    if !dialect.is_plain() {
        parts.push(format!("read with {}", dialect.describe()));
    }
    let recorded = list(Column::Recorded);
    if !recorded.is_empty() {
        parts.push(format!(
            "recorded variables (numbers the model does not read, offered to diagnose): {}",
            recorded.join(", ")
        ));
    }
    let labels = list(Column::Label);
    if !labels.is_empty() {
        parts.push(format!(
            "labels (text, carried through): {}",
            labels.join(", ")
        ));
    }
    let empty = list(Column::Unknown);
    if !empty.is_empty() {
        parts.push(format!("left out (no cells): {}", empty.join(", ")));
    }
    (!parts.is_empty()).then(|| format!("{file}: {}", parts.join("; ")))
}

/// The kind of every column; a repeated name, a name that is close to a
/// field's (a typo would silently become a recorded variable) or a row
/// of names that no separator split is an error.
pub(super) fn column_kinds(names: &[String]) -> Result<Vec<Column>, HeaderError> {
    if names.len() > MAX_COLUMNS {
        return Err(HeaderError::whole(
            format!(
                "{} columns; at most {MAX_COLUMNS} are read (the fields, their uncertainties and the lab's recorded variables): leave the others out of the export",
                names.len()
            ),
        ));
    }
    let known: Vec<&str> = super::csv_columns::COLUMNS.iter().map(|c| c.0).collect();
    if let [only] = names {
        if kind_of(only).is_none() {
            let shown = super::limits::echo(only);
            return Err(HeaderError::whole(
                format!("the column names `{shown}` are one column: no `,`, `;` or tab separates them; save the sheet as CSV with one of these between cells"),
            ));
        }
    }
    // A set, not a search of the names before each: a row of 10^6 names.
    let mut seen = std::collections::HashSet::new();
    names
        .iter()
        .map(|name| {
            if !name.is_empty() && !seen.insert(name.as_str()) {
                return Err(HeaderError::at(name, "the column is given twice"));
            }
            if let Some(kind) = kind_of(name) {
                return Ok(Column::Field(kind));
            }
            let why = if name.is_empty() {
                // Padding if its cells are empty (`unnamed_with_cells`).
                None
            } else if ["u_trials_mm_s", "omega_body_trials_hz", "uncertainty", RECORDED, LABELS]
                .contains(&name.as_str())
            {
                Some(format!("`{name}` has no column: one row per trial replaces u_trials_mm_s and omega_body_trials_hz, uncertainty.KEY columns the uncertainty table, and any other column is a recorded variable"))
            } else {
                known
                    .iter()
                    .find(|k| is_near_miss(k, name))
                    .map(|k| format!("`{}` is not a dataset field: did you mean `{k}`? (a column that is no field is kept as a recorded variable; name it `{RECORDED}.NAME` to keep it so)", super::limits::echo(name)))
            };
            match why {
                Some(why) => Err(HeaderError::at(name, why)),
                None if name.starts_with("recorded.") => Ok(Column::Recorded),
                None if name.starts_with("labels.") => Ok(Column::Label),
                None => Ok(Column::Unknown),
            }
        })
        .collect()
}

/// A column name that is a field's with a typo (`wavelenght_mm`, `ID`),
/// not a short name of the lab's own (`T`, `pH`, `Re` are two edits from
/// `id` but nobody's misspelling of it): at most two edits, ignoring case,
/// and fewer than a third of the longer name's characters.
fn is_near_miss(field: &str, name: &str) -> bool {
    let d = strsim::damerau_levenshtein(field, &name.to_ascii_lowercase());
    let longer = field.chars().count().max(name.chars().count());
    d <= 2 && 3 * d < longer
}
