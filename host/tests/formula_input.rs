//! Hostile formulas: the inputs that would overflow the stack are
//! refused with exit 2 through the binary, and the line and column of a
//! formula error point at the offending character of the raw TOML text,
//! whatever escapes, wide characters and string forms it is written with
//! (a property test against the raw text).

use crate::common::{stderr, swimbot};
use proptest::prelude::*;
use swimbot::effects::user_file::parse;

/// An effects file with one effect whose `tail.c_n` formula is `value` (raw TOML).
fn effect_file(value: &str) -> String {
    format!(
        "[[effect]]\nname = \"hostile\"\nstatement = \"s\"\nreference = \"r\"\n\n\
         [[effect.param]]\nname = \"k\"\nunit = \"1\"\ndefault = 1.0\nmin = 0.5\nmax = 2.0\n\n\
         [effect.places]\n\"tail.c_n\" = {value}\n"
    )
}

#[test]
fn formulas_that_overflowed_the_stack_are_exit_2_with_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "parens",
            format!("{}k{}", "(".repeat(8_000), ")".repeat(8_000)),
            "characters",
        ),
        ("sum", format!("k{}", " + 1".repeat(60_000)), "characters"),
        ("minus", format!("{}k", "-".repeat(100_000)), "characters"),
        (
            "deep-parens",
            format!("{}k{}", "(".repeat(200), ")".repeat(200)),
            "deeper than 64",
        ),
        ("powers", format!("k{}", "^1".repeat(300)), "deeper than 64"),
        ("signs", format!("{}k", "-".repeat(500)), "deeper than 64"),
        (
            "abs",
            format!("{}k{}", "abs(".repeat(100), ")".repeat(100)),
            "deeper than 64",
        ),
    ];
    for (name, formula, expect) in cases {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, effect_file(&format!("\"{formula}\""))).unwrap();
        let o = swimbot(&["effects", "--effect-file", path.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains(expect) && err.contains("tail.c_n"),
            "{name}: {err}"
        );
        assert!(
            err.contains(&format!("{name}.toml, line 14")),
            "{name}: {err}"
        );
        assert!(
            err.len() < 2_000,
            "{name}: the message echoes the whole formula"
        );
    }
    // Just inside the limits, the same shapes load.
    let path = dir.path().join("deep-ok.toml");
    let ok = format!("{}k{}", "(".repeat(60), ")".repeat(60));
    std::fs::write(&path, effect_file(&format!("\"{ok}\""))).unwrap();
    let o = swimbot(&["effects", "--effect-file", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// One character of a formula prefix, all of which the lexer accepts.
fn prefix_char() -> impl Strategy<Value = char> {
    prop::sample::select(vec![
        '1', '2', '+', '-', '*', '(', 'k', ' ', '\t', '\n', '\u{3000}', '\u{a0}', '\u{2003}',
    ])
}

/// How the value is written in the file.
#[derive(Debug, Clone, Copy)]
enum Form {
    Basic,
    MultiBasic,
    Literal,
    MultiLiteral,
}

/// `c` inside a basic string: raw when the form allows it, or escaped.
fn basic_char(c: char, multi: bool, pick: u8) -> String {
    let raw_ok = !(c == '"' || c == '\\' || (c.is_control() && c != '\t' && !(multi && c == '\n')));
    match pick % 4 {
        0 if raw_ok => c.to_string(),
        1 if c == '\t' => "\\t".into(),
        1 if c == '\n' => "\\n".into(),
        2 => format!("\\u{:04X}", c as u32),
        3 => format!("\\U{:08X}", c as u32),
        _ if raw_ok => c.to_string(),
        _ => format!("\\u{:04X}", c as u32),
    }
}

/// The raw value and the byte offset (in the value) where `$` is written.
fn encode(formula: &[char], form: Form, picks: &[u8], bend: bool) -> Option<(String, usize)> {
    let (open, multi, basic) = match form {
        Form::Basic => ("\"", false, true),
        Form::MultiBasic => ("\"\"\"", true, true),
        Form::Literal => ("'", false, false),
        Form::MultiLiteral => ("'''", true, false),
    };
    let mut out = String::from(open);
    if multi && bend {
        out.push('\n'); // trimmed by TOML
    }
    let mut at = None;
    for (i, &c) in formula.iter().enumerate() {
        if c == '$' {
            at = Some(out.len());
        }
        if basic {
            out.push_str(&basic_char(c, multi, picks[i % picks.len()]));
            if multi && bend && c == '+' {
                out.push_str("\\\n   "); // a line-ending backslash: it and the blanks vanish
            }
        } else {
            if c == '\n' && !multi {
                return None;
            }
            out.push(c);
        }
    }
    out.push_str(open);
    Some((out, at?))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    #[test]
    fn formula_errors_point_at_the_raw_character(
        prefix in prop::collection::vec(prefix_char(), 0..12),
        suffix in prop::collection::vec(prefix_char(), 0..4),
        form in prop::sample::select(vec![Form::Basic, Form::MultiBasic, Form::Literal, Form::MultiLiteral]),
        picks in prop::collection::vec(any::<u8>(), 1..8),
        bend in any::<bool>(),
    ) {
        let mut formula = prefix.clone();
        formula.push('$');
        formula.extend(&suffix);
        let Some((value, at)) = encode(&formula, form, &picks, bend) else {
            return Ok(());
        };
        let text = effect_file(&value);
        let start = text.find(&value).unwrap() + at;
        let before = &text[..start];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().unwrap().chars().count() + 1;
        let e = parse(&text, "f.toml").expect_err("`$` is not allowed in a formula");
        prop_assert!(e.message.contains("`$`"), "{}\n{}", e, text);
        prop_assert_eq!((e.line, e.column), (line, column), "{}\n{}", e, text);
    }
}

/// A multiplier of 1e300 or 1e-300 would carry the model out of floating-point
/// range (exit 1, or NaN printed with exit 0): it is exit 2 naming the effect.
#[test]
fn multipliers_beyond_a_million_are_exit_2_naming_the_effect() {
    let dir = tempfile::tempdir().unwrap();
    for value in ["1e300", "1e-300", "-1e7 * k"] {
        let path = dir.path().join("thrust.toml");
        let text = effect_file("\"k\"").replace(
            "\"tail.c_n\" = \"k\"",
            &format!("\"tail.thrust\" = \"{value}\"\n\"tail.c_n\" = \"k\""),
        );
        std::fs::write(&path, text).unwrap();
        let o = swimbot(&[
            "compare",
            "--effect-file",
            path.to_str().unwrap(),
            "--effect",
            "hostile",
        ]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{value}: {err}");
        assert!(
            err.contains("`hostile`") && err.contains("tail.thrust") && err.contains("thrust.toml"),
            "{err}"
        );
    }
}

/// The invariants of the effects fuzz target (host/fuzz/fuzz_targets/
/// effects.rs) on stable, as a property test: arbitrary text around the
/// shape of an effects file never panics; an accepted file round-trips.
mod arbitrary_text {
    use super::*;
    use swimbot::effects::formula::{to_toml, FormulaEffect};

    fn piece() -> impl Strategy<Value = String> {
        prop_oneof![
            Just("[[effect]]\nname = \"x\"\nstatement = \"s\"\nreference = \"r\"\n".to_string()),
            Just("[[effect.param]]\nname = \"k\"\nunit = \"1\"\ndefault = 1.0\nmin = 0.5\nmax = 2.0\n".to_string()),
            Just("[effect.places]\n".to_string()),
            "\"(tail|body|load)\\.[a-zA-Z_]{1,8}\" = \"[ -~]{0,30}\"\n",
            "[ -~\\n\\t\u{3000}é\\\\\"']{0,40}",
            any::<String>(),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        #[test]
        fn arbitrary_effect_files_never_panic(pieces in prop::collection::vec(piece(), 0..8)) {
            let text: String = pieces.concat();
            match parse(&text, "f.toml") {
                Err(e) => prop_assert!(e.line <= text.lines().count() + 1, "{}", e),
                Ok(specs) => {
                    let again = parse(&to_toml(&specs), "again.toml").expect("round trip");
                    prop_assert_eq!(&again, &specs);
                    for spec in specs {
                        let p: Vec<f64> = spec.params.iter().map(|p| p.default).collect();
                        let e = FormulaEffect::new(spec, "").expect("compiles");
                        let _ = e.values(&p, &swimbot::data::paper().cases[0]);
                    }
                }
            }
        }
    }
}

/// A user effect at a local drag coefficient with a non-local tail model
/// would change nothing without a word: exit 2 saying why.
#[test]
fn local_drag_places_are_refused_with_a_non_local_tail() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ct.toml");
    let text = effect_file("\"k\"").replace("\"tail.c_n\"", "\"tail.c_t\"");
    std::fs::write(&path, text).unwrap();
    let file = path.to_str().unwrap();
    let o = swimbot(&[
        "compare",
        "--no-report",
        "--effect-file",
        file,
        "--effect",
        "hostile",
        "--tail-model",
        "sbt",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`hostile`") && err.contains("tail.c_t") && err.contains("ct.toml"),
        "{err}"
    );
    let o = swimbot(&[
        "compare",
        "--no-report",
        "--effect-file",
        file,
        "--effect",
        "hostile",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The position property above, through the binary on the inputs that
/// panicked (an escape then a wide character) or misplaced the error (a
/// multi-line string): exit 2, and the line and column of the `$` in the
/// raw file, counted by hand here.
#[test]
fn formula_error_positions_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    // The places line is line 14 of `effect_file`; `"tail.c_n" = ` is 13
    // characters, so the value opens at column 14.
    let cases = [
        ("escape", "\"\\t\u{3000}$\"", 14, 18),
        ("multi", "\"\"\"\nk *\n  2 $ 1\"\"\"", 16, 5),
        ("literal", "'k\u{3000}\u{3000} + $'", 14, 21),
    ];
    for (name, value, line, column) in cases {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, effect_file(value)).unwrap();
        let o = swimbot(&["effects", "--effect-file", path.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        let at = format!("{name}.toml, line {line}, column {column}");
        assert!(
            err.contains(&at) && err.contains("`$`"),
            "{name}: `{at}` not in {err}"
        );
    }
}
