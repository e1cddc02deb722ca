//! A recorded column as a feature of the search (src/data/feature.rs): an
//! oil whose viscosity follows the recorded temperature (Andrade's
//! `mu = mu_25 exp(-b (T - 25 C))`, on body and tail alike) on the drawn
//! design of a development seed, written as a user effect that reads
//! `recorded.temperature_c`. With a net weight of 0.1 g the viscosity
//! acts against it, as an axial load that changes sign at 25 C: the search
//! locates a law in the recorded column at `load.force`; written as an
//! effect file and loaded again, it predicts what the diagnosis fitted. At
//! neutral trim the same truth leaves no trace and nothing is located.

use crate::fixtures;

use fixtures::diagnosed::drawn_data;
use fixtures::drawn;
use swimbot::data::Dataset;
use swimbot::effects::formula::FormulaEffect;
use swimbot::effects::{user_file, EffectInstance};
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, VerdictKind};

const SEED: u64 = 1704;

/// The oil's viscosity over its value at 25 C, `exp(-0.03 (T - 25))`, at
/// the body's and the tail's resistances alike.
const ANDRADE: &str = r#"
[[effect]]
name = "andrade-oil"
statement = "the oil's viscosity follows its recorded temperature"
reference = "Andrade, Nature 125 (1930) 309"

[[effect.param]]
name = "b"
unit = "1/K"
default = 0.03
min = 0.0
max = 1.0

[effect.places]
"tail.viscosity" = "exp(-b * (recorded.temperature_c - 25))"
"body.D_x" = "exp(-b * (recorded.temperature_c - 25))"
"body.E_x" = "exp(-b * (recorded.temperature_c - 25))"
"#;

fn andrade() -> EffectInstance {
    let spec = user_file::parse(ANDRADE, "andrade.toml").unwrap().remove(0);
    EffectInstance {
        effect: std::sync::Arc::new(FormulaEffect::new(spec, "andrade.toml").unwrap()).into(),
        values: vec![0.03],
    }
}

/// The drawn design at a net weight (g) with a temperature recorded per
/// case, 18-34 C, spread
/// evenly and shuffled by a fixed stride so that it follows no feature.
fn warm_design(net_weight_g: f64) -> Dataset {
    let mut design = drawn::design(&swimbot::data::paper(), SEED);
    let n = design.cases.len();
    for (i, c) in design.cases.iter_mut().enumerate() {
        let t = 18.0 + 16.0 * ((i * 7) % n) as f64 / (n - 1) as f64;
        c.recorded.values.push(("temperature_c".into(), t));
        c.net_weight_g = net_weight_g;
    }
    design
}

fn diagnosed(design: &Dataset) -> (swimbot::workbench::diagnose::Diagnosis, Dataset) {
    let truth = Model::base().with_effect(andrade());
    let data = drawn_data(&truth, design, SEED);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    (d, data)
}

#[test]
fn a_viscosity_that_follows_the_recorded_temperature_is_a_load_in_it() {
    let (d, data) = diagnosed(&warm_design(0.1));
    let v = &d.verdict;
    assert!(
        matches!(v.kind, VerdictKind::Located | VerdictKind::Identified),
        "{:?}: {}",
        v.kind,
        v.note
    );
    let l = v.located.first().expect("a located law");
    assert_eq!(l.place, "load.force", "{}", v.note);
    assert_eq!(
        l.feature.as_deref(),
        Some("recorded.temperature_c"),
        "{}",
        v.note
    );
    assert!(
        l.interpretation.contains("temperature_c (recorded)")
            && l.interpretation.contains("net weight"),
        "{}",
        l.interpretation
    );
    // Written and loaded again, the law predicts what was fitted.
    let text = swimbot::workbench::discovery::write::to_toml(l, "warm-oil");
    assert!(text.contains("recorded.temperature_c"), "{text}");
    let spec = user_file::parse(&text, "w.toml").unwrap().remove(0);
    let values: Vec<f64> = spec.params.iter().map(|p| p.default).collect();
    let law = std::sync::Arc::new(FormulaEffect::new(spec, "w.toml").unwrap());
    let loaded = Model::base().with_effect(EffectInstance {
        effect: law.into(),
        values,
    });
    for c in &data.cases {
        let (a, b) = (loaded.predict(c).unwrap(), l.model.predict(c).unwrap());
        assert!(
            (a.u_mm_s - b.u_mm_s).abs() <= 1e-6 * b.u_mm_s.abs(),
            "{} vs {} on {}",
            a.u_mm_s,
            b.u_mm_s,
            c.id
        );
    }
}

#[test]
fn at_neutral_trim_the_same_viscosity_leaves_no_trace() {
    let (d, _) = diagnosed(&warm_design(0.0));
    assert_eq!(
        d.verdict.kind,
        VerdictKind::NoneNeeded,
        "{}",
        d.verdict.note
    );
    assert!(d.baseline.at_noise_floor, "{:?}", d.baseline);
    assert!(
        d.verdict.note.contains("recorded temperature_c")
            && d.verdict.note.contains("cannot show it"),
        "{}",
        d.verdict.note
    );
}
