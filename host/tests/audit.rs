//! `swimbot audit` on synthetic data (the real binary): a dataset measured
//! on one geometry but recorded with another is flagged, and only that
//! case; a consistent dataset gives no flags; the paper's data give the
//! documented JSON.

use crate::common;
use common::swimbot;
use swimbot::data::{self, to_toml, Dataset};
use swimbot::effects::parse_effect_list;
use swimbot::model::Model;
use swimbot::workbench::synth::{generate, SynthSettings};

const TRUTH: &str = "backflow + body-correction:translation=16,rotation=1.4";
const CHORD_MM: f64 = 185.0;

fn truth() -> Model {
    let mut m = Model::base();
    m.effects = parse_effect_list(TRUTH).unwrap();
    m
}

/// The paper's six wavelengths and amplitudes, each tail's axial length set
/// so that every wire has the same chord length (as the paper intended),
/// measured by the truth model with 2 % noise, with stated uncertainties.
fn consistent() -> Dataset {
    let mut design = data::paper();
    for c in &mut design.cases {
        let k = 2.0 * std::f64::consts::PI * c.amplitude_mm / c.wavelength_mm;
        c.tail_length_mm = CHORD_MM / (1.0 + k * k).sqrt();
        // The trim's band is shared by every case, but the influence check
        // combines each case's band as if it were its own: with the
        // truth's 50 x 20 mm spheroid (little body drag) the 0.1 g trim
        // hides the 30 % mis-record planted below. These tests are about
        // the per-case inputs, so the design leaves the trim out.
        c.inputs.uncertainties.retain(|(f, _)| *f != "net_weight_g");
    }
    generate(
        &truth(),
        &design,
        SynthSettings {
            seed: 3,
            ..Default::default()
        },
    )
    .unwrap()
}

fn audit_flags(d: &Dataset) -> Vec<serde_json::Value> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("data.toml");
    std::fs::write(&path, to_toml(d)).unwrap();
    let mut args = vec![
        "audit",
        "--format",
        "json",
        "--data",
        path.to_str().unwrap(),
    ];
    for e in TRUTH.split('+') {
        args.push("--effect");
        args.push(e.trim());
    }
    let o = swimbot(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    v["flags"].as_array().unwrap().clone()
}

#[test]
fn a_consistent_dataset_gives_no_flags() {
    let flags = audit_flags(&consistent());
    assert!(flags.is_empty(), "{flags:#?}");
}

#[test]
fn a_mis_recorded_case_is_flagged_and_only_that_case() {
    let mut d = consistent();
    // tail-4 was built with a 12 mm pitch but recorded as 9 mm.
    let c = d.cases.iter_mut().find(|c| c.id == "tail-4").unwrap();
    assert_eq!(c.wavelength_mm, 12.0);
    c.wavelength_mm = 9.0;
    let flags = audit_flags(&d);
    assert!(!flags.is_empty(), "the mis-recorded case is not flagged");
    for f in &flags {
        assert_eq!(f["case"], "tail-4", "{flags:#?}");
        let detail = f["detail"].as_str().unwrap();
        assert!(detail.starts_with("tail-4: "), "{detail}");
        assert!(["warning", "error"].contains(&f["severity"].as_str().unwrap()));
    }
    let chord = flags
        .iter()
        .find(|f| f["kind"] == "chord-length")
        .unwrap_or_else(|| panic!("no chord-length flag: {flags:#?}"));
    let detail = chord["detail"].as_str().unwrap();
    assert!(
        detail.contains("above") && detail.contains("check its recorded"),
        "{detail}"
    );
}

