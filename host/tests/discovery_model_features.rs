//! The model's own quantities as features of the search
//! (src/data/model_quantities.rs, src/model/columns.rs): a drive slip set
//! by the tail's load torque (host/tests/fixtures/load_slip.rs, a drawn
//! stall torque) is located as a law in the load torque at the drive, on
//! the drawn design of a development seed; the paper's verdict is still
//! stated; a located law in a model quantity, written as an effect file
//! and loaded again, predicts what the diagnosis fitted.

use crate::fixtures;

use fixtures::diagnosed::drawn_data;
use fixtures::{drawn, load_slip};
use swimbot::effects::correction::Form;
use swimbot::effects::formula::FormulaEffect;
use swimbot::effects::{user_file, EffectInstance};
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, Diagnosis, VerdictKind};

const SEED: u64 = 1703;

fn diagnose_load_slip(seed: u64) -> (Diagnosis, swimbot::data::Dataset) {
    let design = drawn::design(&swimbot::data::paper(), seed);
    let truth_effects = load_slip::load_slip(&design, seed);
    let slips = load_slip::slips(&design, &truth_effects);
    let (lo, hi) = slips
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |a, &s| (a.0.min(s), a.1.max(s)));
    // The drawn designs' load torques span about ten to one: the smallest
    // slip is about a tenth of the largest (fixtures/load_slip.rs).
    assert!(lo > 0.01 && (0.12..0.2).contains(&hi), "slips {lo}-{hi}");
    let mut truth = Model::base();
    truth.effects.extend(truth_effects);
    let data = drawn_data(&truth, &design, seed);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    (d, data)
}

#[test]
fn a_slip_set_by_the_load_torque_is_a_law_in_the_load_torque_at_the_drive() {
    let (d, _) = diagnose_load_slip(SEED);
    let v = &d.verdict;
    let l = v
        .located
        .first()
        .unwrap_or_else(|| panic!("nothing located: {}", v.note));
    assert_eq!(l.place, "drive.rate", "{}", v.note);
    // The power the tail takes is its torque times its rate, nearly the
    // torque's monotone function on a design whose rates vary x2: the
    // torque is the truth's feature and must win.
    assert_eq!(
        l.feature.as_deref(),
        Some("model_tail_torque_n_m"),
        "{}",
        v.note
    );
    assert!(l.score.at_noise_floor, "{}", v.note);
    assert_eq!(v.kind, VerdictKind::Located, "{}", v.note);
    // The truth is the search's `1 + k x` with x = tau/tau_ref exactly:
    // k = -tau_ref/tau_s, within its interval.
    let design = drawn::design(&swimbot::data::paper(), SEED);
    let tau_s = load_slip::stall_torque(&design, SEED);
    assert_eq!(l.form, Form::Linear, "{}", l.describe());
    let tau_ref = l.correction.scale;
    let k = &l.params[0];
    let ci = k.ci95.expect("identifiable");
    let want = -tau_ref / tau_s;
    assert!(
        (k.value - want).abs() < 3.0 * ci,
        "k = {} ± {ci}, truth {want}",
        k.value
    );
}

/// The located law, written as an effect file and loaded on cases that
/// carry nothing, predicts what the diagnosis fitted: the loaded model
/// computes the load torque from the model beneath the law.
#[test]
fn a_written_law_in_the_load_torque_means_the_same_when_loaded() {
    let (d, data) = diagnose_load_slip(1707);
    let l = d.verdict.located.first().expect("a located law");
    assert_eq!(
        l.feature.as_deref(),
        Some("model_tail_torque_n_m"),
        "{}",
        d.verdict.note
    );
    assert!(
        l.interpretation.contains("slowing under load"),
        "{}",
        l.interpretation
    );
    let text = swimbot::workbench::discovery::write::to_toml(l, "load-slip");
    assert!(text.contains("model beneath the law"), "{text}");
    let spec = user_file::parse(&text, "w.toml").unwrap().remove(0);
    assert!(spec.base.is_empty(), "{text}");
    let values: Vec<f64> = spec.params.iter().map(|p| p.default).collect();
    let law = std::sync::Arc::new(FormulaEffect::new(spec, "w.toml").unwrap());
    let loaded = Model::base().with_effect(EffectInstance {
        effect: law.into(),
        values,
    });
    let attached = swimbot::model::columns::attach(&Model::base(), &data).unwrap();
    for (plain, with) in data.cases.iter().zip(&attached.cases) {
        assert!(plain.derived.model.is_none());
        let a = loaded.predict(plain).unwrap();
        let b = l.model.predict(with).unwrap();
        for (x, y) in [(a.u_mm_s, b.u_mm_s), (a.omega_body_hz, b.omega_body_hz)] {
            assert!(
                (x - y).abs() <= 1e-6 * y.abs(),
                "{x} vs {y} on {}",
                plain.id
            );
        }
    }
}

#[test]
fn the_paper_verdict_is_still_stated_with_the_model_quantities_offered() {
    let data = swimbot::data::paper();
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    assert_eq!(
        d.verdict.kind,
        VerdictKind::Unexplained,
        "{}",
        d.verdict.note
    );
    assert!(!d.verdict.note.is_empty() && !d.verdict.located.is_empty());
    // The library offered them: the load torque trends with Omega_b's error.
    assert!(
        d.trends
            .iter()
            .any(|t| t.feature_id == "model_tail_torque_n_m"),
        "no trend in the load torque"
    );
}
