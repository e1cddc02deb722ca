//! User effects from files (`--effect-file FILE.toml`): an independent-method
//! check (catalogue effects restated as formulas give the same predictions),
//! every load error through the real binary (exit 2, file, effect, field,
//! line), and a user effect working in compare, synth, fit, diagnose, sweep
//! and the effects listing.

use crate::common;
use common::{stderr, stdout, swimbot};
use std::path::{Path, PathBuf};
use std::process::Output;
use swimbot::effects::Catalogue;
use swimbot::model::Model;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).expect("JSON on stdout")
}

fn with(cat: &Catalogue, model: Model, spec: &str) -> Model {
    model.with_effect(cat.parse_effect_spec(spec).unwrap())
}

fn assert_same_predictions(a: &Model, b: &Model) {
    for case in &swimbot::data::paper().cases {
        let (pa, pb) = (a.predict(case).unwrap(), b.predict(case).unwrap());
        for (x, y) in [(pa.u_mm_s, pb.u_mm_s), (pa.omega_body_hz, pb.omega_body_hz)] {
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
                "{}: {x} vs {y} ({} / {})",
                case.id,
                a.describe(),
                b.describe()
            );
        }
    }
}

#[test]
fn catalogue_effects_restated_as_formulas_predict_the_same() {
    let mut c = Catalogue::builtin();
    c.load_effect_files(
        &[fixture("restated.toml")],
        &swimbot::provenance::Inputs::new(),
    )
    .unwrap();
    for (t, r) in [(16.0, 1.4), (4.5, 3.4), (0.3, 7.0)] {
        let cat = with(
            &c,
            Model::base(),
            &format!("body-correction:translation={t},rotation={r}"),
        );
        let user = with(
            &c,
            Model::base(),
            &format!("body-factors:translation={t},rotation={r}"),
        );
        assert_same_predictions(&cat, &user);
    }
    for gamma in [0.0, 1.0, 3.7, 20.0] {
        let cat = with(
            &c,
            Model::base(),
            &format!("tail-confinement:gamma={gamma}"),
        );
        let user = with(&c, Model::base(), &format!("wall-log:gamma={gamma}"));
        assert_same_predictions(&cat, &user);
    }
    // Combined with other effects and another coefficient set, still equal.
    let paper = swimbot::model::preset("paper-lighthill").unwrap();
    let cat = with(&c, paper.clone(), "tail-confinement:gamma=2");
    let user = with(&c, paper, "wall-log:gamma=2");
    assert_same_predictions(&cat, &user);
}

