//! Fuzz the dataset parser (`swimbot::data::parse_str`) with arbitrary
//! text: no input may panic; every accepted dataset must satisfy the
//! documented limits (`data::limits`) with finite values, and must survive
//! a write/read round trip unchanged.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swimbot::data::{limits, parse_str, to_toml};

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let Ok(data) = parse_str(text, "<fuzz>") else {
        return;
    };
    assert!(!data.cases.is_empty() && data.cases.len() <= limits::MAX_CASES);
    for c in &data.cases {
        assert_eq!(
            limits::check_case(c),
            Ok(()),
            "accepted case {} breaks a limit",
            c.id
        );
        for m in [c.u_mm_s, c.omega_body_hz].into_iter().flatten() {
            assert!(m.standard_error().is_finite() && m.standard_error() > 0.0);
        }
    }
    let again = parse_str(&to_toml(&data), "<round trip>").expect("written data reads back");
    assert_eq!(again.cases.len(), data.cases.len());
});
