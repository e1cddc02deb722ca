//! A law of the effects-file language (docs/effects-format.md: names,
//! numbers, `+ - * / ^`, parentheses and function calls) written as LaTeX
//! math, for the bundle's equations ([`super::steps_table`]): the paper's
//! symbols as Greek letters (`psi` as `\psi`, `Omega_b` as `\Omega_b`), a
//! one-letter name's suffix as a subscript (`B_o`), longer names upright
//! (`\mathrm{body\_gap\_ratio}`), `*` as `\cdot`, the exponent of `^`
//! braced. A token-level rewrite, not a parser: the law is printed as
//! written, never rearranged, so a reader checks it against the file.

use super::steps_table::tex;

/// Greek names the paper's nomenclature uses, by their LaTeX commands.
const GREEK: [(&str, &str); 12] = [
    ("psi", "\\psi"),
    ("pi", "\\pi"),
    ("lambda", "\\lambda"),
    ("omega", "\\omega"),
    ("Omega", "\\Omega"),
    ("tau", "\\tau"),
    ("mu", "\\mu"),
    ("eta", "\\eta"),
    ("theta", "\\theta"),
    ("alpha", "\\alpha"),
    ("beta", "\\beta"),
    ("chi", "\\chi"),
];

const FUNCTIONS: [(&str, &str); 9] = [
    ("exp", "\\exp"),
    ("ln", "\\ln"),
    ("log", "\\log"),
    ("sin", "\\sin"),
    ("cos", "\\cos"),
    ("tan", "\\tan"),
    ("atan", "\\arctan"),
    ("tanh", "\\tanh"),
    ("sqrt", "\\operatorname{sqrt}"),
];

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Name(String),
    Number(String),
    Op(char),
}

fn tokens(s: &str) -> Vec<Token> {
    let chars: Vec<char> = s.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        if c.is_ascii_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token::Name(chars[start..i].iter().collect()));
        } else if c.is_ascii_digit() || c == '.' {
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // an exponent: `1e-3`
            if i + 1 < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if chars[j] == '-' || chars[j] == '+' {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            out.push(Token::Number(chars[start..i].iter().collect()));
        } else {
            if !c.is_whitespace() {
                out.push(Token::Op(c));
            }
            i += 1;
        }
    }
    out
}

/// A name as math: Greek, a subscripted one-letter (or Greek) symbol, or
/// an upright word.
pub fn name(n: &str) -> String {
    if let Some((_, g)) = GREEK.iter().find(|(w, _)| *w == n) {
        return g.to_string();
    }
    if n == "wx" {
        return "\\omega x".into();
    }
    match n.split_once('_') {
        Some((base, sub)) if !sub.is_empty() && !sub.contains('_') => {
            let base = match GREEK.iter().find(|(w, _)| *w == base) {
                Some((_, g)) => g.to_string(),
                None if base.chars().count() == 1 => base.to_string(),
                None => return format!("\\mathrm{{{}}}", tex(n)),
            };
            let sub = match GREEK.iter().find(|(w, _)| *w == sub) {
                Some((_, g)) => g.to_string(),
                None => format!("\\mathrm{{{}}}", tex(sub)),
            };
            format!("{base}_{{{sub}}}")
        }
        _ if n.chars().count() == 1 => n.to_string(),
        _ => format!("\\mathrm{{{}}}", tex(n)),
    }
}

/// A number as math: `1e-3` as `1\times 10^{-3}`.
pub fn number(s: &str) -> String {
    match s.split_once(['e', 'E']) {
        Some((m, e)) => format!("{m}\\times 10^{{{}}}", e.trim_start_matches('+')),
        None => s.to_string(),
    }
}

/// The formula `law` as LaTeX math.
pub fn math(law: &str) -> String {
    let t = tokens(law);
    let mut out = String::new();
    write(&t, &mut 0, &mut out, false);
    out.trim().to_string()
}

