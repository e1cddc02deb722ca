//! Cost of a user effect stated as formulas against the equivalent
//! hand-written catalogue effect: predicting all six paper cases, and
//! evaluating the formulas alone (the per-case overhead a fit pays per
//! iteration). The fixtures are the test fixtures that restate
//! body-correction and tail-confinement (host/tests/fixtures/restated.toml).
//! Run: `cargo bench -p swimbot --bench formula`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use swimbot::effects::Catalogue;
use swimbot::model::Model;

fn with(catalogue: &Catalogue, spec: &str) -> Model {
    Model::base().with_effect(catalogue.parse_effect_spec(spec).unwrap())
}

fn predict_all(model: &Model, cases: &[swimbot::data::Case]) -> f64 {
    cases.iter().map(|c| model.predict(c).unwrap().u_mm_s).sum()
}

fn formula_vs_catalogue(c: &mut Criterion) {
    let fixture =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/restated.toml");
    let mut known = Catalogue::builtin();
    known
        .load_effect_files(&[fixture], &swimbot::provenance::Inputs::new())
        .unwrap();
    let cases = swimbot::data::paper().cases;
    let pairs = [
        (
            "body-correction:translation=16,rotation=1.4",
            "body-factors:translation=16,rotation=1.4",
        ),
        ("tail-confinement:gamma=2", "wall-log:gamma=2"),
    ];
    let base = Model::base();
    c.bench_function("paper data (6 cases), base model", |b| {
        b.iter(|| predict_all(black_box(&base), &cases))
    });
    for (catalogue, user) in pairs {
        let (mc, mu) = (with(&known, catalogue), with(&known, user));
        c.bench_function(&format!("paper data, catalogue {catalogue}"), |b| {
            b.iter(|| predict_all(black_box(&mc), &cases))
        });
        c.bench_function(&format!("paper data, formula {user}"), |b| {
            b.iter(|| predict_all(black_box(&mu), &cases))
        });
    }
    let wall = known
        .user_effects()
        .iter()
        .find(|e| e.spec().name == "wall-log")
        .unwrap();
    c.bench_function("wall-log formulas alone, 6 cases (2 places)", |b| {
        b.iter(|| {
            cases
                .iter()
                .map(|case| wall.values(black_box(&[2.0]), case)[0].1)
                .sum::<f64>()
        })
    });
}

criterion_group!(benches, formula_vs_catalogue);
criterion_main!(benches);
