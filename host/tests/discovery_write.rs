//! `diagnose --write-effect`: the located law as an effect file in the
//! agreed format, with its base, loadable by `compare`; nothing written on
//! a null (src/workbench/discovery/write.rs, through the binary).

use crate::fixtures;

use fixtures::diagnosed::{data, swimbot_cmd, SEED};
use swimbot::model::Model;

#[test]
fn write_effect_gives_a_file_in_the_agreed_format_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("located.toml");
    let out = crate::common::command()
        .args(["diagnose", "--format", "json", "--write-effect"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let kind = json["verdict"]["kind"].as_str().unwrap();
    assert!(["located", "unexplained", "indistinguishable", "identified"].contains(&kind));
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let e = &v["effect"][0];
    let name = e["name"].as_str().unwrap();
    assert!(
        name.starts_with("located-")
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
    );
    assert!(e["reference"]
        .as_str()
        .unwrap()
        .contains("located by swimbot diagnose"));
    let places = e["places"].as_table().unwrap();
    assert_eq!(places.len(), 1);
    let (place, formula) = places.iter().next().unwrap();
    assert!(
        swimbot::effects::place::Place::from_name(place).is_some(),
        "{place}"
    );
    let formula = formula.as_str().unwrap();
    for p in e["param"].as_array().unwrap() {
        let (d, lo, hi) = (
            p["default"].as_float().unwrap(),
            p["min"].as_float().unwrap(),
            p["max"].as_float().unwrap(),
        );
        assert!(lo <= d && d <= hi, "{p:?}");
        assert!(formula.contains(p["name"].as_str().unwrap()));
    }
    // The formula names its feature by a quantity id.
    let located = &json["verdict"]["located"][0];
    if let Some(f) = located["feature"].as_str() {
        assert!(formula.contains(f), "{formula}");
        assert!(swimbot::data::quantities::by_id(f).is_some());
    }
}

/// A correct null is an answer: exit 0, a message, no file.
#[test]
fn write_effect_on_a_null_writes_nothing_and_exits_zero() {
    let dir = tempfile::tempdir().unwrap();
    let data = data(&Model::base(), SEED);
    std::fs::write(dir.path().join("null.toml"), swimbot::data::to_toml(&data)).unwrap();
    let out = swimbot_cmd(
        &[
            "diagnose",
            "--data",
            "null.toml",
            "--write-effect",
            "w.toml",
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("no file was written"), "{err}");
    assert!(!dir.path().join("w.toml").exists());
}

/// The written file carries its base; loading the law alone adds the base
/// and reproduces the MARE `diagnose` reported for it.
#[test]
fn the_written_base_is_applied_when_the_effect_is_loaded() {
    let dir = tempfile::tempdir().unwrap();
    let out = swimbot_cmd(
        &["diagnose", "--format", "json", "--write-effect", "w.toml"],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(dir.path().join("w.toml")).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let first = &v["effect"][0];
    let base = first["base"].as_array().expect("a base field");
    assert!(!base.is_empty(), "{text}");
    let name = first["name"].as_str().unwrap();
    let out = swimbot_cmd(
        &[
            "compare",
            "--format",
            "json",
            "--effect-file",
            "w.toml",
            "--effect",
            name,
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("was fitted on top of"), "{err}");
    let cmp: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mare = cmp["summary"]["mare"].as_f64().unwrap();
    let want = json["verdict"]["located"][0]["mare"].as_f64().unwrap();
    assert!((mare - want).abs() < 1e-6 * want, "{mare} vs {want}");
}
