//! CSV datasets: the same [`Dataset`] as the TOML they convert to and from
//! (the paper's data, a per-trial file, and random datasets), raw trials
//! aggregated as the TOML's are, and bad cells named by file, row and column.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use swimbot::data::{self, convert_file, load_file, Dataset, FileFormat};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The shipped example, read relative to the crate.
fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
}

/// TOML -> CSV -> TOML: the same dataset at each step, and the CSV written
/// again from the TOML is the same text.
fn round_trip(toml_text: &str) -> (Dataset, String) {
    let dir = tempfile::tempdir().unwrap();
    let t = write(dir.path(), "d.toml", toml_text);
    let d = load_file(&t).unwrap();
    let csv = convert_file(&t, FileFormat::Csv).unwrap();
    let c = write(dir.path(), "d.csv", &csv);
    assert_eq!(load_file(&c).unwrap(), d, "CSV:\n{csv}");
    let toml2 = convert_file(&c, FileFormat::Toml).unwrap();
    let t2 = write(dir.path(), "d2.toml", &toml2);
    assert_eq!(load_file(&t2).unwrap(), d, "TOML:\n{toml2}");
    assert_eq!(convert_file(&t2, FileFormat::Csv).unwrap(), csv);
    (d, csv)
}

#[test]
fn the_paper_data_round_trips_through_csv() {
    let (d, csv) = round_trip(data::PAPER_TOML);
    assert_eq!(d, data::paper());
    // The setup stays a header block; the cases are six rows.
    assert!(csv.contains("# viscosity_pa_s = 3.5\n"), "{csv}");
    assert!(
        csv.contains("# uncertainty.frequency_hz = \"2%\"\n"),
        "{csv}"
    );
    let rows = csv.lines().filter(|l| !l.starts_with('#')).count();
    assert_eq!(rows, 1 + 6, "{csv}");
}

#[test]
fn the_shipped_csv_examples_equal_their_toml() {
    let paper = load_file(&example("paper.csv")).unwrap();
    assert_eq!(paper, data::paper());
    let trials = load_file(&example("trials-example.csv")).unwrap();
    assert_eq!(trials.cases.len(), 2);
    let a = &trials.cases[0];
    // Five rows of one id: mean and Student-t half-width of the five.
    let u = [0.219, 0.224, 0.221, 0.218, 0.222];
    let (mean, half) = swimbot::stats::mean_and_ci(&u, 0.95);
    let m = a.u_mm_s.unwrap();
    assert_eq!((m.mean, m.ci_half_width, m.trials), (mean, half, 5));
}

#[test]
fn rows_per_trial_give_the_raw_trials_toml_dataset() {
    let setup = "# channel_diameter_mm = 35.0\n# channel_length_mm = 350.0\n# viscosity_pa_s = 3.5\n# density_kg_m3 = 985.0\n# body_diameter_mm = 20.0\n# body_length_mm = 50.0\n# wire_diameter_mm = 1.0\n";
    let csv = format!(
        "{setup}id,wavelength_mm,amplitude_mm,tail_length_mm,frequency_hz,u_mm_s,omega_body_hz\n\
         a,10,2.5,88,1.5,0.21,0.118\na,10,2.5,88,1.5,0.22,0.119\na,10,2.5,88,1.5,0.23,\n"
    );
    let toml = "[setup]\nchannel_diameter_mm = 35.0\nchannel_length_mm = 350.0\nviscosity_pa_s = 3.5\ndensity_kg_m3 = 985.0\nbody_diameter_mm = 20.0\nbody_length_mm = 50.0\nwire_diameter_mm = 1.0\n[[case]]\nid = \"a\"\nwavelength_mm = 10.0\namplitude_mm = 2.5\ntail_length_mm = 88.0\nfrequency_hz = 1.5\nu_trials_mm_s = [0.21, 0.22, 0.23]\nomega_body_trials_hz = [0.118, 0.119]\n";
    let dir = tempfile::tempdir().unwrap();
    let from_csv = load_file(&write(dir.path(), "t.csv", &csv)).unwrap();
    let from_toml = load_file(&write(dir.path(), "t.toml", toml)).unwrap();
    assert_eq!(from_csv.cases, from_toml.cases);
    assert_eq!(from_csv.cases[0].omega_body_hz.unwrap().trials, 2);
}

#[test]
fn a_setup_file_beside_the_csv_gives_the_setup() {
    let dir = tempfile::tempdir().unwrap();
    let setup: String = data::PAPER_TOML
        .split("[[case]]")
        .next()
        .unwrap()
        .to_string();
    write(dir.path(), "rig.toml", &setup);
    let full = convert_file(&example("paper.csv"), FileFormat::Csv).unwrap();
    let rows: String = full
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let csv = format!("# setup_file = \"rig.toml\"\n{rows}");
    let d = load_file(&write(dir.path(), "runs.csv", &csv)).unwrap();
    assert_eq!(d.cases, data::paper().cases);
    assert_eq!(d.name, data::paper().name);
}

