//! Each located term's stability under bootstrap resampling of the cases
//! (`workbench/search/stability.rs`): filled for a found set, with the
//! counts it states, and near one for a strong true term.

use swimbot::effects::correction::{Form, LocatedCorrection};
use swimbot::effects::place::Place;
use swimbot::effects::EffectInstance;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::discovery::Table;
use swimbot::workbench::synth::{generate, rich_design, SynthSettings};

#[test]
fn a_strong_constant_load_is_selected_on_nearly_every_resample() {
    let design = rich_design(&swimbot::data::paper());
    let scale = Table::build(&Model::base(), &design)
        .unwrap()
        .load_scale(Place::LoadForce);
    let law = LocatedCorrection::new(Place::LoadForce, None, Form::Constant, 1.0, 1.0).unwrap();
    let truth = Model::base().with_effect(EffectInstance {
        effect: std::sync::Arc::new(law).into(),
        values: vec![1.5 * scale],
    });
    let settings = SynthSettings {
        seed: 4242,
        ..Default::default()
    };
    let data = generate(&truth, &design, settings).unwrap();
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert!(!v.stability.is_empty(), "{}", v.note);
    for s in &v.stability {
        assert_eq!(s.method, "bootstrap");
        assert_eq!(s.resamples, 200);
        assert!((s.fraction - s.selected as f64 / 200.0).abs() < 1e-12);
    }
    let load = v
        .stability
        .iter()
        .find(|s| s.term.contains("load.force") || s.term == "buoyancy")
        .unwrap_or_else(|| panic!("no load term among {:?}", v.stability));
    assert!(load.fraction >= 0.9, "{load:?}");
    let json = serde_json::to_value(v).unwrap();
    assert!(json["stability"][0]["fraction"].is_number());
}

#[test]
fn a_null_has_no_terms_to_be_sure_of() {
    let design = rich_design(&swimbot::data::paper());
    let settings = SynthSettings {
        seed: 4243,
        ..Default::default()
    };
    let data = generate(&Model::base(), &design, settings).unwrap();
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    assert!(d.verdict.stability.is_empty());
}
