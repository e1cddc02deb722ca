//! The dialect of a spreadsheet's CSV export: the separator between cells
//! (`,`, `;` or a tab) and the decimal mark (a point, or the comma of most
//! European locales, which then writes `;` between cells).
//!
//! The separator is the one of the three that splits the column-name row
//! into the most columns; the decimal mark is read off the number cells
//! (`0,586` against `0.586`), or set with `--decimal-comma`. A file that
//! writes both marks is refused with an example of each: guessing would
//! silently scale a number by 1000 or split it in two.

use std::borrow::Cow;

/// How a CSV file writes its cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dialect {
    pub separator: u8,
    pub decimal_comma: bool,
}

/// What the caller knows of the file's dialect beyond what detection sees.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Numbers are written with a decimal comma (`0,586`), whatever the
    /// cells suggest.
    pub decimal_comma: bool,
}

impl Dialect {
    /// `;` between cells, decimal commas: for the note on what was read.
    pub fn describe(&self) -> String {
        let sep = match self.separator {
            b'\t' => "tabs".to_string(),
            s => format!("`{}`", s as char),
        };
        let mark = if self.decimal_comma {
            "decimal commas"
        } else {
            "decimal points"
        };
        format!("{sep} between cells, {mark}")
    }

    /// Whether this is the format's own dialect (nothing to note).
    pub fn is_plain(&self) -> bool {
        self.separator == b',' && !self.decimal_comma
    }
}

/// The separator that splits `row` (the column names) into the most cells,
/// counted outside quotes; `,` on a tie or when none occurs.
pub fn separator(row: &str) -> u8 {
    let mut counts = [(b',', 0usize), (b';', 0), (b'\t', 0)];
    let mut quoted = false;
    for b in row.bytes() {
        if b == b'"' {
            quoted = !quoted;
        } else if !quoted {
            if let Some(c) = counts.iter_mut().find(|(s, _)| *s == b) {
                c.1 += 1;
            }
        }
    }
    // max_by_key keeps the last maximum: reverse so that `,` wins a tie.
    counts
        .iter()
        .rev()
        .max_by_key(|(_, n)| *n)
        .map_or(b',', |(s, _)| *s)
}

/// A number written with a decimal comma: `0,586`, `-1,5e-3`, `12,0`.
pub fn is_decimal_comma(cell: &str) -> bool {
    let Some((int, frac)) = cell.split_once(',') else {
        return false;
    };
    let int = int.strip_prefix(['-', '+']).unwrap_or(int);
    let frac_digits = frac.split(['e', 'E']).next().unwrap_or("");
    !int.is_empty()
        && int.bytes().all(|b| b.is_ascii_digit())
        && !frac_digits.is_empty()
        && frac_digits.bytes().all(|b| b.is_ascii_digit())
        && cell.replacen(',', ".", 1).parse::<f64>().is_ok()
}

/// A number written with a decimal point: `0.586`, `1.5e-3`.
pub fn is_decimal_point(cell: &str) -> bool {
    cell.contains('.') && cell.parse::<f64>().is_ok()
}

/// The decimal mark of a file from its number cells `(row, cell)`.
/// `Err` says what was seen and what to do.
pub fn decimal_comma<'a>(
    cells: impl Iterator<Item = (u64, &'a str)>,
    options: &ReadOptions,
) -> Result<bool, DecimalMarkError> {
    let (mut comma, mut point) = (None, None);
    for (row, cell) in cells {
        if comma.is_none() && is_decimal_comma(cell) {
            comma = Some((row, cell));
        }
        if point.is_none() && is_decimal_point(cell) {
            point = Some((row, cell));
        }
        if comma.is_some() && point.is_some() {
            break;
        }
    }
    match (comma, point) {
        (Some((rc, c)), Some((rp, p))) => Err(DecimalMarkError::Mixed {
            comma: (rc, c.to_string()),
            point: (rp, p.to_string()),
        }),
        (None, Some((rp, p))) if options.decimal_comma => Err(DecimalMarkError::PointUnderFlag {
            point: (rp, p.to_string()),
        }),
        (comma, _) => Ok(options.decimal_comma || comma.is_some()),
    }
}

