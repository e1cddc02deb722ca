//! A lab's data in and out through the real binary: a CSV dataset gives
//! the same `compare` JSON as its TOML, `convert` both ways, the
//! provenance block of every output (and its hash following one changed
//! byte), progress lines on a redirected stderr, `sweep --data`.

use crate::common::{stderr, stdout, swimbot};
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).unwrap()
}

/// `compare --format json` on a dataset, the provenance block removed.
fn compare_json(data: &Path) -> (serde_json::Value, serde_json::Value) {
    let mut v = json(&swimbot(&[
        "compare",
        "--no-report",
        "--format",
        "json",
        "--data",
        data.to_str().unwrap(),
    ]));
    let provenance = v.as_object_mut().unwrap().remove("swimbot").unwrap();
    (v, provenance)
}

#[test]
fn a_csv_dataset_and_its_toml_give_the_same_compare_json() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("paper.toml");
    std::fs::write(&toml, swimbot::data::PAPER_TOML).unwrap();
    let (from_toml, _) = compare_json(&toml);
    let (from_csv, provenance) = compare_json(&example("paper.csv"));
    assert_eq!(from_csv, from_toml);
    // The block comes first; the comparison's keys keep their order after it.
    let o = swimbot(&["compare", "--no-report", "--format", "json"]);
    let text = stdout(&o);
    assert!(text.starts_with("{\n  \"swimbot\": {"), "{text}");
    let (model, cases) = (
        text.find("\"model\"").unwrap(),
        text.find("\"cases\"").unwrap(),
    );
    assert!(model < cases, "declared order: model, dataset, cases, ...");
    assert_eq!(from_csv["cases"].as_array().unwrap().len(), 6);
    // The block names the CSV and its hash.
    let csv_bytes = std::fs::read(example("paper.csv")).unwrap();
    let input = &provenance["inputs"][0];
    assert!(input["path"].as_str().unwrap().ends_with("paper.csv"));
    assert_eq!(
        input["sha256"],
        swimbot::provenance::sha256_hex(&csv_bytes).as_str()
    );
    assert_eq!(provenance["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(provenance["command"][1], "compare");
}

#[test]
fn one_changed_input_byte_changes_the_recorded_hash() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.toml");
    let hash_of_run = |text: &str| {
        std::fs::write(&path, text).unwrap();
        let (_, p) = compare_json(&path);
        p["inputs"][0]["sha256"].as_str().unwrap().to_string()
    };
    let original = swimbot::data::PAPER_TOML;
    // One byte of a comment: the same data, another file.
    let edited = original.replacen("# The paper's data", "# The paper's dat4", 1);
    assert_eq!(edited.len(), original.len());
    assert_ne!(edited, original);
    let (a, b) = (hash_of_run(original), hash_of_run(&edited));
    assert_eq!(a, swimbot::provenance::sha256_hex(original.as_bytes()));
    assert_eq!(b, swimbot::provenance::sha256_hex(edited.as_bytes()));
    assert_ne!(a, b);
}

