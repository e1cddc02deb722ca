//! Positions in the raw text of a TOML file for errors found in a decoded
//! string value (a formula): the decoded string differs from what the user
//! sees in the file wherever the value has escapes (`\t`, `\u3000`), a
//! multi-line delimiter or a line-ending backslash, so a column counted in
//! the decoded string is mapped back through the value's raw text.
//!
//! The string forms and escapes are those of the TOML 1.0 specification
//! (<https://toml.io/en/v1.0.0#string>), plus `\e` and `\xHH` of TOML 1.1,
//! which the `toml` crate also accepts.

/// Line and column (1-based, the column in characters) of byte `offset` in
/// `text`; an offset inside a character or past the end is moved back to
/// the character's start or the end.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Byte offset, within `raw` (the value's text, delimiters included), of
/// the decoded string's character number `index` (0-based); the index one
/// past the last character gives the closing delimiter. Text that is not a
/// string literal maps to its start.
pub fn raw_offset(raw: &str, index: usize) -> usize {
    let starts = decoded_starts(raw);
    starts
        .get(index)
        .or(starts.last())
        .copied()
        .unwrap_or_default()
}

/// The raw byte offset of each decoded character, then of the closing delimiter.
fn decoded_starts(raw: &str) -> Vec<usize> {
    let (open, basic) = if raw.starts_with("\"\"\"") {
        (3, true)
    } else if raw.starts_with("'''") {
        (3, false)
    } else if raw.starts_with('"') {
        (1, true)
    } else if raw.starts_with('\'') {
        (1, false)
    } else {
        return vec![0];
    };
    let close = raw.len().saturating_sub(open).max(open);
    let mut i = open;
    // A newline right after a multi-line opening delimiter is not part of the string.
    if open == 3 {
        if raw[i..].starts_with("\r\n") {
            i += 2;
        } else if raw[i..].starts_with('\n') {
            i += 1;
        }
    }
    let body = &raw[..close];
    let mut out = Vec::new();
    while i < close {
        let c = body[i..]
            .chars()
            .next()
            .expect("i < close is inside the body");
        if basic && c == '\\' {
            let next = body[i + 1..].chars().next().unwrap_or(' ');
            if is_toml_blank(next) {
                // A line-ending backslash: it and the whitespace after it vanish.
                i += 1;
                while let Some(w) = body[i..].chars().next().filter(|w| is_toml_blank(*w)) {
                    i += w.len_utf8();
                }
                continue;
            }
            out.push(i);
            i += 1 + match next {
                'u' => 5,
                'U' => 9,
                'x' => 3,
                other => other.len_utf8(),
            };
        } else {
            out.push(i);
            i += c.len_utf8();
        }
    }
    out.push(close);
    out
}

/// TOML's whitespace and newlines (not Unicode's: U+3000 is a character of the string).
fn is_toml_blank(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\r')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_wide_characters_and_multi_line_strings_map_back() {
        // `"\t　$"`: decoded `\t`, U+3000, `$`; the `$` is raw byte 6.
        let raw = "\"\\t\u{3000}$\"";
        assert_eq!(raw_offset(raw, 2), 6);
        assert_eq!(raw_offset(raw, 3), raw.len() - 1);
        assert_eq!(raw_offset("'a$'", 1), 2);
        assert_eq!(raw_offset("\"\"\"\nab\\\n   c$\"\"\"", 3), 12);
        assert_eq!(raw_offset("\"\\u0024\"", 0), 1);
        assert_eq!(line_col("ab\n\u{3000}c", 6), (2, 2));
        // Inside a wide character: moved back to its start, never a panic.
        assert_eq!(line_col("\u{3000}x", 1), (1, 1));
    }
}
