//! Fuzz the effects-file reader (`swimbot::effects::user_file::parse`) and
//! the formula compiler with arbitrary text: no input may panic or
//! overflow the stack; an error's line and column lie inside the text; every
//! accepted file compiles, evaluates without a panic on the paper's cases,
//! and survives a write/read round trip unchanged.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swimbot::effects::formula::{to_toml, FormulaEffect};
use swimbot::effects::user_file::parse;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let specs = match parse(text, "<fuzz>") {
        Ok(s) => s,
        Err(e) => {
            assert!(e.line <= text.lines().count().max(1) + 1, "{e}");
            return;
        }
    };
    let again = parse(&to_toml(&specs), "<round trip>").expect("written effects read back");
    assert_eq!(again, specs);
    for spec in specs {
        let defaults: Vec<f64> = spec.params.iter().map(|p| p.default).collect();
        let effect = FormulaEffect::new(spec, "<fuzz>").expect("a checked spec compiles");
        for case in &swimbot::data::paper().cases {
            let _ = effect.values(&defaults, case);
        }
    }
});