/// Write `text` as `name` in `dir` and run `effects --effects` on it.
fn load_error(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let o = swimbot(&["effects", "--effect-file", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(name), "file missing: {err}");
    err
}

const HEAD: &str = "[[effect]]\nname = \"my-effect\"\nstatement = \"s\"\nreference = \"r\"\n";
const PARAM_K: &str =
    "\n[[effect.param]]\nname = \"k\"\nunit = \"1\"\ndefault = 0.0\nmin = -1.0\nmax = 1.0\n";

#[test]
fn every_load_error_names_file_effect_field_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let places = |f: &str| format!("\n[effect.places]\n{f}\n");
    // (file, text, needles: effect, field, line, what is allowed)
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "unknown_ident.toml",
            format!(
                "{HEAD}{PARAM_K}{}",
                places("\"tail.c_n\" = \"1 + k * shear_rat\"")
            ),
            vec![
                "my-effect",
                "places.\"tail.c_n\"",
                "line 14",
                "column 23",
                "formula column 9",
                "`shear_rate`",
            ],
        ),
        (
            "unknown_place.toml",
            format!("{HEAD}{PARAM_K}{}", places("\"tail.cn\" = \"1 + k\"")),
            vec![
                "my-effect",
                "field `places`",
                "line 14",
                "`tail.c_n`",
                "drive.rate",
            ],
        ),
        (
            "duplicate.toml",
            format!(
                "{HEAD}{PARAM_K}{}{HEAD}{PARAM_K}{}",
                places("\"tail.c_n\" = \"1 + k\""),
                places("\"tail.c_t\" = \"1 + k\"")
            ),
            vec!["my-effect", "field `name`", "line 16", "twice"],
        ),
        (
            "duplicate_param.toml",
            format!(
                "{HEAD}{PARAM_K}{PARAM_K}{}",
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["my-effect", "param.name", "line 14", "twice"],
        ),
        (
            "catalogue.toml",
            format!(
                "{}{PARAM_K}{}",
                HEAD.replace("my-effect", "backflow"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["backflow", "field `name`", "line 2", "catalogue"],
        ),
        (
            "default_out.toml",
            format!(
                "{HEAD}{}{}",
                PARAM_K.replace("default = 0.0", "default = 2.0"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["my-effect", "param.k.default", "line 9", "outside"],
        ),
        (
            "min_max.toml",
            format!(
                "{HEAD}{}{}",
                PARAM_K.replace("min = -1.0", "min = 1.0"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["my-effect", "param.k.min", "line 10", "below max"],
        ),
        (
            "non_finite.toml",
            format!(
                "{HEAD}{}{}",
                PARAM_K.replace("max = 1.0", "max = inf"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["my-effect", "param.k.max", "line 11", "finite"],
        ),
        (
            "empty_places.toml",
            format!("{HEAD}{PARAM_K}\n[effect.places]\n"),
            vec!["my-effect", "field `places`", "line 13", "tail.viscosity"],
        ),
        (
            "param_is_quantity.toml",
            format!(
                "{HEAD}{}{}",
                PARAM_K.replace("\"k\"", "\"shear_rate\""),
                places("\"tail.c_n\" = \"1 + shear_rate\"")
            ),
            vec!["my-effect", "param.name", "line 7", "case quantity"],
        ),
        (
            "unknown_field.toml",
            format!(
                "{HEAD}{}{}",
                PARAM_K.replace("unit", "units"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["my-effect", "field `units`", "line 8", "unit"],
        ),
        (
            "syntax.toml",
            format!("{HEAD}{PARAM_K}{}", places("\"tail.c_n\" = \"(1 + k\"")),
            vec!["my-effect", "places.\"tail.c_n\"", "line 14", "close"],
        ),
        (
            "unused.toml",
            format!("{HEAD}{PARAM_K}{}", places("\"tail.c_n\" = \"2\"")),
            vec!["my-effect", "param.k", "line 7", "no formula"],
        ),
        (
            "bad_name.toml",
            format!(
                "{}{PARAM_K}{}",
                HEAD.replace("my-effect", "My_Effect"),
                places("\"tail.c_n\" = \"1 + k\"")
            ),
            vec!["My_Effect", "field `name`", "line 2", "kebab-case"],
        ),
    ];
    for (name, text, needles) in cases {
        let err = load_error(dir.path(), name, &text);
        for n in needles {
            assert!(err.contains(n), "{name}: `{n}` missing from: {err}");
        }
    }
}

fn design_file(dir: &Path) -> PathBuf {
    let d = swimbot::workbench::synth::varied_design(&swimbot::data::paper());
    let path = dir.join("design.toml");
    std::fs::write(&path, swimbot::data::to_toml(&d)).unwrap();
    path
}

#[test]
fn a_user_effect_works_in_synth_fit_diagnose_compare_sweep_and_the_listing() {
    let dir = tempfile::tempdir().unwrap();
    let shear = fixture("shear.toml");
    let shear = shear.to_str().unwrap();
    let design = design_file(dir.path());
    let data = dir.path().join("data.toml");
    let o = swimbot(&[
        "synth",
        "--data",
        design.to_str().unwrap(),
        "--truth",
        "base + shear-thinning-tail:k=-0.3",
        "--effect-file",
        shear,
        "--seed",
        "5",
        // the truth on the recorded inputs: this test is about the effect
        "--nominal-inputs",
        "-o",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let data = data.to_str().unwrap();

    // fit recovers its own parameter within its 95 % interval.
    let v = json(&swimbot(&[
        "fit",
        "--data",
        data,
        "--effect-file",
        shear,
        "--effect",
        "shear-thinning-tail",
        "--format",
        "json",
    ]));
    let p = &v["fit"]["estimates"][0];
    let (k, ci) = (p["value"].as_f64().unwrap(), p["ci95"].as_f64().unwrap());
    assert_eq!(p["effect"], "shear-thinning-tail");
    assert!((k + 0.3).abs() <= ci && ci < 0.1, "k = {k} +- {ci}");

    // diagnose proposes it and names it when it is the truth.
    let v = json(&swimbot(&[
        "diagnose",
        "--data",
        data,
        "--effect-file",
        shear,
        "--no-pairs",
        "--format",
        "json",
    ]));
    assert_eq!(
        v["verdict"]["effect"], "shear-thinning-tail",
        "{}",
        v["verdict"]
    );
    assert_eq!(v["ranking"][0]["effect"], "shear-thinning-tail");

    // compare: the error with the effect is far below the base model's.
    let mare = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            "--data",
            data,
            "--effect-file",
            shear,
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        json(&swimbot(&args))["summary"]["mare"].as_f64().unwrap()
    };
    let (base, with_k) = (mare(&[]), mare(&["--effect", "shear-thinning-tail:k=-0.3"]));
    assert!(with_k < 0.5 * base, "MARE {base} -> {with_k}");

    // sweep: the effect reaches the swept predictions.
    let sweep = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "--wavelength-mm",
            "15",
            "--amplitude-mm",
            "2.5",
            "--tail-length-mm",
            "130",
            "--effect-file",
            shear,
        ];
        args.extend_from_slice(extra);
        let o = swimbot(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let (a, b) = (
        sweep(&[]),
        sweep(&["--effect", "shear-thinning-tail:k=-0.3"]),
    );
    assert_eq!(a.lines().count(), b.lines().count());
    assert_ne!(a, b, "the effect must change the sweep");

    // listing: the user effect with its formula and file.
    let v = json(&swimbot(&[
        "effects",
        "--effect-file",
        shear,
        "--format",
        "json",
    ]));
    let e = v
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["name"] == "shear-thinning-tail")
        .expect("listed");
    assert_eq!(e["formulas"][0][0], "tail.viscosity");
    assert_eq!(e["formulas"][0][1], "1 + k * shear_rate / 100");
    assert!(e["source"].as_str().unwrap().ends_with("shear.toml"));
}

#[test]
fn a_bad_multiplier_at_evaluation_is_exit_2_naming_case_and_effect() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("neg.toml");
    std::fs::write(
        &path,
        format!(
            "{HEAD}{}\n[effect.places]\n\"tail.c_n\" = \"1 - k * amplitude_ratio\"\n",
            PARAM_K.replace("max = 1.0", "max = 5.0")
        ),
    )
    .unwrap();
    let o = swimbot(&[
        "compare",
        "--effect-file",
        path.to_str().unwrap(),
        "--effect",
        "my-effect:k=4",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    for n in [
        "case `",
        "effect `my-effect`",
        "tail.c_n",
        "within [1e-6, 1e6]",
        "k=4",
    ] {
        assert!(err.contains(n), "`{n}` missing from: {err}");
    }
    assert!(!err.contains("NaN") && !err.contains("panicked"), "{err}");
}

#[test]
fn the_documented_worked_example_lowers_the_error_on_the_paper_data() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/effects");
    let annular = docs.join("annular-body.toml");
    let annular = annular.to_str().unwrap();
    let shear = docs.join("shear-thinning-tail.toml");
    let v = json(&swimbot(&[
        "effects",
        "--effect-file",
        annular,
        "--effect-file",
        shear.to_str().unwrap(),
        "--format",
        "json",
    ]));
    let names: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"annular-body") && names.contains(&"shear-thinning-tail"));
    let fit = json(&swimbot(&[
        "fit",
        "--effect-file",
        annular,
        "--effect",
        "annular-body",
        "--format",
        "json",
    ]));
    let piston = fit["fit"]["estimates"][0]["value"].as_f64().unwrap();
    let mare = |extra: &[&str]| {
        let mut args = vec!["compare", "--effect-file", annular, "--format", "json"];
        args.extend_from_slice(extra);
        json(&swimbot(&args))["summary"]["mare"].as_f64().unwrap()
    };
    let spec = format!("annular-body:piston={piston}");
    let (base, with) = (mare(&[]), mare(&["--effect", &spec]));
    // Measured: 294.6 % -> 36.8 % (docs/effects-format.md, "A worked example").
    assert!(base > 2.5 && with < 0.45, "MARE {base} -> {with}");
}
