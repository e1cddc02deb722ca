//! Cross-crate integration tests live in `tests/tests/`; this library holds
//! the helpers they share.
