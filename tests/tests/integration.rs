//! The one test binary of `swimbot-integration`: each file below is a
//! module, so the host crate is linked once, not once per file
//! (`autotests = false` in tests/Cargo.toml).

mod battery_ripple;
mod controller_motor;
mod firmware_safety;
mod motor_supervisor;

/// A file added to tests/tests/ but not declared above would never be
/// compiled, its tests silently lost.
#[test]
fn every_test_file_is_a_module_of_this_binary() {
    let root = include_str!("integration.rs");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("tests/tests is readable") {
        let path = entry.expect("a directory entry").path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_some_and(|e| e == "rs")
            && stem != "integration"
            && !root.contains(&format!("\nmod {stem};"))
        {
            missing.push(stem.to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "tests/tests/{{{}}}.rs: add `mod NAME;` to tests/tests/integration.rs",
        missing.join(",")
    );
}