/// A file whose numbers are written with two decimal marks: each mark's
/// first `(row, cell)` as data.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecimalMarkError {
    #[error(
        "the numbers are written two ways: a decimal comma in row {} (`{}`) and a decimal point in row {} (`{}`); write every number one way (with `--decimal-comma`, a point is refused)",
        .comma.0, .comma.1, .point.0, .point.1
    )]
    Mixed {
        comma: (u64, String),
        point: (u64, String),
    },
    #[error(
        "`--decimal-comma` was given, but row {} writes `{}` with a decimal point; drop the flag, or write every number with a comma",
        .point.0, .point.1
    )]
    PointUnderFlag { point: (u64, String) },
}

/// A number cell as Rust reads numbers: `0,586` -> `0.586` under a
/// decimal comma.
pub fn number_text(cell: &str, decimal_comma: bool) -> Cow<'_, str> {
    match without_grouping(cell, decimal_comma) {
        Some(plain) if decimal_comma => Cow::Owned(plain.replacen(',', ".", 1)),
        Some(plain) => Cow::Owned(plain),
        None if decimal_comma && is_decimal_comma(cell) => Cow::Owned(cell.replacen(',', ".", 1)),
        None => Cow::Borrowed(cell),
    }
}

/// A number with its thousands grouped -> without the grouping, when the
/// grouping is unambiguous: `1 130,5` or `1 130.5` (a space, a no-break
/// space or a narrow one, as French and Swiss sheets write), and under
/// decimal commas `1.130,5` (German). Every group after the first has
/// exactly three digits, and a point-grouped number needs its decimal
/// comma (`1.130` alone is refused elsewhere as a decimal point among
/// commas: 1.13 or 1130 cannot be told). `None`: not grouped.
fn without_grouping(cell: &str, decimal_comma: bool) -> Option<String> {
    let (sign, rest) = match cell.strip_prefix(['-', '+']) {
        Some(r) => (&cell[..1], r),
        None => ("", cell),
    };
    let mark = if decimal_comma { ',' } else { '.' };
    let (int, frac) = match rest.split_once(mark) {
        Some((i, f)) => (i, Some(f)),
        None => (rest, None),
    };
    let spaces = ['\u{20}', '\u{a0}', '\u{202f}'];
    let group = if int.contains(spaces) {
        ' '
    } else if decimal_comma && int.contains('.') && frac.is_some() {
        '.'
    } else {
        return None;
    };
    let parts: Vec<&str> = if group == ' ' {
        int.split(spaces).collect()
    } else {
        int.split('.').collect()
    };
    let first_ok = (1..=3).contains(&parts[0].len());
    let rest_ok = parts[1..].iter().all(|p| p.len() == 3);
    let digits = parts.iter().all(|p| p.bytes().all(|b| b.is_ascii_digit()));
    let frac_ok = frac.is_none_or(|f| !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit()));
    if !(first_ok && rest_ok && digits && frac_ok && parts.len() > 1) {
        return None;
    }
    let mut out = format!("{sign}{}", parts.concat());
    if let Some(f) = frac {
        out.push(mark);
        out.push_str(f);
    }
    Some(out)
}

