//! `swimbot sweep` inside a study: the study's calibrated model, its
//! located law included (a user effect only the study knows), on the
//! study's data; at a case's own geometry it predicts what `compare`
//! inside the study predicts for that case.

use crate::common::{run_in, stderr};
use std::path::Path;

fn ok(cwd: &Path, args: &[&str]) -> String {
    let o = run_in(cwd, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

/// The predicted U and Omega_b of a sweep's CSV rows (after the
/// provenance comments and the header).
fn swept(csv: &str) -> Vec<(f64, f64)> {
    csv.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let cells: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            (cells[5], cells[6])
        })
        .collect()
}

/// Equal to the last bit but one: serde_json (without its
/// `float_roundtrip` feature) may read a printed f64 one ulp off.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 2.0 * f64::EPSILON * a.abs().max(b.abs())
}

#[test]
fn a_sweep_in_a_study_is_the_studys_model_with_its_located_law() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        d.join("lab.csv"),
    )
    .unwrap();
    ok(d, &["init", "--data", "lab.csv"]);
    ok(d, &["diagnose", "--write-effect", "found.toml"]);
    ok(d, &["add", "found.toml"]);
    let steps: serde_json::Value =
        serde_json::from_str(&ok(d, &["steps", "--format", "json"])).unwrap();
    let law = steps["step"][0]["effect"]["name"].as_str().unwrap();
    assert!(law.starts_with("located-"), "{law}");
    let cmp: serde_json::Value =
        serde_json::from_str(&ok(d, &["compare", "--format", "json"])).unwrap();
    let base: serde_json::Value = serde_json::from_str(&ok(
        d,
        &["compare", "--data", "lab.csv", "--format", "json"],
    ))
    .unwrap();
    for (c, b) in cmp["cases"]
        .as_array()
        .unwrap()
        .iter()
        .zip(base["cases"].as_array().unwrap())
    {
        let id = c["id"].as_str().unwrap();
        let row = std::fs::read_to_string(d.join("lab.csv"))
            .unwrap()
            .lines()
            .find(|l| l.starts_with(&format!("{id},")))
            .unwrap()
            .to_string();
        let cells: Vec<&str> = row.split(',').collect();
        let csv = ok(
            d,
            &[
                "sweep",
                "--case",
                id,
                "--wavelength-mm",
                cells[1],
                "--amplitude-mm",
                cells[2],
                "--tail-length-mm",
                cells[3],
                "--frequency-hz",
                cells[4],
            ],
        );
        let (u, omega) = swept(&csv)[0];
        let (cu, co) = (
            c["u_pred_mm_s"].as_f64().unwrap(),
            c["omega_pred_hz"].as_f64().unwrap(),
        );
        assert!(
            same(u, cu) && same(omega, co),
            "{id}: {u} {omega} against {cu} {co}"
        );
        // The law changes the prediction (the body's E_x moves Omega_b
        // more than U): a sweep of the bare preset would not have passed.
        let (bu, bo) = (
            b["u_pred_mm_s"].as_f64().unwrap(),
            b["omega_pred_hz"].as_f64().unwrap(),
        );
        let moved = |x: f64, y: f64| (x - y).abs() > 1e-6 * y.abs();
        assert!(
            moved(u, bu) || moved(omega, bo),
            "{id}: {u} {omega} as the preset's"
        );
    }
    // Naming the law as a catalogue effect cannot work; the message says
    // what it is.
    let o = run_in(
        d,
        &[
            "sweep",
            "--effect",
            law,
            "--wavelength-mm",
            "12",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "88",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--effect-file"), "{}", stderr(&o));
}

#[test]
fn a_case_without_data_or_a_study_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(
        dir.path(),
        &[
            "sweep",
            "--case",
            "tail-3",
            "--wavelength-mm",
            "12",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "88",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--case `tail-3`"), "{}", stderr(&o));
}
