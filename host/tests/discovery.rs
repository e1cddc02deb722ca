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

use fixtures::{drawn, truths};
use swimbot::data::Dataset;
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, Diagnosis, Verdict, VerdictKind};
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
    assert!(
        l.score.at_noise_floor || l.score.cv_mare <= noise_mare,
        "{}",
        v.note
    );
    assert!(l.score.cv_mare < d.baseline.mare, "{}", v.note);
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

/// Two out-of-catalogue truths at different places (body drag, tail
/// viscosity): the stagewise search takes several steps, each fitted on top
/// of the ones before it (`on_top_of` grows by one effect per step, MARE
/// falls), and the tail's shear-thinning law is among them at its place and
/// feature. (The body law is often taken first by the catalogue's
/// body-correction and its remainder misplaced: docs/discovery.md reports
/// the counts; this test asserts what holds.)
#[test]
fn two_missing_effects_at_once_are_found_in_steps_each_on_top_of_the_last() {
    let truth = base_with(&truths::BODY).with_effect(truths::instance(&truths::SHEAR));
    let (d, _data) = run(truth);
    let v = &d.verdict;
    assert!(v.steps.len() >= 2, "{}", v.note);
    for w in v.steps.windows(2) {
        assert_eq!(w[1].on_top_of.len(), w[0].on_top_of.len() + 1, "{}", v.note);
        assert!(w[1].mare < w[0].mare, "{}", v.note);
    }
    assert!(
        v.located
            .iter()
            .any(|l| l.place == "tail.viscosity" && l.feature == Some("shear_rate")),
        "{}",
        v.note
    );
    // Each located law's own `on_top_of` is its step's.
    let laws: Vec<_> = v.steps.iter().filter(|s| s.kind == "located").collect();
    for (l, s) in v.located.iter().zip(laws) {
        assert_eq!(l.on_top_of, s.on_top_of);
    }
}

/// No located list names the same place, feature and form twice.
fn assert_no_repeats(v: &swimbot::workbench::diagnose::Verdict) {
    for (i, a) in v.located.iter().enumerate() {
        for b in &v.located[i + 1..] {
            let same = a.place == b.place && a.feature == b.feature && a.form == b.form;
            assert!(!same, "{} listed twice: {}", a.describe(), v.note);
        }
    }
}

fn drawn_data(truth: &Model, design: &Dataset, seed: u64) -> Dataset {
    let settings = SynthSettings {
        seed,
        ..Default::default()
    };
    generate(truth, design, settings).unwrap()
}

const BODY_FEATURES: &[&str] = &["body_ratio", "body_gap_ratio", "body_over_gap"];

/// Whether the verdict locates a law at `place` in one of `feats`.
fn placed(v: &Verdict, place: &str, feats: &[&str]) -> bool {
    v.located
        .iter()
        .any(|l| l.place == place && l.feature.is_some_and(|f| feats.contains(&f)))
}

/// `diagnose` from the base model on the drawn two-effect truth (body law
/// and shear-thinning oil, tests/fixtures/drawn.rs) of `seed`.
fn diagnose_drawn_pair(seed: u64) -> Diagnosis {
    let truth = Model::base()
        .with_effect(drawn::body_law(seed))
        .with_effect(drawn::shear_law(seed));
    let data = drawn_data(&truth, &drawn::design(&swimbot::data::paper(), seed), seed);
    diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap()
}

/// Two out-of-catalogue effects at once, both drawn (constants and design:
/// tests/fixtures/drawn.rs, seed 31). The catalogue's body-correction
/// takes most of the body law first; backfitting re-locates each step on
/// top of the others, so both laws end up at their places and the set
/// reaches the floor without it.
#[test]
fn two_drawn_effects_at_once_are_both_placed_after_backfitting() {
    let seed = 31;
    let d = diagnose_drawn_pair(seed);
    let v = &d.verdict;
    assert!(placed(v, "body.D_x", BODY_FEATURES), "{}", v.note);
    assert!(placed(v, "tail.viscosity", &["shear_rate"]), "{}", v.note);
    assert!(v.steps.iter().all(|s| s.kind == "located"), "{}", v.note);
    assert!(v.steps.last().unwrap().at_noise_floor, "{}", v.note);
    assert_eq!(v.kind, VerdictKind::Located, "{}", v.note);
    assert_no_repeats(v);
}

