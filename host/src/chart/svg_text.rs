//! Text in figures: the paper's symbols written out in code (`Omega_b`,
//! `N_lambda`, `psi`) turned into physics notation (Ω_b, N_λ, ψ), then into
//! SVG text with real subscripts and superscripts, and a width estimate for
//! layout (the SVG is drawn without font metrics).

/// Greek letters (and ℓ) spelled out as whole words in code and labels.
const SYMBOLS: &[(&str, &str)] = &[
    ("alpha", "α"),
    ("beta", "β"),
    ("gamma", "γ"),
    ("delta", "δ"),
    ("Delta", "Δ"),
    ("epsilon", "ε"),
    ("lambda", "λ"),
    ("mu", "μ"),
    ("pi", "π"),
    ("rho", "ρ"),
    ("sigma", "σ"),
    ("tau", "τ"),
    ("phi", "φ"),
    ("chi", "χ"),
    ("psi", "ψ"),
    ("omega", "ω"),
    ("Omega", "Ω"),
    ("ell", "ℓ"),
];

/// Physics notation: spelled-out Greek words become letters (`Omega_b` ->
/// `Ω_b`, `N_lambda` -> `N_λ`); `_` and `^` are kept for `rich`.
pub fn notation(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        match SYMBOLS.iter().find(|(w, _)| w == word) {
            Some((_, g)) => out.push_str(g),
            None => out.push_str(word),
        }
        word.clear();
    };
    for ch in s.chars() {
        if ch.is_ascii_alphabetic() {
            word.push(ch);
        } else {
            flush(&mut word, &mut out);
            out.push(ch);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// A unit as printed after a label: `deg` -> `°`, dimensionless -> none.
pub fn unit(u: &str) -> Option<String> {
    match u {
        "" | "1" | "-" => None,
        "deg" => Some("°".into()),
        "kg/m^3" => Some("kg/m³".into()),
        other => Some(notation(other)),
    }
}

/// Text as SVG/XML text content or a quoted attribute value: `&`, `<`,
/// `>`, `"` and `'` as entities, so no drawn text (a case name, an
/// effect's name) can become markup.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// Splits `s` into runs of (text, shift): shift -1 subscript, +1 superscript.
/// `_x`/`^x` take the following run of letters and digits (`^` also a sign).
pub fn runs(s: &str) -> Vec<(String, i8)> {
    let mut out: Vec<(String, i8)> = vec![(String::new(), 0)];
    let mut chars = s.chars().peekable();
    while let Some(ch) = chars.next() {
        let shift = match ch {
            '_' => -1,
            '^' => 1,
            _ => 0,
        };
        let starts_run = chars
            .peek()
            .is_some_and(|c| c.is_alphanumeric() || (shift == 1 && *c == '-'));
        if shift == 0 || !starts_run {
            out.last_mut().expect("never empty").0.push(ch);
            continue;
        }
        let mut run = String::new();
        if let Some(c) = chars.next() {
            run.push(c);
        }
        while let Some(c) = chars.peek().filter(|c| c.is_alphanumeric()) {
            run.push(*c);
            chars.next();
        }
        out.push((run, shift));
        out.push((String::new(), 0));
    }
    out.retain(|r| !r.0.is_empty());
    out
}

/// SVG text content: escaped, with `_b` as a subscript tspan and `^2` as a
/// superscript tspan (`Ω_b` -> `Ω<tspan baseline-shift="sub" ...>b</tspan>`).
pub fn rich(s: &str) -> String {
    runs(s)
        .into_iter()
        .map(|(t, shift)| match shift {
            0 => escape(&t),
            -1 => format!(
                "<tspan baseline-shift=\"sub\" font-size=\"75%\">{}</tspan>",
                escape(&t)
            ),
            _ => format!(
                "<tspan baseline-shift=\"super\" font-size=\"75%\">{}</tspan>",
                escape(&t)
            ),
        })
        .collect()
}

/// Advance of one character, in em, of DejaVu Sans (the first face the SVG
/// asks for and the one Linux browsers fall back to; the widest of the
/// faces listed, so the layout holds for the narrower ones). Digits are
/// 0.636 em there: the old 0.58 em left "0.15" 4 px short and the y title
/// of Fig. 4 (e) ran into it.
fn advance(c: char) -> f64 {
    match c {
        'i' | 'l' | 'j' | '\'' | '|' | '!' => 0.28,
        '.' | ',' | ':' | ';' | ' ' => 0.32,
        'f' | 't' | '(' | ')' | '[' | ']' | '/' | '-' => 0.4,
        'r' | 's' | 'z' | 'c' => 0.55,
        '0'..='9' => 0.64,
        'm' | 'M' | '%' | 'W' => 0.98,
        'w' | 'ω' | 'Ω' | '±' | '=' | '+' | '<' | '>' | '≈' | '×' => 0.84,
        c if c.is_ascii_uppercase() => 0.75,
        _ => 0.63,
    }
}

/// Estimated width in pixels of `rich` text `s` at `size_px`.
pub fn width(s: &str, size_px: f64) -> f64 {
    runs(s)
        .iter()
        .map(|(t, shift)| {
            let scale = if *shift == 0 { 1.0 } else { 0.75 };
            t.chars().map(advance).sum::<f64>() * scale
        })
        .sum::<f64>()
        * size_px
}

/// How far text of `size_px` reaches above and below its baseline, in px:
/// DejaVu Sans' ascent (0.93 em) and descent (0.24 em), plus the drop of a
/// `baseline-shift="sub"` run when `subscripts` (about a third of an em
/// in Chromium, which measured the Ω_b title reaching 7 px below its
/// baseline at 12 px).
pub fn extent(size_px: f64, subscripts: bool) -> (f64, f64) {
    let below = if subscripts { 0.24 + 0.36 } else { 0.24 };
    (0.93 * size_px, below * size_px)
}

/// Whether `rich` text `s` has a subscript run.
pub fn has_subscript(s: &str) -> bool {
    runs(s).iter().any(|r| r.1 == -1)
}

/// `10` to the power `e` with Unicode superscripts: 10⁻², 10⁰, 10⁶.
pub fn power_of_ten(e: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits: String = e
        .unsigned_abs()
        .to_string()
        .chars()
        .map(|d| SUP[d.to_digit(10).unwrap_or(0) as usize])
        .collect();
    format!("10{}{digits}", if e < 0 { "⁻" } else { "" })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subscripts_become_tspans() {
        assert_eq!(
            rich("Ω_b"),
            "Ω<tspan baseline-shift=\"sub\" font-size=\"75%\">b</tspan>"
        );
        assert_eq!(
            rich("B_o/R_body < 1"),
            "B<tspan baseline-shift=\"sub\" font-size=\"75%\">o</tspan>/R<tspan baseline-shift=\"sub\" font-size=\"75%\">body</tspan> &lt; 1"
        );
        assert_eq!(
            rich("mm^-1"),
            "mm<tspan baseline-shift=\"super\" font-size=\"75%\">-1</tspan>"
        );
        // A lone underscore is text, not markup.
        assert_eq!(rich("a _ b"), "a _ b");
    }

    #[test]
    fn drawn_text_never_becomes_markup() {
        assert_eq!(
            rich("t<script>&\"q\"'s"),
            "t&lt;script&gt;&amp;&quot;q&quot;&#39;s"
        );
    }

    #[test]
    fn code_names_become_physics_notation() {
        assert_eq!(notation("Omega_b / omega"), "Ω_b / ω");
        assert_eq!(notation("N_lambda = L_t/lambda"), "N_λ = L_t/λ");
        assert_eq!(
            notation("psi = atan(2 pi B_o/lambda)"),
            "ψ = atan(2 π B_o/λ)"
        );
        // Words that merely contain a symbol's name stay as they are.
        assert_eq!(notation("shell pitch"), "shell pitch");
        assert_eq!(unit("deg").as_deref(), Some("°"));
        assert_eq!(unit("1"), None);
    }

    #[test]
    fn powers_of_ten_use_superscripts() {
        assert_eq!(power_of_ten(-2), "10⁻²");
        assert_eq!(power_of_ten(0), "10⁰");
        assert_eq!(power_of_ten(16), "10¹⁶");
    }

    #[test]
    fn subscripts_are_narrower_than_text() {
        assert!(width("R_body", 12.0) < width("Rbody", 12.0));
        assert!(width("tail-1", 11.0) > 20.0);
    }
}
