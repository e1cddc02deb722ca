//! What a study proposes is what `diagnose --write-effect` writes: the
//! `#NAME` of a proposed law is a law of the written file, also when the
//! law's plain name is already taken in the model (it is written as
//! `-2`), so a user who types the proposed command adds the proposed law.

use crate::common::{run_in, stderr, stdout};
use std::path::Path;

fn ok(cwd: &Path, args: &[&str]) -> String {
    let o = run_in(cwd, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o) + &stderr(&o)
}

/// The effect names (`[[effect]]` tables) of an effect file.
fn effect_names(file: &Path) -> Vec<String> {
    let t: toml::Table = std::fs::read_to_string(file).unwrap().parse().unwrap();
    t["effect"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap().to_string())
        .collect()
}

/// The `#NAME`s the study's last diagnosis proposes.
fn proposed(d: &Path) -> Vec<String> {
    let study: toml::Table = std::fs::read_to_string(d.join("swimbot-study.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let last = |v: &toml::Value| -> Vec<String> {
        v.get("proposal")
            .and_then(|p| p.as_array())
            .map(|ps| {
                ps.iter()
                    .filter(|p| p.get("law").is_some())
                    .map(|p| p["name"].as_str().unwrap().to_string())
                    .collect()
            })
            .unwrap_or_default()
    };
    let steps = study.get("step").and_then(|s| s.as_array());
    let diag = steps
        .and_then(|s| s.last())
        .and_then(|s| s.get("diagnosis_after"))
        .or_else(|| study.get("first_diagnosis"))
        .expect("the study keeps its last diagnosis");
    last(diag)
}

#[test]
fn a_proposed_law_is_in_the_file_by_the_name_it_is_proposed_under() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let paper = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/paper.csv");
    std::fs::copy(paper, d.join("paper.csv")).unwrap();
    // A law of the user's own that holds the name diagnose would give a
    // law at the tail's torque, and does (almost) nothing.
    std::fs::write(
        d.join("mine.toml"),
        r#"[[effect]]
name = "located-tail-torque"
statement = "a placeholder that does almost nothing"
reference = "this test"
[[effect.param]]
name = "k"
unit = "1"
default = 0.0
min = -0.000001
max = 0.000001
[effect.places]
"tail.torque" = "1 + k"
"#,
    )
    .unwrap();
    ok(d, &["init", "--data", "paper.csv", "--quiet"]);
    let said = ok(d, &["add", "mine.toml"]);
    let names = proposed(d);
    assert!(
        !names.is_empty(),
        "a law is proposed after the step: {said}"
    );
    ok(d, &["diagnose", "--write-effect", "found.toml"]);
    let written = effect_names(&d.join("found.toml"));
    for n in &names {
        assert!(written.contains(n), "proposed `{n}`, written {written:?}");
        assert!(said.contains(&format!("found.toml#{n}")), "{said}");
    }
    assert!(
        names.iter().any(|n| n == "located-tail-torque-2"),
        "the taken name is written as -2: {names:?}"
    );
    // The proposed command adds the proposed law.
    ok(d, &["add", &format!("found.toml#{}", names[0])]);
}
