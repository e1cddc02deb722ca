//! The real `swimbot` binary on temporary directories: outputs, exit codes,
//! and error messages for bad input.

use crate::common;
use common::{stderr, stdout, swimbot};
use std::process::Output;

fn assert_input_error(o: &Output, needles: &[&str]) {
    assert_eq!(o.status.code(), Some(2), "stderr: {}", stderr(o));
    let err = stderr(o);
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` missing from: {err}");
    }
}

#[test]
fn compare_json_has_the_documented_keys_and_writes_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("rep");
    let o = swimbot(&[
        "compare",
        "--preset",
        "paper",
        "--format",
        "json",
        "--output",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 6);
    for key in [
        "id",
        "u_pred_mm_s",
        "u_obs_mm_s",
        "u_ci_mm_s",
        "omega_pred_hz",
        "omega_obs_hz",
        "omega_ci_hz",
        "u_rel_err",
        "omega_rel_err",
    ] {
        assert!(!cases[0][key].is_null(), "missing {key}");
    }
    for key in ["mare", "max_abs_rel_err", "chi2_reduced"] {
        assert!(v["summary"][key].is_number(), "missing summary.{key}");
    }
    assert!(report.join("index.html").exists());
}

#[test]
fn compare_rejects_bad_data_with_file_case_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.toml");
    let text = swimbot::data::PAPER_TOML.replace("tail_length_mm = 60.0", "tail_length_mm = 0.0");
    std::fs::write(&f, text).unwrap();
    let o = swimbot(&["compare", "--no-report", "--data", f.to_str().unwrap()]);
    assert_input_error(&o, &["bad.toml", "tail-4", "tail_length_mm"]);
}

#[test]
fn unknown_preset_effect_and_parameter_are_input_errors() {
    assert_input_error(
        &swimbot(&["compare", "--no-report", "--preset", "nope"]),
        &["nope", "paper"],
    );
    assert_input_error(
        &swimbot(&["compare", "--no-report", "--effect", "nope"]),
        &["nope", "backflow"],
    );
    assert_input_error(
        &swimbot(&["compare", "--no-report", "--effect", "buoyancy:mass=3"]),
        &["mass", "net_force_mn"],
    );
}

#[test]
fn helix_prints_the_matrix_and_its_entries() {
    let o = swimbot(&[
        "helix",
        "--wavelength-mm",
        "15.5",
        "--amplitude-mm",
        "2.5",
        "--tail-length-mm",
        "130",
        "--wire-diameter-mm",
        "1",
        "--viscosity-pa-s",
        "3.5",
        "--format",
        "json",
    ]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["matrix"].as_array().unwrap().len(), 6);
    assert!(v["thrust_n_s"].as_f64().unwrap() < 0.0);
    assert!(
        v["drag_n_s_per_m"].as_f64().unwrap() > 0.0 && v["torque_n_m_s"].as_f64().unwrap() > 0.0
    );
    let q = swimbot(&[
        "helix",
        "--wavelength-mm",
        "15.5",
        "--amplitude-mm",
        "2.5",
        "--tail-length-mm",
        "130",
        "--method",
        "quadrature",
        "--format",
        "json",
    ]);
    let w: serde_json::Value = serde_json::from_str(&stdout(&q)).unwrap();
    let rel =
        (w["drag_n_s_per_m"].as_f64().unwrap() / v["drag_n_s_per_m"].as_f64().unwrap() - 1.0).abs();
    assert!(rel < 1e-4);
    assert_input_error(
        &swimbot(&[
            "helix",
            "--wavelength-mm",
            "-1",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "130",
        ]),
        &["--wavelength-mm"],
    );
    assert_input_error(
        &swimbot(&[
            "helix",
            "--wavelength-mm",
            "0.5",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "130",
        ]),
        &["gray-hancock"],
    );
}

#[test]
fn sweep_writes_one_row_per_grid_point() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.csv");
    let o = swimbot(&[
        "sweep",
        "--wavelength-mm",
        "8:16:5",
        "--amplitude-mm",
        "2:7:3",
        "--tail-length-mm",
        "60",
        "--frequency-hz",
        "0.5:1.5:2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    // Below the provenance comments (`# swimbot ...`).
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 1 + 5 * 3 * 2);
    assert!(lines[0].starts_with("wavelength_mm,amplitude_mm"));
    assert!(lines[1..]
        .iter()
        .all(|l| l.split(',').count() == 9 && !l.contains("NaN")));
    // Omega_b as a positive counter-rotation (the summaries' convention),
    // every number in plain decimals (no `1.110260e0`).
    let header: Vec<&str> = lines[0].split(',').collect();
    let omega = header
        .iter()
        .position(|h| *h == "omega_body_counter_hz")
        .expect("the counter-rotation column");
    for l in &lines[1..] {
        let w: f64 = l.split(',').nth(omega).unwrap().parse().unwrap();
        assert!(w > 0.0, "{l}");
        assert!(!l.contains('e'), "scientific notation: {l}");
    }
    assert_input_error(
        &swimbot(&[
            "sweep",
            "--wavelength-mm",
            "8:16",
            "--amplitude-mm",
            "2",
            "--tail-length-mm",
            "60",
        ]),
        &["--wavelength-mm"],
    );
    assert_input_error(
        &swimbot(&[
            "sweep",
            "--wavelength-mm",
            "10",
            "--amplitude-mm",
            "20",
            "--tail-length-mm",
            "60",
        ]),
        &["--amplitude-mm", "channel"],
    );
}