/// `(edit of the paper's CSV, what the error must name)`.
fn bad_csv_cases(paper: &str) -> Vec<(String, Vec<String>)> {
    let header_row = paper.lines().position(|l| !l.starts_with('#')).unwrap() + 1;
    let row3: &str = &format!("row {}", header_row + 3);
    let cases: Vec<(String, Vec<&str>)> = vec![
        (
            paper.replacen("tail-3,16", "tail-3,ten", 1),
            vec!["bad.csv", row3, "wavelength_mm", "`ten` is not a number"],
        ),
        (
            paper.replacen(",wavelength_mm,", ",wavelenght_mm,", 1),
            vec![
                "bad.csv",
                "header row",
                "wavelenght_mm",
                "not a dataset field",
            ],
        ),
        (
            paper.replacen("tail-3,16,", "tail-3,16,,", 1),
            vec!["bad.csv", row3, "cells where the header row has"],
        ),
        (
            paper.replacen("# viscosity_pa_s = 3.5\n", "", 1),
            vec!["bad.csv", "tail-1", "viscosity_pa_s", "give it a column"],
        ),
        (
            paper.replacen("# viscosity_pa_s = 3.5", "# viscosity_pa_s = ", 1),
            vec!["bad.csv", "line", "`viscosity_pa_s`", "not a TOML value"],
        ),
        (
            paper.replacen("tail-3,16,", "tail-3,-16,", 1),
            vec!["bad.csv", row3, "tail-3", "wavelength_mm", "positive"],
        ),
        (
            // tail-4 becomes a second trial of tail-3, but rows of means.
            paper.replacen("tail-4,", "tail-3,", 1),
            vec![
                "bad.csv",
                "column `u_ci_mm_s`",
                "tail-3",
                "one row per trial",
            ],
        ),
    ];
    cases
        .into_iter()
        .map(|(t, n)| (t, n.into_iter().map(str::to_string).collect()))
        .collect()
}

#[test]
fn bad_cells_name_file_row_and_column() {
    let paper = std::fs::read_to_string(example("paper.csv")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (text, needles) in bad_csv_cases(&paper) {
        assert_ne!(text, paper, "an edit did not apply: {needles:?}");
        let e = load_file(&write(dir.path(), "bad.csv", &text))
            .unwrap_err()
            .to_string();
        for n in needles {
            assert!(e.contains(&n), "`{n}` missing from: {e}");
        }
    }
}

#[test]
fn trial_rows_of_one_case_must_agree_but_in_the_measurements() {
    let text = std::fs::read_to_string(example("trials-example.csv")).unwrap();
    let first = text.lines().position(|l| l.starts_with("a,")).unwrap() + 1;
    let bad = text.replacen("a,10,2.5,88,1.5,0.224", "a,10,2.6,88,1.5,0.224", 1);
    assert_ne!(bad, text);
    let dir = tempfile::tempdir().unwrap();
    let e = load_file(&write(dir.path(), "t.csv", &bad))
        .unwrap_err()
        .to_string();
    let want = [
        format!("t.csv: row {}", first + 1),
        "column `amplitude_mm`".into(),
        format!("differs from row {first}"),
    ];
    for n in want {
        assert!(e.contains(&n), "`{n}` missing from: {e}");
    }
}

#[test]
fn a_case_that_mixes_trials_and_a_mean_is_refused_not_changed() {
    let text = data::PAPER_TOML.replacen(
        "u_mm_s = 0.5860\nu_ci_mm_s = 0.0640",
        "u_trials_mm_s = [0.5, 0.6, 0.65]",
        1,
    );
    assert_ne!(text, data::PAPER_TOML);
    let dir = tempfile::tempdir().unwrap();
    let e = convert_file(&write(dir.path(), "m.toml", &text), FileFormat::Csv)
        .unwrap_err()
        .to_string();
    assert!(e.contains("tail-1") && e.contains("no CSV form"), "{e}");
}

/// A random valid dataset as TOML: some keys in `[setup]`, the rest per
/// case; means with intervals or raw trials; absolute and relative
/// uncertainties; ids with quotes and a leading `#`.
fn dataset_toml() -> impl Strategy<Value = String> {
    let case = (
        (5.0..30.0f64, 1.0..6.0f64, 20.0..150.0f64, 0.2..3.0f64),
        prop::option::of((0.1..2.0f64, 0.01..0.2f64)),
        prop::option::of(prop::collection::vec(-0.5..0.5f64, 2..6)),
        // within the 50 %-of-value limit for the smallest amplitude (1 mm)
        prop::option::of(0.0..0.5f64),
        any::<bool>(),
        "[a-zA-Z0-9\"#' -]{0,6}",
    );
    (
        prop::collection::vec(case, 1..5),
        (0.5..1.2f64, 10.0..25.0f64, 1.0..3.0f64, 0.5..50.0f64),
        any::<bool>(),
    )
        .prop_map(|(cases, (wire, body_d, body_ratio, mu), mean_first)| {
            let mut t = format!(
                "name = \"random\"\n[setup]\nchannel_diameter_mm = 36.0\nchannel_length_mm = 350.0\nviscosity_pa_s = {mu:?}\ndensity_kg_m3 = 985.0\nbody_diameter_mm = {body_d:?}\nbody_length_mm = {:?}\ntrials = 4\n[setup.uncertainty]\nviscosity_pa_s = \"3.5%\"\n",
                body_d * body_ratio
            );
            for (i, ((l, a, lt, f), mean, trials, unc, left, id)) in cases.into_iter().enumerate() {
                t += &format!(
                    "[[case]]\nid = {}\nwavelength_mm = {l:?}\namplitude_mm = {a:?}\ntail_length_mm = {lt:?}\nwire_diameter_mm = {wire:?}\nfrequency_hz = {f:?}\n",
                    toml::Value::String(format!("{}{id}-{i}", if mean_first { "#" } else { "c" }))
                );
                if left {
                    t += "handedness = \"left\"\n";
                }
                if let Some((m, ci)) = mean {
                    t += &format!("u_mm_s = {m:?}\nu_ci_mm_s = {ci:?}\n");
                } else if let Some(v) = &trials {
                    t += &format!("omega_body_trials_hz = {v:?}\n");
                }
                if let Some(u) = unc {
                    t += &format!("uncertainty = {{ amplitude_mm = {u:?} }}\n");
                }
            }
            t
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_datasets_convert_losslessly(text in dataset_toml()) {
        round_trip(&text);
    }
}
