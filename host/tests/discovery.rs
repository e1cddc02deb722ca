//! Discovery beyond the catalogue, proven on hidden truths that are NOT in
//! the catalogue (host/tests/fixtures/truths.rs): each acts at a different
//! place and scales with a different feature, in a law that is not one of
//! the search's forms. Synthetic data: `synth::rich_design` (channel, rate,
//! tail length, amplitude and wavelength vary), 2 % noise, five trials.
//!
//! Accepted equivalent features, and why: the gap features
//! `wire_over_gap`, `tail_clearance`, `tail_gap_ratio` all measure how
//! close the helix comes to the wall (at the fixed wire diameter of these
//! designs they order the cases almost identically); `body_ratio`,
//! `body_gap_ratio`, `body_over_gap` are exact monotone functions of
//! `D_b/D_ch` (the body diameter is fixed), so no fit can tell them apart.

use crate::fixtures;

use fixtures::truths;
use swimbot::data::Dataset;
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, Diagnosis, VerdictKind};
use swimbot::workbench::synth::{generate, rich_design, SynthSettings};

const SEED: u64 = 23;

fn data(truth: &Model, seed: u64) -> Dataset {
    generate(
        truth,
        &rich_design(&swimbot::data::paper()),
        SynthSettings {
            seed,
            ..Default::default()
        },
    )
    .unwrap()
}

fn run(truth: Model) -> (Diagnosis, Dataset) {
    let data = data(&truth, SEED);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    (d, data)
}

fn assert_located(d: &Diagnosis, data: &Dataset, place: &str, features: &[&str]) {
    let v = &d.verdict;
    let l = v
        .located
        .first()
        .unwrap_or_else(|| panic!("nothing located: {}", v.note));
    assert_eq!(l.place, place, "{}", v.note);
    match l.feature {
        None => assert!(
            features.is_empty(),
            "constant found, expected {features:?}: {}",
            v.note
        ),
        Some(f) => assert!(
            features.contains(&f),
            "feature {f}, expected {features:?}: {}",
            v.note
        ),
    }
    // At the noise floor, or an approximate law whose out-of-sample error
    // is at the noise level (the truths are not in the search's forms).
    let noise_mare =
        2.0 * swimbot::workbench::design::median_rel_se(data) * (2.0 / std::f64::consts::PI).sqrt();
    assert!(l.at_noise_floor || l.cv_mare <= noise_mare, "{}", v.note);
    assert!(l.cv_mare < d.baseline.mare, "{}", v.note);
    let f = l.explained_fraction.expect("an excess to explain");
    assert!(f > 0.9, "explained fraction {f}: {}", v.note);
}

fn base_with(e: &'static dyn swimbot::effects::Effect) -> Model {
    Model::base().with_effect(truths::instance(e))
}

#[test]
fn locates_wall_proximity_on_the_tail_normal_resistance() {
    let (d, data) = run(base_with(&truths::WALL));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(
        &d,
        &data,
        "tail.c_n",
        &["wire_over_gap", "tail_clearance", "tail_gap_ratio"],
    );
    assert!(d.verdict.located[0].interpretation.contains("wall"));
}

#[test]
fn locates_a_shear_thinning_oil_on_the_tail_viscosity() {
    let (d, data) = run(base_with(&truths::SHEAR));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(&d, &data, "tail.viscosity", &["shear_rate"]);
    assert!(d.verdict.located[0]
        .interpretation
        .contains("shear-thinning"));
}

#[test]
fn locates_a_drive_turning_slower_than_recorded() {
    let (d, data) = run(base_with(&truths::SLIP));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(&d, &data, "drive.rate", &[]);
    let k = &d.verdict.located[0].params[0];
    let ci = k.ci95.expect("identifiable");
    assert!(
        (k.value - 0.85).abs() < 3.0 * ci.max(1e-3),
        "{} ± {ci}",
        k.value
    );
}

#[test]
fn locates_a_quartic_body_confinement_on_the_body_drag() {
    let (d, data) = run(base_with(&truths::BODY));
    // backflow + body-correction is a two-parameter confinement law on the
    // body too: when it fits as well, the honest verdict is
    // indistinguishable, with the located law and a separating case.
    assert!(
        matches!(
            d.verdict.kind,
            VerdictKind::Located | VerdictKind::Indistinguishable
        ),
        "{}",
        d.verdict.note
    );
    if d.verdict.kind == VerdictKind::Indistinguishable {
        assert!(d
            .verdict
            .suggestion
            .as_ref()
            .is_some_and(|g| g.in_sigma >= 3.0));
    }
    assert_located(
        &d,
        &data,
        "body.D_x",
        &["body_ratio", "body_gap_ratio", "body_over_gap"],
    );
}

#[test]
fn names_the_catalogue_effect_and_locates_the_remainder() {
    let truth = Model::base()
        .with_effect(parse_effect_spec("body-confinement").unwrap())
        .with_effect(truths::instance(&truths::SLIP));
    let (d, data) = run(truth);
    assert_eq!(
        d.verdict.kind,
        VerdictKind::Identified,
        "{}",
        d.verdict.note
    );
    assert_eq!(
        d.verdict.effect.as_deref(),
        Some("body-confinement"),
        "{}",
        d.verdict.note
    );
    assert!(d.verdict.effect_explained_fraction.is_some_and(|f| f > 0.3));
    assert_located(&d, &data, "drive.rate", &[]);
}

#[test]
fn the_null_control_needs_nothing_and_locates_nothing() {
    let (d, _data) = run(Model::base());
    assert_eq!(
        d.verdict.kind,
        VerdictKind::NoneNeeded,
        "{}",
        d.verdict.note
    );
    assert!(d.verdict.located.is_empty());
    assert_eq!(d.verdict.effect, None);
}

#[test]
fn write_effect_gives_a_file_in_the_agreed_format_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("located.toml");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_swimbot"))
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