/// A `# key = value` line as the spreadsheet left it -> as written: the
/// cells it was split into (at the commas of the original text) joined
/// again, the separators a spreadsheet pads rows with dropped, a value in
/// decimal comma (`# viscosity_pa_s = 3,5`) read as a number.
pub fn header_line(line: &str, dialect: &Dialect) -> String {
    let line = line.trim();
    let joined = if dialect.separator != b',' || line.starts_with('"') {
        let mut reader = csv::ReaderBuilder::new()
            .delimiter(dialect.separator)
            .has_headers(false)
            .flexible(true)
            .from_reader(line.as_bytes());
        let mut cells: Vec<String> = reader
            .records()
            .next()
            .and_then(Result::ok)
            .map(|r| r.iter().map(str::to_string).collect())
            .unwrap_or_else(|| vec![line.to_string()]);
        while cells.last().is_some_and(|c| c.trim().is_empty()) {
            cells.pop();
        }
        cells.join(",")
    } else {
        line.trim_end_matches(|c: char| c == ',' || c.is_whitespace())
            .to_string()
    };
    match joined.split_once('=') {
        Some((key, value)) if dialect.decimal_comma && is_decimal_comma(value.trim()) => {
            format!("{key}= {}", value.trim().replacen(',', ".", 1))
        }
        _ => joined,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_separator_is_the_one_that_splits_the_column_row_most() {
        assert_eq!(separator("id,wavelength_mm,amplitude_mm"), b',');
        assert_eq!(separator("id;wavelength_mm;amplitude_mm"), b';');
        assert_eq!(separator("id\twavelength_mm\tnote"), b'\t');
        assert_eq!(separator("id;\"a;b,c,d,e\""), b';');
        assert_eq!(separator("id"), b',');
    }

    #[test]
    fn decimal_marks_are_told_apart() {
        for yes in ["0,586", "-1,5", "12,0", "1,5e-3"] {
            assert!(is_decimal_comma(yes), "{yes}");
        }
        for no in ["1.234,5", ",5", "5,", "a,b", "1,2,3", "0.586"] {
            assert!(!is_decimal_comma(no), "{no}");
        }
        assert_eq!(number_text("0,586", true), "0.586");
        assert_eq!(number_text("0,586", false), "0,586");
        // Thousands grouped as sheets write them, when it is unambiguous.
        assert_eq!(number_text("1.130,5", true), "1130.5");
        assert_eq!(number_text("-12.345.678,25", true), "-12345678.25");
        assert_eq!(number_text("1 130,5", true), "1130.5");
        assert_eq!(number_text("1\u{a0}130", false), "1130");
        assert_eq!(number_text("1\u{202f}130.25", false), "1130.25");
        // (`1.130` alone: refused by the reader as a point among commas.)
        for ambiguous in ["1.13,5", "1 13", "12 3456", "1.130,", "1 2 3"] {
            assert!(
                number_text(ambiguous, true).parse::<f64>().is_err(),
                "{ambiguous}"
            );
        }
        let plain = ReadOptions::default();
        let cells = [(3, "1"), (4, "0,5")];
        assert_eq!(decimal_comma(cells.into_iter(), &plain), Ok(true));
        let mixed = [(3, "1.5"), (4, "0,5")];
        let e = decimal_comma(mixed.into_iter(), &plain)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("row 4 (`0,5`)") && e.contains("row 3 (`1.5`)"),
            "{e}"
        );
        let forced = ReadOptions {
            decimal_comma: true,
        };
        assert_eq!(decimal_comma([(3, "2")].into_iter(), &forced), Ok(true));
        assert!(decimal_comma([(3, "2.5")].into_iter(), &forced).is_err());
    }

    #[test]
    fn header_lines_are_put_back_together() {
        let euro = Dialect {
            separator: b';',
            decimal_comma: true,
        };
        assert_eq!(
            header_line("# body_profile = [[10.0; 20.0]; [30.0; 18.0]];;;", &euro),
            "# body_profile = [[10.0, 20.0], [30.0, 18.0]]"
        );
        assert_eq!(
            header_line(r##""# source = ""Tables I";" II""";;"##, &euro),
            r##"# source = "Tables I, II""##
        );
        assert_eq!(
            header_line("# viscosity_pa_s = 3,5;;", &euro),
            "# viscosity_pa_s = 3.5"
        );
        let plain = Dialect {
            separator: b',',
            decimal_comma: false,
        };
        assert_eq!(header_line("# x = [1, 2],,,", &plain), "# x = [1, 2]");
    }
}