#[test]
fn convert_writes_toml_and_csv_that_read_back_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("paper.toml");
    let back = dir.path().join("back.csv");
    let paper_csv = example("paper.csv");
    for (input, output) in [(&paper_csv, &toml), (&toml, &back)] {
        let o = swimbot(&[
            "convert",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let written = std::fs::read_to_string(&toml).unwrap();
    assert!(written.starts_with("# swimbot "), "{written}");
    assert!(written.contains("# command: "), "{written}");
    let load = |p: &Path| swimbot::data::load_file(p).unwrap();
    assert_eq!(load(&toml), swimbot::data::paper());
    assert_eq!(load(&back), swimbot::data::paper());
    // A bad cell is an input error naming file, row and column; nothing is written.
    let bad = dir.path().join("bad.csv");
    let text = std::fs::read_to_string(&paper_csv).unwrap();
    std::fs::write(&bad, text.replacen("tail-2,", "tail-2,x", 1)).unwrap();
    let out = dir.path().join("bad.toml");
    let o = swimbot(&[
        "convert",
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("bad.csv: row ") && e.contains("wavelength_mm") && !e.contains("panicked"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn csv_and_written_files_open_with_the_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let o = swimbot(&["compare", "--no-report", "--format", "csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = stdout(&o);
    let first: Vec<&str> = csv.lines().take(3).collect();
    assert!(first[0].starts_with("# swimbot "), "{csv}");
    assert!(first[1].starts_with("# command: "), "{csv}");
    assert!(
        first[2].starts_with("# input: <built-in paper data> sha256 "),
        "{csv}"
    );
    let synth = dir.path().join("s.toml");
    let o = swimbot(&["synth", "--truth", "base", "-o", synth.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&synth).unwrap();
    assert!(text.starts_with("# swimbot "), "{text}");
    // The comments do not stop it from loading.
    swimbot::data::load_file(&synth).unwrap();
    let report = dir.path().join("rep");
    let o = swimbot(&["compare", "-o", report.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        page.contains("<h2 id=\"provenance\">Provenance</h2>"),
        "{page}"
    );
}

/// Runs the binary with stderr redirected to a file, as a notebook or a
/// log does; returns that file's text.
fn stderr_in_a_file(args: &[&str], progress_ms: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("stderr.txt");
    let status = crate::common::command()
        .args(args)
        .current_dir(dir.path())
        .env("SWIMBOT_PROGRESS_MS", progress_ms)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .status()
        .unwrap();
    assert!(status.success());
    std::fs::read_to_string(&log).unwrap()
}

#[test]
fn diagnose_audit_and_compare_say_which_stage_of_how_many() {
    for (args, needle) in [
        (
            &["diagnose", "--no-discovery", "--no-pairs"][..],
            "swimbot: diagnosing 6 cases: the data's quality: stage 1 of 6, ",
        ),
        (&["audit", "--family-samples", "16"][..], " of 4, "),
        (
            &["compare", "--no-report"][..],
            "compare: the model on 6 cases: stage 1 of 1, ",
        ),
    ] {
        let log = stderr_in_a_file(args, "0");
        assert!(log.contains(needle), "{args:?}: no `{needle}` in: {log}");
    }
}

#[test]
fn progress_lines_reach_a_redirected_stderr_and_quiet_silences_them() {
    let sweep = [
        "sweep",
        "--wavelength-mm",
        "8:16:40",
        "--amplitude-mm",
        "2:7:40",
        "--tail-length-mm",
        "60:120:10",
    ];
    let log = stderr_in_a_file(&sweep, "1");
    let lines: Vec<&str> = log
        .lines()
        .filter(|l| l.starts_with("swimbot: sweep: "))
        .collect();
    assert!(!lines.is_empty(), "no progress lines in: {log}");
    assert!(
        lines
            .iter()
            .any(|l| l.contains(" of 16000 geometries (") && l.contains(" left, ")),
        "{log}"
    );
    assert!(!log.contains('\u{1b}'), "escape codes in: {log:?}");
    let quiet: Vec<&str> = sweep.iter().copied().chain(["--quiet"]).collect();
    assert_eq!(stderr_in_a_file(&quiet, "1"), "");
    // The default waits 2 s: a short run prints nothing.
    let short = [
        "sweep",
        "--wavelength-mm",
        "10",
        "--amplitude-mm",
        "2.5",
        "--tail-length-mm",
        "88",
    ];
    assert_eq!(stderr_in_a_file(&short, "2000"), "");
}

/// The first row of `sweep` on the tail (10, 2.5, 88) mm with `extra` flags.
fn sweep_row(extra: &[&str]) -> Vec<f64> {
    let mut args = vec![
        "sweep",
        "--wavelength-mm",
        "10",
        "--amplitude-mm",
        "2.5",
        "--tail-length-mm",
        "88",
    ];
    args.extend_from_slice(extra);
    let o = swimbot(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let line = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .nth(1)
        .unwrap()
        .to_string();
    line.split(',').map(|c| c.parse().unwrap()).collect()
}

#[test]
fn sweep_takes_its_setup_from_a_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let lab = |name: &str, edits: &[(&str, &str)]| -> String {
        let text = edits
            .iter()
            .fold(swimbot::data::PAPER_TOML.to_string(), |t, (a, b)| {
                assert!(t.contains(a), "{a}");
                t.replacen(a, b, 1)
            });
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let paper = sweep_row(&[]);
    // Stokes flow is linear in the viscosity and the base model has no
    // weight: half the viscosity leaves the speed exactly as it was.
    let thin = lab(
        "thin.toml",
        &[("viscosity_pa_s = 3.5", "viscosity_pa_s = 1.75")],
    );
    let thin_row = sweep_row(&["--data", &thin]);
    assert!(
        (thin_row[5] - paper[5]).abs() <= 1e-12 * paper[5].abs(),
        "{thin_row:?} {paper:?}"
    );
    // A slimmer body drags less and is turned faster by the tail; the
    // channel column is the dataset's 40 mm, not the paper's 35.
    let slim = lab(
        "slim.toml",
        &[
            (
                "body_profile = [[10.0, 20.0], [30.0, 18.0], [10.0, 20.0]]\n",
                "",
            ),
            // without a profile its sections' lengths are no input
            ("body_nose_length_mm = 2.887\n", ""),
            ("body_rear_length_mm = 2.887\n", ""),
            ("body_diameter_mm = 20.0", "body_diameter_mm = 16.0"),
            ("channel_diameter_mm = 35.0", "channel_diameter_mm = 40.0"),
        ],
    );
    let slim_row = sweep_row(&["--data", &slim]);
    assert_eq!((paper[4], slim_row[4]), (35.0, 40.0));
    assert!(
        slim_row[5] > paper[5] && slim_row[6] > paper[6],
        "{slim_row:?} {paper:?}"
    );
    // Cases that differ in their setup need --case.
    let mixed = lab(
        "mixed.toml",
        &[("id = \"tail-2\"", "id = \"tail-2\"\nviscosity_pa_s = 1.0")],
    );
    let base = [
        "sweep",
        "--wavelength-mm",
        "10",
        "--amplitude-mm",
        "2.5",
        "--tail-length-mm",
        "88",
        "--data",
        &mixed,
    ];
    let o = swimbot(&base);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("viscosity_pa_s") && stderr(&o).contains("--case"),
        "{}",
        stderr(&o)
    );
    let with_case: Vec<&str> = base.iter().copied().chain(["--case", "tail-2"]).collect();
    assert!(swimbot(&with_case).status.success());
}