#[test]
fn the_paper_data_audit_is_reported_in_the_documented_form() {
    let o = swimbot(&["audit", "--format", "json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let flags = v["flags"].as_array().unwrap();
    // The paper's tails 2 and 4 imply chords 11 % and 17 % below the others.
    let t4 = flags
        .iter()
        .find(|f| f["case"] == "tail-4" && f["kind"] == "chord-length")
        .unwrap_or_else(|| panic!("{flags:#?}"));
    assert!(
        t4["detail"].as_str().unwrap().contains("17 % below"),
        "{t4}"
    );
    for f in flags {
        for key in ["case", "kind", "detail", "severity"] {
            assert!(f[key].is_string(), "{f}");
        }
    }
    let bad = swimbot(&["audit", "--family-samples", "3"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// The one-step leave-one-out (what the audit uses beyond 40 cases) and the
/// exact refits reach the same conclusions and flags, on consistent data
/// and on data with a mis-recorded case.
#[test]
fn one_step_and_exact_leave_one_out_agree() {
    use swimbot::workbench::audit::influence::influence_with;
    use swimbot::workbench::audit::loo::LooMethod;
    use swimbot::workbench::propagate::with_input_uncertainty;
    use swimbot::workbench::robust::Likelihood;
    let mut bad = consistent();
    let c = bad.cases.iter_mut().find(|c| c.id == "tail-4").unwrap();
    c.u_mm_s.as_mut().unwrap().mean *= 1.3;
    for (d, flagged) in [(consistent(), false), (bad, true)] {
        let model = truth();
        let combined = with_input_uncertainty(&model, &d).unwrap();
        let (ex, ex_flags) =
            influence_with(&model, &combined, LooMethod::Exact, Likelihood::Gaussian);
        let (os, os_flags) =
            influence_with(&model, &combined, LooMethod::OneStep, Likelihood::Gaussian);
        assert_eq!(ex.conclusion, os.conclusion);
        assert_eq!(ex.without, os.without);
        let key = |f: &Vec<swimbot::workbench::audit::Flag>| {
            f.iter()
                .map(|f| (f.case.clone(), f.kind.clone()))
                .collect::<Vec<_>>()
        };
        assert_eq!(key(&ex_flags), key(&os_flags));
        assert_eq!(
            ex_flags.iter().any(|f| f.case == "tail-4"),
            flagged,
            "{ex_flags:#?}"
        );
    }
}

/// One run 6 standard errors off (a case's U) in otherwise consistent
/// data: the audit names that case as an `outlier`, on most of six fresh
/// seeds (the one-bad-run test names such a run on about three datasets in
/// four of this size: docs/discovery.md), and never another case.
#[test]
fn a_bad_run_is_named_as_an_outlier() {
    use swimbot::workbench::audit::{audit, AuditSettings};
    let mut design = data::paper();
    for c in &mut design.cases {
        let k = 2.0 * std::f64::consts::PI * c.amplitude_mm / c.wavelength_mm;
        c.tail_length_mm = CHORD_MM / (1.0 + k * k).sqrt();
    }
    let mut named = 0;
    for seed in 701..707u64 {
        let s = SynthSettings {
            seed,
            ..Default::default()
        };
        let mut d = generate(&truth(), &design, s).unwrap();
        let k = seed as usize % d.cases.len();
        d.cases[k].u_mm_s.as_mut().unwrap().mean +=
            6.0 * d.cases[k].u_mm_s.unwrap().standard_error();
        let id = d.cases[k].id.clone();
        let a = audit(&truth(), &d, &AuditSettings::default()).unwrap();
        let outliers: Vec<&str> = a
            .flags
            .iter()
            .filter(|f| f.kind == "outlier")
            .map(|f| f.case.as_str())
            .collect();
        assert!(
            outliers.iter().all(|c| *c == id),
            "seed {seed}: {outliers:?} not {id}"
        );
        named += outliers.contains(&id.as_str()) as usize;
    }
    assert!(named >= 4, "named on {named} of 6 seeds");
}

/// The one-step case deletion (what the audit uses beyond 40 cases) can
/// claim that without a case a candidate is clearly best when the exact
/// refits say it is not: the audit confirms such a claim by exact refits
/// before it warns. Such draws are rare: none of 320 least-squares
/// draws searched (5 truths, 2 designs, seeds 900-905, 2-15 % noise, with
/// and without one bad run) nor of 240 Student-t ones of the same, 2 of
/// 384 more Student-t ones (8 truths, seeds 906-911). This is one of them:
/// the varied design, truth buoyancy, 3 % noise, seed 909, one case's U
/// moved by 8 standard errors.
#[test]
fn a_claim_of_the_one_step_deletion_is_confirmed_by_exact_refits() {
    use swimbot::workbench::audit::influence::{decide, influence_with, Finding};
    use swimbot::workbench::audit::loo::LooMethod;
    use swimbot::workbench::robust::Likelihood;
    use swimbot::workbench::synth::varied_design;
    let mut truth = Model::base();
    truth.effects = parse_effect_list("buoyancy").unwrap();
    let s = SynthSettings {
        seed: 909,
        noise_rel: 0.03,
        ..Default::default()
    };
    let mut d = generate(&truth, &varied_design(&data::paper()), s).unwrap();
    let k = 909 % d.cases.len();
    let u = d.cases[k].u_mm_s.unwrap();
    d.cases[k].u_mm_s.as_mut().unwrap().mean += 8.0 * u.standard_error();
    let (base, lik) = (Model::base(), Likelihood::StudentT);
    let (raw, raw_findings) = decide(&base, &d, LooMethod::OneStep, lik, false);
    let (exact, _) = decide(&base, &d, LooMethod::Exact, lik, false);
    // The approximation claims a conclusion without some case that the
    // exact refits do not give.
    let wrong: Vec<&String> = raw
        .without
        .iter()
        .zip(&exact.without)
        .filter(|(a, b)| a != b)
        .map(|(a, _)| &a.0)
        .collect();
    assert!(!wrong.is_empty(), "{:?} {:?}", raw.without, exact.without);
    assert!(raw_findings
        .iter()
        .any(|f| matches!(f, Finding::MakesAConclusion { case, .. } if wrong.contains(&case))));
    // With the re-check, the audit's answer is the exact one, and no
    // warning rests on the approximation's claim.
    let (checked, flags) = influence_with(&base, &d, LooMethod::OneStep, lik);
    assert_eq!(checked.without, exact.without);
    assert_eq!(checked.conclusion, exact.conclusion);
    assert!(
        !flags
            .iter()
            .any(|f| f.kind == "influence-verdict" && wrong.contains(&&f.case)),
        "{flags:#?}"
    );
}
