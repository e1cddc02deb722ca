//! The loop from the real binary: a hidden truth (the body confined by
//! the tube) drawn on the paper's six cases, where the two-parameter
//! `body-correction` mimics it; `init`, whose diagnosis picks the mimic
//! with the truth close behind; `plan` in the lab's three tubes; the
//! simulated lab (`sim --plan --truth`); `data add`, which recalibrates and
//! diagnoses again; and a verdict that names the truth. Then what the loop
//! refuses: a rig that runs nothing, a sheet from another robot, a sheet
//! joined twice or edited after it joined; and a plan with nothing to do.

use crate::common::{run_in, stderr, stdout};
use std::path::Path;

fn ok(cwd: &Path, args: &[&str]) -> String {
    let o = run_in(cwd, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

fn refused(cwd: &Path, args: &[&str]) -> String {
    let o = run_in(cwd, args);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stdout(&o));
    let e = stderr(&o);
    assert!(e.contains("error:"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

fn sha(p: &Path) -> String {
    swimbot::provenance::sha256_hex(&std::fs::read(p).unwrap())
}

/// A study on the paper's six cases measured in a world of `truth`
/// (seed `seed` of the noise).
fn study_of(truth: &str, seed: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let synth = [
        "synth",
        "--truth",
        truth,
        "--seed",
        seed,
        "--nominal-inputs",
        "-o",
        "lab.toml",
    ];
    ok(d, &synth);
    ok(d, &["init", "--data", "lab.toml", "--quiet"]);
    dir
}

/// A study on the confined-body truth.
fn confined_study() -> tempfile::TempDir {
    study_of("base + body-confinement", "3")
}

fn last_verdict(d: &Path) -> serde_json::Value {
    let json: serde_json::Value =
        serde_json::from_str(&ok(d, &["steps", "--format", "json"])).unwrap();
    let steps = json["step"].as_array().cloned().unwrap_or_default();
    match steps.last() {
        Some(s) => s["diagnosis_after"].clone(),
        None => json["first_diagnosis"].clone(),
    }
}

#[test]
fn a_planned_run_in_another_tube_resolves_the_mimic_and_names_the_truth() {
    let dir = confined_study();
    let d = dir.path();
    let first = last_verdict(d);
    assert_eq!(first["verdict"], "identified", "{first}");
    assert!(
        first["proposal"].to_string().contains("body-correction"),
        "{first}"
    );

    let said = ok(
        d,
        &[
            "plan",
            "--runs",
            "1",
            "--tubes-mm",
            "25,35,50",
            "-o",
            "plan.csv",
        ],
    );
    assert!(said.contains("body-correction (AICc +0.0)"), "{said}");
    assert!(said.contains("body-confinement (AICc +"), "{said}");
    let sheet = std::fs::read_to_string(d.join("plan.csv")).unwrap();
    let row = sheet
        .lines()
        .find(|l| l.starts_with("plan-1,"))
        .expect("one run");
    // Not the data's own 35 mm tube: there the two models agree.
    assert!(!row.contains(",35.0,350.0,"), "{row}");

    let ran = ok(
        d,
        &[
            "sim",
            "--plan",
            "plan.csv",
            "--truth",
            "base + body-confinement",
            "-o",
            "lab",
        ],
    );
    assert!(ran.contains("plan-1: motor held at"), "{ran}");
    assert!(d.join("lab/plan-1.swlog").is_file());
    // The simulated run's log reads as a robot's does.
    ok(d, &["log", "lab/plan-1.swlog", "-o", "log", "--quiet"]);

    let data_before = sha(&d.join("lab.toml"));
    let joined = ok(d, &["data", "add", "lab/plan-filled.csv"]);
    assert!(joined.contains("1 run (plan-1), 6 -> 7 cases"), "{joined}");
    assert!(joined.contains("start (base): MARE"), "{joined}");
    assert_eq!(
        sha(&d.join("lab.toml")),
        data_before,
        "the dataset is never rewritten"
    );
    let now = last_verdict(d);
    let effect = now["proposal"].to_string();
    assert!(effect.contains("body-confinement"), "{now}");
    assert!(!effect.contains("body-correction"), "{now}");

    let listed = ok(d, &["data", "list"]);
    assert!(
        listed.contains("lab/plan-filled.csv: 1 run (plan-1)"),
        "{listed}"
    );
    assert!(listed.contains("7 cases in all"), "{listed}");
}

#[test]
fn the_loop_refuses_what_it_cannot_run_or_join_and_loses_nothing() {
    let dir = confined_study();
    let d = dir.path();
    let e = refused(d, &["plan", "--tubes-mm", "12", "-o", "p.csv"]);
    assert!(e.contains("--tubes-mm"), "{e}");
    let e = refused(d, &["plan", "--oils-pa-s", "1e9", "-o", "p.csv"]);
    assert!(e.contains("--oils-pa-s"), "{e}");
    assert!(!d.join("p.csv").exists());
    // A robot whose motor holds no set-point against this load.
    let robot = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/robot.toml"))
        .unwrap()
        .replace(
            "viscous_friction_n_m_s = 1.18e-4",
            "viscous_friction_n_m_s = 5e-2",
        );
    std::fs::write(d.join("weak.toml"), robot).unwrap();
    let e = refused(d, &["plan", "--robot", "weak.toml", "-o", "p.csv"]);
    assert!(e.contains("--robot") && e.contains("holds none"), "{e}");
    assert!(!d.join("p.csv").exists());

    ok(
        d,
        &[
            "plan",
            "--runs",
            "2",
            "--tubes-mm",
            "25,35,50",
            "-o",
            "plan.csv",
        ],
    );
    let e = refused(d, &["sim", "--plan", "plan.csv", "-o", "lab"]);
    assert!(e.contains("--truth"), "{e}");
    ok(
        d,
        &[
            "sim",
            "--plan",
            "plan.csv",
            "--truth",
            "base + body-confinement",
            "-o",
            "lab",
        ],
    );
    let study = d.join("swimbot-study.toml");
    let before = sha(&study);

    // Another robot's run: a wider body.
    let filled = std::fs::read_to_string(d.join("lab/plan-filled.csv")).unwrap();
    let other = filled.replacen(",20.0,50.0,", ",22.0,50.0,", 1);
    assert_ne!(other, filled);
    std::fs::write(d.join("other.csv"), other).unwrap();
    let e = refused(d, &["data", "add", "other.csv"]);
    assert!(
        e.contains("row 1 (case `plan-1`): field `body_diameter_mm`"),
        "{e}"
    );
    assert!(e.contains("nothing was changed"), "{e}");
    assert_eq!(sha(&study), before);

    // An empty sheet (no run made).
    std::fs::write(
        d.join("empty.csv"),
        std::fs::read(d.join("plan.csv")).unwrap(),
    )
    .unwrap();
    let e = refused(d, &["data", "add", "empty.csv"]);
    assert!(e.contains("no row of the sheet has a measurement"), "{e}");
    assert_eq!(sha(&study), before);

    ok(d, &["data", "add", "lab/plan-filled.csv", "--no-diagnose"]);
    let e = refused(d, &["data", "add", "lab/plan-filled.csv"]);
    assert!(e.contains("already joined"), "{e}");

    // A joined sheet edited afterwards: every command on the study refuses.
    let mut edited = std::fs::read_to_string(d.join("lab/plan-filled.csv")).unwrap();
    edited.push('\n');
    std::fs::write(d.join("lab/plan-filled.csv"), edited).unwrap();
    let e = refused(d, &["steps"]);
    assert!(e.contains("changed since it joined"), "{e}");
}

#[test]
fn a_plan_with_nothing_to_separate_or_sharpen_says_so_and_writes_nothing() {
    let dir = study_of("base", "1");
    let d = dir.path();
    let said = ok(d, &["plan", "-o", "plan.csv"]);
    assert!(said.starts_with("nothing to plan"), "{said}");
    assert!(!d.join("plan.csv").exists());
}

/// The lines of docs/study.md's worked example inside ```text blocks
/// after its heading.
fn worked_example_lines() -> Vec<String> {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/study.md")).unwrap();
    let from = doc
        .find("### A worked example: a mimic refuted by one planned run")
        .expect("the worked example's heading");
    let mut lines = Vec::new();
    let mut inside = false;
    for l in doc[from..]
        .lines()
        .take_while(|l| !l.starts_with("**Planned against"))
    {
        match l {
            "```text" => inside = true,
            "```" => inside = false,
            l if inside => lines.push(l.to_string()),
            _ => {}
        }
    }
    lines
}

#[test]
fn the_worked_example_of_the_docs_is_what_the_commands_print() {
    let dir = confined_study();
    let d = dir.path();
    let mut said = ok(d, &["add", "body-correction"]);
    said += &ok(
        d,
        &[
            "plan",
            "--runs",
            "1",
            "--tubes-mm",
            "25,35,50",
            "-o",
            "plan.csv",
        ],
    );
    said += &ok(
        d,
        &[
            "sim",
            "--plan",
            "plan.csv",
            "--truth",
            "base + body-confinement",
            "-o",
            "lab",
        ],
    );
    let joined = ok(d, &["data", "add", "lab/plan-filled.csv"]);
    assert!(joined.contains("the new runs contradict it"), "{joined}");
    said += &joined;
    said += &ok(d, &["undo"]);
    said += &ok(d, &["diagnose"]);
    let quoted = worked_example_lines();
    assert!(quoted.len() >= 10, "{quoted:?}");
    for l in &quoted {
        assert!(
            said.lines().any(|s| s == l),
            "docs/study.md quotes `{l}`, the commands print:\n{said}"
        );
    }
}