#[test]
fn effects_lists_the_catalogue() {
    let o = swimbot(&["effects", "--format", "json"]);
    assert!(o.status.success());
    let listed: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let names: Vec<&str> = listed
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    let catalogue: Vec<&str> = swimbot::effects::CATALOGUE
        .iter()
        .map(|e| e.name())
        .collect();
    assert_eq!(names, catalogue);
    assert!(listed
        .as_array()
        .unwrap()
        .iter()
        .all(|e| !e["statement"].as_str().unwrap().is_empty()));
}

#[test]
fn synth_then_diagnose_finds_the_hidden_effect_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    let design = dir.path().join("design.toml");
    std::fs::write(
        &design,
        swimbot::data::to_toml(&swimbot::workbench::synth::varied_design(
            &swimbot::data::paper(),
        )),
    )
    .unwrap();
    let out = dir.path().join("synthetic.toml");
    let o = swimbot(&[
        "synth",
        "--data",
        design.to_str().unwrap(),
        "--truth",
        "base + buoyancy:net_force_mn=0.3",
        "--noise",
        "0.02",
        "--trials",
        "5",
        "--seed",
        "7",
        // the truth on the recorded inputs: this test is about the effect
        "--nominal-inputs",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = swimbot(&[
        "diagnose",
        "--data",
        out.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(
        v["verdict"]["effect"], "buoyancy",
        "{}",
        v["verdict"]["note"]
    );
    assert_eq!(v["verdict"]["explained"], true);
    for key in ["mare", "chi2_reduced"] {
        assert!(v["baseline"][key].is_number());
    }
    let top = &v["ranking"][0];
    for key in [
        "effect",
        "params",
        "mare",
        "cv_mare",
        "chi2_reduced",
        "aicc",
    ] {
        assert!(!top[key].is_null(), "ranking[0].{key}");
    }
}

#[test]
fn diagnose_on_the_paper_data_says_unexplained_and_ranks_confinement_first_among_zero_parameter_effects(
) {
    let o = swimbot(&["diagnose", "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(v["verdict"]["effect"].is_null());
    assert_eq!(v["verdict"]["explained"], false);
    let ranking = v["ranking"].as_array().unwrap();
    let zero_param: Vec<&serde_json::Value> = ranking
        .iter()
        .filter(|c| c["params"].as_array().unwrap().is_empty())
        .collect();
    assert_eq!(zero_param[0]["effect"], "body-confinement");
    assert!(
        zero_param[0]["mare"].as_f64().unwrap() < 0.5 * v["baseline"]["mare"].as_f64().unwrap()
    );
}

#[test]
fn fit_calibrates_on_chosen_cases_and_rejects_unknown_ones() {
    let o = swimbot(&[
        "fit",
        "--effect",
        "body-correction",
        "--cases",
        "tail-3,tail-4",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let est = v["fit"]["estimates"].as_array().unwrap();
    assert_eq!(est.len(), 2);
    assert!(
        est[0]["value"].as_f64().unwrap() > 1.0,
        "the body needs more drag than a free spheroid"
    );
    assert_eq!(v["comparison"]["cases"].as_array().unwrap().len(), 6);
    assert_input_error(
        &swimbot(&["fit", "--effect", "body-correction", "--cases", "tail-9"]),
        &["tail-9", "tail-1"],
    );
    assert_input_error(
        &swimbot(&["fit", "--effect", "coupler"]),
        &["no free parameter"],
    );
    assert_input_error(
        &swimbot(&[
            "fit",
            "--effect",
            "body-correction",
            "--effect",
            "buoyancy",
            "--cases",
            "tail-3",
        ]),
        &["3 free parameters", "2 measured"],
    );
}

#[test]
fn synth_rejects_bad_settings() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.toml");
    let o = out.to_str().unwrap();
    assert_input_error(
        &swimbot(&["synth", "--truth", "base", "--noise=-0.1", "-o", o]),
        &["--noise"],
    );
    assert_input_error(
        &swimbot(&["synth", "--truth", "base", "--trials", "1", "-o", o]),
        &["--trials"],
    );
    assert_input_error(
        &swimbot(&["synth", "--truth", "nonsense", "-o", o]),
        &["nonsense"],
    );
    assert!(!out.exists(), "nothing is written on bad input");
}
/// The binary in `dir` as its working directory.
fn swimbot_in(dir: &std::path::Path, args: &[&str]) -> Output {
    crate::common::command()
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the swimbot binary runs")
}

#[test]
fn default_outputs_go_under_swimbot_out_only() {
    let dir = tempfile::tempdir().unwrap();
    let o = swimbot_in(
        dir.path(),
        &["sim", "--max-time-s", "3", "--sample-every-s", "1"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("swimbot-out/sim/sim.csv").is_file());
    let top: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(top, ["swimbot-out"], "sim wrote beside swimbot-out/");
    // The default shown in the help is the one used.
    let help = stdout(&swimbot(&["sim", "--help"]));
    assert!(help.contains("[default: swimbot-out/sim]"), "{help}");
    let help = stdout(&swimbot(&["compare", "--help"]));
    assert!(help.contains("[default: swimbot-out/compare]"), "{help}");
}

#[test]
fn old_flag_spellings_still_work_but_are_not_advertised() {
    // The JSON without its provenance, which records the command line, and
    // without the run's own memory high-water mark.
    let helix = |len_flag: &str| {
        let mut v: serde_json::Value = serde_json::from_str(&stdout(&swimbot(&[
            "helix",
            "--wavelength-mm",
            "15.5",
            "--amplitude-mm",
            "2.5",
            len_flag,
            "130",
            "--format",
            "json",
        ])))
        .unwrap();
        v.as_object_mut().unwrap().remove("swimbot");
        v.as_object_mut().unwrap().remove("process_peak_rss_bytes");
        v
    };
    let new = helix("--tail-length-mm");
    assert!(new["drag_n_s_per_m"].is_number(), "{new}");
    assert_eq!(helix("--length-mm"), new);
    let dir = tempfile::tempdir().unwrap();
    let o = swimbot_in(
        dir.path(),
        &[
            "sim",
            "--max-time",
            "2",
            "--sample-every",
            "1",
            "--out",
            "old",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("old/sim.csv").is_file());
    for (cmd, old) in [
        ("sim", "--out "),
        ("sim", "--max-time "),
        ("sim", "--sample-every "),
        ("compare", "--report "),
        ("compare", "--effects "),
        ("helix", " --length-mm"),
    ] {
        let help = stdout(&swimbot(&[cmd, "--help"]));
        assert!(!help.contains(old), "{cmd} --help shows {old}");
    }
    // The old `helix --method stokeslets` and the new `--tail-model` must agree.
    assert_input_error(
        &swimbot(&[
            "helix",
            "--wavelength-mm",
            "15.5",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "130",
            "--method",
            "sbt",
            "--tail-model",
            "stokeslets",
        ]),
        &["--tail-model stokeslets", "--method sbt"],
    );
}

#[test]
fn commands_without_rows_refuse_csv_at_parse_time() {
    for cmd in ["effects", "body"] {
        let o = swimbot(&[cmd, "--format", "csv"]);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("possible values: table, json"),
            "{cmd}: {}",
            stderr(&o)
        );
    }
}

/// `swimbot sweep | head` (and any other command whose reader stops early)
/// ends quietly with exit 0, as ripgrep does: no panic, no error message,
/// no death by SIGPIPE (exit 141 in a shell, a failure under pipefail).
/// 10^5 rows are far more than a pipe buffer holds, so the reader closes
/// the pipe while the sweep is still writing.
#[cfg(unix)]
#[test]
fn a_reader_that_stops_early_ends_the_process_quietly() {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let mut child = crate::common::command()
        .args([
            "sweep",
            "--wavelength-mm",
            "5:30:100",
            "--amplitude-mm",
            "1:8:100",
            "--tail-length-mm",
            "20:150:10",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = [0u8; 100];
    child.stdout.take().unwrap().read_exact(&mut head).unwrap();
    // The read end is dropped here, as `head` closes it.
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    // Nothing but progress lines (a sweep past 2 s on a busy machine).
    assert!(
        err.lines().all(|l| l.starts_with("swimbot: sweep: ")),
        "stderr: {err}"
    );
    assert_eq!(out.status.signal(), None, "{:?}", out.status);
    assert_eq!(out.status.code(), Some(0), "{:?}", out.status);
}

/// `diagnose`, `fit` and `audit --format csv`: each command's main table as
/// CSV after the provenance block, with the documented columns and one row
/// per line of the table (checked against the JSON of the same run).
#[test]
fn diagnose_fit_and_audit_print_their_tables_as_csv() {
    let table = |o: &std::process::Output| -> Vec<String> {
        assert!(o.status.success(), "{}", stderr(o));
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(text.starts_with("# swimbot "), "{text}");
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    let json = |args: &[&str]| -> serde_json::Value {
        let o = swimbot(args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let d = table(&swimbot(&["diagnose", "--no-discovery", "--format", "csv"]));
    assert!(
        d[0].starts_with("kind,effect,params,mare,cv_mare,chi2,"),
        "{}",
        d[0]
    );
    let dj = json(&["diagnose", "--no-discovery", "--format", "json"]);
    let ranked = dj["ranking"].as_array().unwrap().len() + dj["pairs"].as_array().unwrap().len();
    assert_eq!(d.len() - 1, ranked);
    let fit = ["fit", "--effect", "body-correction"];
    let f = table(&swimbot(&[fit[0], fit[1], fit[2], "--format", "csv"]));
    assert_eq!(f[0], "effect,name,unit,value,ci95,at_bound");
    assert_eq!(f.len() - 1, 2, "translation and rotation: {f:?}");
    let fj = json(&[fit[0], fit[1], fit[2], "--format", "json"]);
    let first = fj["fit"]["estimates"][0]["value"].as_f64().unwrap();
    let csv_first: f64 = f[1].split(',').nth(3).unwrap().parse().unwrap();
    assert_eq!(csv_first, first, "full precision in the CSV");
    let a = table(&swimbot(&["audit", "--format", "csv"]));
    assert_eq!(a[0], "case,kind,detail,severity");
    let aj = json(&["audit", "--format", "json"]);
    assert_eq!(a.len() - 1, aj["flags"].as_array().unwrap().len());
    assert!(a.len() > 1, "the paper's data carry audit flags");
    // compare's columns keep the README's names after the provenance block
    let c = table(&swimbot(&["compare", "--no-report", "--format", "csv"]));
    assert!(c[0].contains(",omega_body_counter_pred_hz,"), "{}", c[0]);
}

/// One case allows no diagnosis (cross-validation has nothing to predict
/// from): an input error that says what one case allows, not a NaN (exit 1).
#[test]
fn diagnose_on_one_case_says_what_one_case_allows() {
    let dir = tempfile::tempdir().unwrap();
    let paper =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.toml")).unwrap();
    let second = paper.match_indices("[[case]]").nth(1).unwrap().0;
    let one = dir.path().join("one.toml");
    std::fs::write(&one, &paper[..second]).unwrap();
    let o = swimbot(&["diagnose", "--data", one.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("at least 2 cases") && stderr(&o).contains("swimbot fit"),
        "{}",
        stderr(&o)
    );
}
