//! The lexer of the formula language ([`super::expr`]) and the "did you
//! mean" suggestions of its error messages (Levenshtein distance).

use super::expr::ExprError;

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Kind {
    Num(f64),
    Ident,
    Op(char),
}

#[derive(Debug, Clone)]
pub(super) struct Token {
    pub kind: Kind,
    pub text: String,
    pub column: usize,
}

pub(super) fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent only when digits follow, so `2e` stays an error, not 2.
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let x: f64 = s.parse().map_err(|_| ExprError {
                column,
                message: format!("`{s}` is not a number"),
            })?;
            out.push(Token {
                kind: Kind::Num(x),
                text: s,
                column,
            });
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            // A dot joins a name to the next (`recorded.temperature_c`);
            // the parser says which dotted names exist.
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric()
                    || chars[i] == '_'
                    || (chars[i] == '.'
                        && chars
                            .get(i + 1)
                            .is_some_and(|c| c.is_ascii_alphabetic() || *c == '_')))
            {
                i += 1;
            }
            out.push(Token {
                kind: Kind::Ident,
                text: chars[start..i].iter().collect(),
                column,
            });
        } else if "+-*/^(),".contains(c) {
            out.push(Token {
                kind: Kind::Op(c),
                text: c.to_string(),
                column,
            });
            i += 1;
        } else {
            return Err(ExprError {
                column,
                message: format!(
                    "unexpected character `{c}`; allowed: numbers, names, + - * / ^ ( ) and commas"
                ),
            });
        }
    }
    Ok(out)
}

/// `" (did you mean `a`, `b`?)"` for the closest candidates, or nothing.
pub fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> String {
    let mut close: Vec<(usize, &str)> = candidates
        .filter_map(|c| {
            let d = edit_distance(name, c);
            let near = d <= 2.max(name.len() / 4)
                || (name.len() >= 3 && (c.contains(name) || name.contains(c) && c.len() >= 3));
            near.then_some((d, c))
        })
        .collect();
    close.sort();
    close.dedup_by(|a, b| a.1 == b.1);
    if close.is_empty() {
        return String::new();
    }
    let names: Vec<String> = close.iter().take(4).map(|c| format!("`{}`", c.1)).collect();
    format!(" (did you mean {}?)", names.join(", "))
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != b[j]))
                .min(row[j] + 1)
                .min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}
