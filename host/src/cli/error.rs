//! Errors of the command line and their exit codes: bad input (files,
//! flags, values) is exit 2, anything that fails afterwards exit 1.

use std::fmt;

#[derive(Debug)]
pub enum CliError {
    /// The user's input is wrong; the message says where and what.
    Input(String),
    /// The work failed for another reason (I/O while writing, a solver).
    Failure(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failure(_) => 1,
        }
    }

    pub fn input(msg: impl fmt::Display) -> Self {
        CliError::Input(msg.to_string())
    }

    pub fn failure(msg: impl fmt::Display) -> Self {
        CliError::Failure(msg.to_string())
    }
}

/// The longest message printed, in characters. Messages quote the user's
/// input, usually cut already ([`crate::data::limits::echo`]); this is the
/// last guard, so that no input reaches stderr unbounded.
const MAX_MESSAGE_CHARS: usize = 4_000;

/// Control characters (NUL, escape sequences) of a message escaped, except
/// the newlines and tabs of its own layout, and its length bounded.
fn printable(m: &str) -> String {
    let n = m.chars().count();
    let mut out: String = m
        .chars()
        .take(MAX_MESSAGE_CHARS)
        .flat_map(|c| {
            let raw = !c.is_control() || c == '\n' || c == '\t';
            let v: Vec<char> = if raw {
                vec![c]
            } else {
                c.escape_default().collect()
            };
            v
        })
        .collect();
    if n > MAX_MESSAGE_CHARS {
        out.push_str(&format!("... (message cut: {n} characters)"));
    }
    out
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Failure(m) => f.write_str(&printable(m)),
        }
    }
}

impl From<crate::data::DataError> for CliError {
    fn from(e: crate::data::DataError) -> Self {
        CliError::Input(e.to_string())
    }
}

impl From<crate::effects::EffectSpecError> for CliError {
    fn from(e: crate::effects::EffectSpecError) -> Self {
        CliError::Input(e.to_string())
    }
}

/// A model that cannot be evaluated for a case is a problem of the input
/// (geometry, fluid, effect settings), so it exits with 2 as well.
impl From<crate::model::ModelError> for CliError {
    fn from(e: crate::model::ModelError) -> Self {
        CliError::Input(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_escaped_and_bounded() {
        let e = CliError::input(format!(
            "bad `a\0b\u{1b}[31m`:\n\t{}",
            "x".repeat(10_000_000)
        ));
        let shown = e.to_string();
        assert!(
            shown.starts_with("bad `a\\u{0}b\\u{1b}[31m`:\n\t"),
            "{}",
            &shown[..40]
        );
        assert!(shown.len() < MAX_MESSAGE_CHARS + 100);
        assert!(shown.ends_with("(message cut: 10000017 characters)"));
    }
}
