//! The one integration-test binary of the `swimbot` crate. Each file below
//! is a module, not its own test binary: separate binaries would each link
//! the whole crate with its debug info; as modules of one binary the crate
//! is linked once, which saves most of the test build's link time. One
//! file still runs alone: `cargo test -p swimbot --test integration cli::`.

mod common;
mod fixtures;

mod audit;
mod axisym;
mod cli;
mod cli_body;
mod data;
mod data_cli;
mod data_csv;
mod data_quality;
mod discovery_features;
mod discovery_joint;
mod discovery_located;
mod discovery_model_features;
mod discovery_nulls;
mod discovery_pairs;
mod discovery_recorded;
mod discovery_stability;
mod discovery_stagewise;
mod discovery_verdict;
mod discovery_write;
mod emulator_motor;
mod formula_input;
mod hardening;
mod hardening_answer;
mod hardening_inputs;
mod hardening_log;
mod hardening_messages;
mod hardening_outputs;
mod hardening_study;
mod hardening_study_read;
mod hardening_study_write;
mod hidden_effect;
mod input_covariance;
mod likelihood;
mod model;
mod mutation;
mod nonlocal;
mod nonlocal_effects;
mod outputs;
mod page;
mod page_answer;
mod page_escaping;
mod physics_tail;
mod plan_loop;
mod provenance;
mod rate_control;
mod report;
mod robust;
mod run_log;
mod run_log_lost;
mod screens;
mod sim;
mod spreadsheets;
mod study;
mod study_profile;
mod study_proposals;
mod study_sweep;
mod tail_compat;
mod tail_tube;
mod uncertainty;
mod user_effects;

/// A file added to host/tests/ but not declared above would never be
/// compiled (`autotests = false`), its tests silently lost.
#[test]
fn every_test_file_is_a_module_of_this_binary() {
    let root = include_str!("integration.rs");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("host/tests is readable") {
        let path = entry.expect("a directory entry").path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        let is_rust_file = path.extension().is_some_and(|e| e == "rs");
        let is_module_dir = path.join("mod.rs").is_file();
        if (is_rust_file || is_module_dir)
            && stem != "integration"
            && !root.contains(&format!("\nmod {stem};"))
        {
            missing.push(stem.to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "host/tests/{{{}}}.rs: add `mod NAME;` to host/tests/integration.rs",
        missing.join(",")
    );
}