/// Backfitting above the floor (issue 23 item 1), on a synth seed (139)
/// outside the recovery study's: the catalogue's body-correction takes most
/// of the fixed body law first and the rest lands on `tail.c_n` in a body
/// gap; no one-for-one exchange reaches the floor, so backfitting used to
/// keep that. A clearly better set above the floor is now taken, and the
/// body law is re-located on the body.
#[test]
fn backfitting_above_the_floor_moves_the_body_law_back_to_the_body() {
    let truth = base_with(&truths::BODY).with_effect(truths::instance(&truths::SHEAR));
    let data = data(&truth, 139);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert!(placed(v, "body.D_x", BODY_FEATURES), "{}", v.note);
    assert!(placed(v, "tail.viscosity", &["shear_rate"]), "{}", v.note);
    assert!(
        v.located.iter().all(|l| l.place != "tail.c_n"),
        "{}",
        v.note
    );
    assert_no_repeats(v);
}

/// Backfitting tries the best law at every other place (issue 23): on seed
/// 203 of the drawn two-effect truth the path took the catalogue's
/// backflow and the shear-rate law (identified, at the floor), and the
/// single best proposal on top of the shear-rate law was never at the
/// body. Refitted jointly, the body law at `body.D_x` beats backflow by
/// more than the clear margin at the floor, and is exchanged for it.
#[test]
fn backfitting_tries_the_best_law_at_each_other_place() {
    let seed = 203;
    let d = diagnose_drawn_pair(seed);
    let v = &d.verdict;
    assert!(placed(v, "body.D_x", BODY_FEATURES), "{}", v.note);
    assert!(placed(v, "tail.viscosity", &["shear_rate"]), "{}", v.note);
    assert!(v.steps.iter().all(|s| s.kind == "located"), "{}", v.note);
    assert!(v.steps.last().unwrap().at_noise_floor, "{}", v.note);
    assert_eq!(v.kind, VerdictKind::Located, "{}", v.note);
    assert_no_repeats(v);
}

/// A null never gains a step: base-only data on twenty seeds of the
/// paper's design and four of the rich design.
#[test]
fn a_null_dataset_gains_no_step_on_many_seeds() {
    let paper = swimbot::data::paper();
    let rich = rich_design(&paper);
    let designs = (300..320)
        .map(|s| (s, &paper))
        .chain((320..324).map(|s| (s, &rich)));
    for (seed, design) in designs {
        let settings = SynthSettings {
            seed,
            ..Default::default()
        };
        let data = generate(&Model::base(), design, settings).unwrap();
        let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
        let v = &d.verdict;
        assert!(v.steps.is_empty(), "seed {seed}: {}", v.note);
        assert!(v.located.is_empty(), "seed {seed}: {}", v.note);
    }
}

/// One bad run (a case's U moved by 8 standard errors) on null data of the
/// paper's design: the case is named, and no effect is needed. (On the
/// paper's 12 quantities such a run lifts the chi-square above the floor;
/// on the 84 of the rich design it usually does not, and then the data
/// need nothing anyway: docs/discovery.md.)
#[test]
fn one_bad_run_is_named_and_needs_no_effect() {
    let settings = SynthSettings {
        seed: SEED,
        ..Default::default()
    };
    let mut data = generate(&Model::base(), &swimbot::data::paper(), settings).unwrap();
    let id = truths::spoil_one(&mut data, 2, 8.0);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert_eq!(v.kind, VerdictKind::NoneNeeded, "{}", v.note);
    assert_eq!(
        d.lone_case.as_ref().map(|l| l.case.as_str()),
        Some(id.as_str()),
        "{}",
        v.note
    );
    assert!(
        v.note.contains("one case stands out") && v.note.contains(&id),
        "{}",
        v.note
    );
    assert!(v.located.is_empty() && v.steps.is_empty());
}

