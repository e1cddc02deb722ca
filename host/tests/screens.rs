//! The concluding commands' screens through the real binary: lines within
//! 100 columns off a terminal (each item's length: `cli/screen/render.rs`), the paper's
//! symbols, and the headline's numbers the same in the terminal and in the
//! JSON (`cli/screen`).

use crate::common::{stderr, stdout, swimbot};
use swimbot::cli::screen::rounding::value_pm;

fn ok(args: &[&str]) -> String {
    let o = swimbot(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

fn check_layout(text: &str) {
    for line in text.lines() {
        let w = textwrap::core::display_width(line);
        assert!(w <= 100, "{w} columns: {line:?}");
    }
}

#[test]
fn the_paper_s_diagnosis_fits_a_screen_and_says_the_json_s_numbers() {
    let text = ok(&["diagnose"]);
    check_layout(&text);
    assert!(text.lines().count() <= 25, "{text}");
    assert!(text.starts_with("verdict: "), "{text}");
    assert!(!text.contains("psi") && text.contains('ψ'), "{text}");
    assert!(!text.contains("unexplained: unexplained"), "{text}");
    let v: serde_json::Value =
        serde_json::from_str(&ok(&["diagnose", "--format", "json"])).unwrap();
    let h = &v["headline"];
    assert_eq!(h["kind"], v["verdict"]["kind"]);
    assert!(text.starts_with(&format!("verdict: {}", h["kind"].as_str().unwrap())));
    // The MARE chain: the baseline's, then each step's, as the verdict has them.
    let mare: Vec<f64> = h["mare"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_f64().unwrap())
        .collect();
    assert_eq!(mare[0], v["baseline"]["mare"].as_f64().unwrap());
    let steps = v["verdict"]["steps"].as_array().unwrap();
    assert_eq!(mare.len(), steps.len() + 1);
    for (m, s) in mare[1..].iter().zip(steps) {
        assert_eq!(*m, s["mare"].as_f64().unwrap());
    }
    let chain: Vec<String> = mare
        .iter()
        .map(|m| format!("{:.2}\u{a0}%", 100.0 * m))
        .collect();
    assert!(
        text.contains(&format!("MARE {}", chain.join(" -> "))),
        "{chain:?}\n{text}"
    );
    // Each parameter as JCGM 100 rounds it from the JSON's numbers.
    let mut seen = 0;
    for step in h["steps"].as_array().unwrap() {
        for p in step["params"].as_array().unwrap() {
            let printed = value_pm(
                p["value"].as_f64().unwrap(),
                p["standard_uncertainty"].as_f64(),
            );
            let line = format!("{} = {printed}", p["name"].as_str().unwrap());
            assert!(text.contains(&line), "{line:?} not in\n{text}");
            seen += 1;
        }
    }
    assert!(seen > 0, "no parameter in the headline: {h}");
    // Full precision in the JSON, and the interval around the value.
    let p = &h["steps"][1]["params"][1];
    let (lo, val, hi) = (
        p["ci95_low"].as_f64().unwrap(),
        p["value"].as_f64().unwrap(),
        p["ci95_high"].as_f64().unwrap(),
    );
    assert!(lo < val && val < hi, "{p}");
}

#[test]
fn verbose_keeps_every_table_and_ends_with_the_same_answer() {
    let short = ok(&["diagnose"]);
    let long = ok(&["diagnose", "--verbose"]);
    assert!(long.contains("each candidate effect added alone"), "{long}");
    assert!(
        long.ends_with(&short),
        "the answer closes the verbose output"
    );
    assert!(long.lines().count() > short.lines().count() + 40);
}

#[test]
fn a_planted_set_s_screen_names_the_pair_and_a_command_that_runs() {
    let dir = tempfile::tempdir().unwrap();
    let planted = dir.path().join("planted.toml");
    ok(&[
        "synth",
        "--data",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/twelve-tails.csv"
        ),
        "--nominal-inputs",
        "--seed",
        "1",
        "--truth",
        "base + backflow + body-correction:translation=16,rotation=1.4 + buoyancy:net_force_mn=0.3",
        "-o",
        planted.to_str().unwrap(),
    ]);
    let text = ok(&["diagnose", "--data", planted.to_str().unwrap()]);
    check_layout(&text);
    let next = text
        .lines()
        .find_map(|l| l.strip_prefix("next: swimbot "))
        .unwrap_or_else(|| panic!("no next command:\n{text}"));
    let mut args: Vec<&str> = next.split_whitespace().collect();
    args.extend(["--data", planted.to_str().unwrap()]);
    if args[0] == "compare" {
        args.push("--no-report");
    }
    let o = swimbot(&args);
    assert!(o.status.success(), "`swimbot {next}` fails: {}", stderr(&o));
}

#[test]
fn the_study_commands_print_within_the_width_and_the_note_behind_verbose() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let paper = concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv");
    let run = |args: &[&str]| {
        let o = crate::common::run_in(d, args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        stdout(&o)
    };
    let init = run(&["init", "--data", paper]);
    check_layout(&init);
    assert!(init.contains("first diagnosis: unexplained\n"), "{init}");
    assert!(
        !init.contains("2 steps lower") && !init.contains("reduced chi-square"),
        "{init}"
    );
    let add = run(&["add", "body-correction"]);
    check_layout(&add);
    let steps = run(&["steps"]);
    check_layout(&steps);
    let verbose = run(&["steps", "--verbose"]);
    check_layout(&verbose);
    let study: toml::Value =
        toml::from_str(&std::fs::read_to_string(d.join("swimbot-study.toml")).unwrap()).unwrap();
    let note = study["first_diagnosis"]["note"].as_str().unwrap();
    let first_words: Vec<&str> = note.split_whitespace().take(4).collect();
    assert!(
        verbose.contains(&first_words.join(" ")) && !steps.contains(&first_words.join(" ")),
        "{note}\n{verbose}"
    );
}