/// Tokens from `*i` to the end (or, with `group`, to the closing
/// parenthesis), appended to `out`.
fn write(t: &[Token], i: &mut usize, out: &mut String, group: bool) {
    while *i < t.len() {
        let tok = t[*i].clone();
        *i += 1;
        match tok {
            Token::Op(')') if group => return,
            Token::Op('^') => {
                out.push_str("^{");
                exponent(t, i, out);
                out.push('}');
            }
            Token::Op('*') => out.push_str(" \\cdot "),
            // a sign (after an opening or at the start) keeps to its number
            Token::Op(c @ ('+' | '-')) if out.is_empty() || out.ends_with(['{', '(', '=', ' ']) => {
                out.push(c);
            }
            Token::Op(c) if "+-=".contains(c) => {
                out.push(' ');
                out.push(c);
                out.push(' ');
            }
            Token::Op(c) => out.push_str(&math_char(c)),
            Token::Number(n) => out.push_str(&number(&n)),
            Token::Name(n) => {
                let call = matches!(t.get(*i), Some(Token::Op('(')));
                match FUNCTIONS.iter().find(|(w, _)| *w == n) {
                    Some((_, f)) if call => out.push_str(f),
                    _ => out.push_str(&name(&n)),
                }
            }
        }
    }
}

/// The atom after `^`: a parenthesised group (its parentheses dropped,
/// the braces group it), or one signed name or number.
fn exponent(t: &[Token], i: &mut usize, out: &mut String) {
    match t.get(*i) {
        Some(Token::Op('(')) => {
            *i += 1;
            write(t, i, out, true);
        }
        Some(Token::Op('-')) => {
            out.push('-');
            *i += 1;
            exponent(t, i, out);
        }
        Some(Token::Number(n)) => {
            out.push_str(&number(n));
            *i += 1;
        }
        Some(Token::Name(n)) => {
            out.push_str(&name(n));
            *i += 1;
        }
        _ => {}
    }
}

/// One character outside names and numbers, safe in math mode: LaTeX's
/// special characters escaped (`\textbackslash` and friends are text-mode
/// commands, an error in math), the paper's Greek letters as commands.
fn math_char(c: char) -> String {
    match c {
        '{' | '}' | '#' | '$' | '%' | '&' | '_' => format!("\\{c}"),
        '\\' => "\\backslash ".into(),
        '~' => "\\sim ".into(),
        'ψ' => "\\psi ".into(),
        'λ' => "\\lambda ".into(),
        'Ω' => "\\Omega ".into(),
        'ω' => "\\omega ".into(),
        'π' => "\\pi ".into(),
        '·' => " \\cdot ".into(),
        c if c.is_control() => " ".into(),
        c if c.is_ascii() => c.to_string(),
        c => format!("\\text{{{c}}}"),
    }
}

/// `value ± u` (from [`crate::format::rounding::value_pm`]) as math.
pub fn value_pm(text: &str) -> String {
    let t = text.replace(" ± ", " \\pm ");
    match t.rsplit_once(")e") {
        Some((m, e)) if t.starts_with('(') => format!("{m})\\times 10^{{{e}}}"),
        _ => number(&t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_located_law_reads_as_the_paper_writes_it() {
        assert_eq!(
            math("tau_t = k * (body_gap_ratio / 0.473684)^p"),
            "\\tau_{\\mathrm{t}} = k \\cdot (\\mathrm{body\\_gap\\_ratio}/0.473684)^{p}"
        );
        assert_eq!(
            math("E_x = a * x^(-2)"),
            "E_{\\mathrm{x}} = a \\cdot x^{-2}"
        );
        assert_eq!(
            math("psi = atan(2 * pi * B_o / lambda)"),
            "\\psi = \\arctan(2 \\cdot \\pi \\cdot B_{\\mathrm{o}}/\\lambda)"
        );
        assert_eq!(math("k * 1e-3"), "k \\cdot 1\\times 10^{-3}");
    }

    #[test]
    fn names_that_are_latex_commands_stay_text() {
        // a user's name cannot issue a command or close a group
        let m = math("x_\\input{a} = 1 # $");
        assert!(!m.contains("\\input"), "{m}");
        assert!(!m.contains(" # ") && !m.contains(" $"), "{m}");
    }

    #[test]
    fn rounded_values_become_math() {
        assert_eq!(value_pm("1.255 ± 0.030"), "1.255 \\pm 0.030");
        assert_eq!(
            value_pm("(1.234 ± 0.045)e-7"),
            "(1.234 \\pm 0.045)\\times 10^{-7}"
        );
    }
}
