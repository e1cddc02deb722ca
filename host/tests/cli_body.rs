//! `swimbot body` as a user runs it: the real binary, JSON output checked
//! against exact values, bad input exits with 2 and a clear message.

use crate::common;
use common::swimbot;
use std::f64::consts::PI;
use std::process::Output;

fn json(o: &Output) -> serde_json::Value {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

fn assert_input_error(o: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` missing from: {err}");
    }
}

#[test]
fn a_sphere_in_free_space_has_the_stokes_drag_and_torque() {
    // 20 mm sphere in 1 Pa s: 6 pi mu a, 8 pi mu a^3.
    let v = json(&swimbot(&[
        "body",
        "--spheroid",
        "20:20",
        "--viscosity-pa-s",
        "1",
        "--format",
        "json",
    ]));
    let a = 0.01;
    let drag = v["drag_n_s_per_m"].as_f64().unwrap();
    let rot = v["rotational_drag_n_m_s"].as_f64().unwrap();
    assert!((drag / (6.0 * PI * a) - 1.0).abs() < 0.003, "{v}");
    assert!((rot / (8.0 * PI * a.powi(3)) - 1.0).abs() < 0.006, "{v}");
    assert!(v["flux_error"].is_null() && v["annular_drag_n_s_per_m"].is_null());
}

#[test]
fn the_paper_profile_in_the_closed_tube_sits_between_free_space_and_beyond_the_annulus() {
    let v = json(&swimbot(&[
        "body",
        "--profile",
        "10:20,30:18,10:20",
        "--channel-diameter-mm",
        "35",
        "--channel-length-mm",
        "350",
        "--format",
        "json",
    ]));
    let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
    assert!(f("drag_n_s_per_m") > 3.0 * f("free_drag_n_s_per_m"), "{v}");
    // A cylinder's end effects add to the annular formula's drag; the
    // 18 mm waist takes some away: within 30 % of the formula.
    let r = f("drag_n_s_per_m") / f("annular_drag_n_s_per_m");
    assert!(r > 0.7 && r < 1.3, "{r}");
    assert!(f("flux_error") < 0.005, "{v}");
    assert!(f("body_elements") > 10.0 && f("wall_elements") > 10.0);
    // The open tube drags less than the closed one.
    let open = json(&swimbot(&[
        "body",
        "--profile",
        "10:20,30:18,10:20",
        "--channel-diameter-mm",
        "35",
        "--open",
        "--format",
        "json",
    ]));
    assert!(open["drag_n_s_per_m"].as_f64().unwrap() < f("drag_n_s_per_m"));
    assert!(open["confinement"].as_str().unwrap().contains("open"));
}

#[test]
fn the_dataset_profile_is_used_with_the_case_channel() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.toml");
    let data = include_str!("../data/paper-profile.toml");
    std::fs::write(&path, data).unwrap();
    let p = path.to_str().unwrap();
    let v = json(&swimbot(&[
        "body", "--data", p, "--case", "tail-1", "--format", "json",
    ]));
    assert!(
        v["body"].as_str().unwrap().contains("10:20,30:18,10:20"),
        "{v}"
    );
    assert!(v["confinement"]
        .as_str()
        .unwrap()
        .contains("closed tube, 35 mm x 350 mm"));
    let table = swimbot(&["body", "--data", p, "--case", "tail-1"]);
    let out = String::from_utf8_lossy(&table.stdout);
    assert!(
        out.contains("drag_n_s_per_m") && out.contains("flux error"),
        "{out}"
    );
}

#[test]
fn bad_input_exits_with_2_and_says_what_is_wrong() {
    assert_input_error(
        &swimbot(&["body", "--profile", "10:20,x:18"]),
        &["--profile", "section 2"],
    );
    assert_input_error(
        &swimbot(&["body", "--profile", "10:20,30:-1"]),
        &["section 2 diameter_mm", "positive"],
    );
    assert_input_error(
        &swimbot(&["body", "--spheroid", "50:20", "--channel-diameter-mm", "18"]),
        &["does not fit"],
    );
    // A neck far thinner than its neighbours: the solve's own flux check
    // fails (3.3e6 of the piston flux), so no drag is printed.
    assert_input_error(
        &swimbot(&[
            "body",
            "--profile",
            "10:20,0.001:0.001,10:20",
            "--channel-diameter-mm",
            "35",
        ]),
        &["own check fails", "piston flux"],
    );
    assert_input_error(
        &swimbot(&[
            "body",
            "--spheroid",
            "50:20",
            "--channel-diameter-mm",
            "35",
            "--channel-length-mm",
            "40",
        ]),
        &["tube ends"],
    );
    assert_input_error(&swimbot(&["body", "--spheroid", "50"]), &["--spheroid"]);
    assert_input_error(&swimbot(&["body"]), &["--profile", "--spheroid", "--data"]);
    assert_input_error(
        &swimbot(&["body", "--spheroid", "50:20", "--open"]),
        &["--open needs a channel"],
    );
    assert_input_error(
        &swimbot(&["body", "--spheroid", "50:20", "--viscosity-pa-s=-1"]),
        &["--viscosity-pa-s"],
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.toml");
    let bad = include_str!("../data/paper-profile.toml").replace(
        "body_profile = [[10.0, 20.0], [30.0, 18.0], [10.0, 20.0]]",
        "body_profile = [[10.0, 20.0], [30.0, 18.0], [20.0, 20.0]]",
    );
    std::fs::write(&path, bad).unwrap();
    assert_input_error(
        &swimbot(&["body", "--data", path.to_str().unwrap(), "--case", "tail-1"]),
        &[
            "d.toml",
            "tail-1",
            "body_profile",
            "60 mm",
            "body_length_mm",
        ],
    );
    let bad = include_str!("../data/paper-profile.toml").replace(
        "body_profile = [[10.0, 20.0], [30.0, 18.0], [10.0, 20.0]]",
        "body_profile = [[10.0, 20.0], [30.0, 40.0], [10.0, 20.0]]",
    );
    std::fs::write(&path, bad).unwrap();
    assert_input_error(
        &swimbot(&["body", "--data", path.to_str().unwrap(), "--case", "tail-1"]),
        &["body_profile[1]", "does not fit"],
    );
    assert_input_error(
        &swimbot(&["body", "--data", "/nonexistent.toml", "--case", "x"]),
        &["nonexistent"],
    );
}