/// A recorded setup field is a feature when it varies: the oil's
/// viscosity on a design with three oils; a field that does not vary (the
/// channel) is left out, and so is a field that orders the cases exactly
/// as a feature already in the library.
#[test]
fn varying_setup_fields_are_features_and_constant_ones_are_not() {
    let oils = truths::oil_design(&swimbot::data::paper());
    let ids: Vec<&str> = swimbot::workbench::discovery::search::usable_features(&oils)
        .iter()
        .map(|(q, _)| q.id)
        .collect();
    assert!(ids.contains(&"viscosity_pa_s"), "{ids:?}");
    assert!(ids.contains(&"reynolds"), "{ids:?}");
    assert!(!ids.contains(&"channel_diameter_mm"), "{ids:?}");
    assert!(!ids.contains(&"channel_length_ratio"), "{ids:?}");
    // `frequency` is in the derived library: its field twin is left out.
    assert!(
        ids.contains(&"frequency") && !ids.contains(&"frequency_hz"),
        "{ids:?}"
    );
}

fn swimbot_cmd(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_swimbot"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
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

const WALL_FEATURES: &[&str] = &["wire_over_gap", "tail_clearance", "tail_gap_ratio"];

/// Issue 23.5, on a fresh draw (seed 41, tests/fixtures/drawn.rs): a tail
/// drag rising near the wall is located on the tail with a wall feature
/// (on `tail.drag`, or on `tail.thrust` falling: in the axial model both
/// change the ratio of thrust to drag, and the law says so in its
/// `equivalent`), never on `drive.rate`.
#[test]
fn a_tail_drag_rising_near_the_wall_is_placed_on_the_tail() {
    let seed = 41;
    let truth = Model::base().with_effect(drawn::tail_wall_drag(seed));
    let data = drawn_data(&truth, &drawn::design(&swimbot::data::paper(), seed), seed);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    let l = v.located.first().unwrap_or_else(|| panic!("{}", v.note));
    assert!(
        ["tail.drag", "tail.thrust"].contains(&l.place),
        "{}",
        v.note
    );
    let stated = l.place == "tail.drag"
        || l.equivalent
            .iter()
            .any(|e| e.place == "tail.drag" && e.relation == "opposite");
    assert!(stated, "{}: {:?}", l.describe(), l.equivalent);
    assert!(
        l.feature.is_some_and(|f| WALL_FEATURES.contains(&f)),
        "{}",
        v.note
    );
    assert!(
        v.located.iter().all(|l| l.place != "drive.rate"),
        "{}",
        v.note
    );
    assert_no_repeats(v);
}

/// Issue 23 item 4: a catalogue candidate and a located law carry one
/// score type, flattened, so the JSON keeps the six fields at the top of
/// each entry (no nested `score`) and they read alike in both lists.
#[test]
fn candidates_and_located_laws_carry_the_same_score_fields_in_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = swimbot_cmd(&["diagnose", "--format", "json"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let ranking = json["ranking"].as_array().unwrap();
    let located = json["discovery"]["located"].as_array().unwrap();
    assert!(!ranking.is_empty() && !located.is_empty());
    for entry in ranking.iter().chain(located) {
        let obj = entry.as_object().unwrap();
        assert!(!obj.contains_key("score"), "{entry}");
        for key in ["mare", "cv_mare", "chi2"] {
            assert!(
                obj[key].as_f64().is_some_and(f64::is_finite),
                "{key}: {entry}"
            );
        }
        for key in ["chi2_reduced", "aicc"] {
            assert!(obj[key].is_number() || obj[key].is_null(), "{key}: {entry}");
        }
        assert!(obj["at_noise_floor"].is_boolean(), "{entry}");
    }
    // Item 2: every located law states its equivalent readings.
    for l in located {
        let eq = l["equivalent"].as_array().unwrap();
        if l["place"] == "tail.torque" {
            assert_eq!(eq[0]["place"], "body.E_x", "{l}");
            assert_eq!(eq[0]["relation"], "reciprocal", "{l}");
        }
    }
    // The paper's data are above the floor for the base model: a located
    // law's chi-square is below the baseline's, as its score says.
    let base_chi2 = json["baseline"]["chi2"].as_f64().unwrap();
    assert!(located[0]["chi2"].as_f64().unwrap() < base_chi2);
}
