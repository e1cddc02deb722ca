//! The dataset format: the built-in data round-trips, and every kind of bad
//! input is an error that names the file, the case and the field.

use swimbot::data::{self, parse_str, to_toml};

#[test]
fn built_in_paper_data_has_the_papers_tables() {
    let d = data::paper();
    assert_eq!(d.cases.len(), 6);
    let t1 = &d.cases[0];
    assert_eq!(
        (
            t1.wavelength_mm,
            t1.amplitude_mm,
            t1.tail_length_mm,
            t1.frequency_hz
        ),
        (15.5, 2.5, 130.0, 1.05)
    );
    assert_eq!(t1.u_mm_s.unwrap().mean, 0.586);
    assert_eq!(d.cases[5].omega_body_hz.unwrap().ci_half_width, 0.0001);
    assert!(d
        .cases
        .iter()
        .all(|c| c.viscosity_pa_s == 3.5 && c.channel_closed));
}

#[test]
fn built_in_data_round_trips_through_the_writer() {
    let d = data::paper();
    let again = parse_str(&to_toml(&d), "round-trip").unwrap();
    assert_eq!(d, again);
}

#[test]
fn raw_trials_become_a_mean_and_student_t_interval() {
    let text = r#"
[setup]
channel_diameter_mm = 35.0
channel_length_mm = 350.0
viscosity_pa_s = 3.5
density_kg_m3 = 985.0
body_diameter_mm = 20.0
body_length_mm = 50.0
wire_diameter_mm = 1.0
[[case]]
id = "a"
wavelength_mm = 10.0
amplitude_mm = 2.5
tail_length_mm = 88.0
frequency_hz = 1.5
u_trials_mm_s = [0.21, 0.22, 0.23]
"#;
    let d = parse_str(text, "t.toml").unwrap();
    let u = d.cases[0].u_mm_s.unwrap();
    assert!((u.mean - 0.22).abs() < 1e-12);
    // t(0.975, 2) = 4.3027, s = 0.01, se = 0.01/sqrt(3)
    assert!((u.ci_half_width - 4.302653 * 0.01 / 3f64.sqrt()).abs() < 1e-6);
    assert_eq!(u.trials, 3);
}

/// `(text to replace, replacement, what the error must name)`.
const BAD_EDITS: &[(&str, &str, &[&str])] = &[
    (
        "wavelength_mm = 10.0",
        "wavelenght_mm = 10.0",
        &["bad.toml", "wavelenght_mm"],
    ),
    (
        "wavelength_mm = 10.0\n",
        "",
        &["bad.toml", "tail-2", "wavelength_mm", "missing"],
    ),
    (
        "tail_length_mm = 88.0",
        "tail_length_mm = -88.0",
        &["tail-2", "tail_length_mm", "positive"],
    ),
    (
        "frequency_hz = 1.50",
        "frequency_hz = nan",
        &["tail-2", "frequency_hz", "finite"],
    ),
    (
        "wavelength_mm = 10.0",
        "wavelength_mm = 0.9",
        &["tail-2", "wavelength_mm", "wire diameter"],
    ),
    (
        "amplitude_mm = 7.5\ntail_length_mm = 42.0",
        "amplitude_mm = 17.5\ntail_length_mm = 42.0",
        &["tail-6", "amplitude_mm", "channel"],
    ),
    (
        "u_ci_mm_s = 0.0051\n",
        "",
        &["tail-2", "u_ci_mm_s", "missing"],
    ),
    (
        "id = \"tail-3\"",
        "id = \"tail-2\"",
        &["tail-2", "duplicate"],
    ),
    ("trials = 5\n", "", &["tail-1", "trials"]),
    (
        "[[case]]",
        "[[case]\n",
        &["bad.toml", "not a valid dataset"],
    ),
];

#[test]
fn bad_input_names_file_case_and_field() {
    for (from, to, needles) in BAD_EDITS {
        let text = data::PAPER_TOML.replacen(from, to, 1);
        assert_ne!(text, data::PAPER_TOML, "edit `{from}` did not apply");
        let e = parse_str(&text, "bad.toml").unwrap_err().to_string();
        for n in *needles {
            assert!(e.contains(n), "`{n}` missing from: {e}");
        }
    }
}

#[test]
fn a_missing_file_is_a_clear_error() {
    let e = data::load_file(std::path::Path::new("/nonexistent/data.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/nonexistent/data.toml") && e.contains("cannot read"),
        "{e}"
    );
}
