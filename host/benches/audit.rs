//! Speed of the audit at scale: 1 000 synthetic cases (the
//! paper's six tails, frequencies spread by +-2 %, measured by a truth
//! model with 2 % noise). The goal is 15 s for the whole process on two
//! cores; this is the library call without start-up.
//! Run: `cargo bench -p swimbot --bench audit`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use swimbot::data::Dataset;
use swimbot::model::preset;
use swimbot::workbench::audit::{audit, AuditSettings};
use swimbot::workbench::synth::{generate, SynthSettings};

fn cases(n: usize) -> Dataset {
    let paper = swimbot::data::paper();
    let mut design = paper.clone();
    design.cases = (0..n)
        .map(|i| {
            let mut c = paper.cases[i % paper.cases.len()].clone();
            c.id = format!("c{i}");
            c.frequency_hz *= 1.0 + 0.02 * ((i as f64 * 0.618).fract() * 2.0 - 1.0);
            c
        })
        .collect();
    generate(&preset("paper").unwrap(), &design, SynthSettings::default()).unwrap()
}

fn audit_at_scale(c: &mut Criterion) {
    let model = preset("base").unwrap();
    let mut g = c.benchmark_group("audit");
    g.sample_size(10);
    for n in [100, 1_000] {
        let data = cases(n);
        g.bench_function(format!("audit, {n} synthetic cases"), |b| {
            b.iter(|| audit(black_box(&model), &data, &AuditSettings::default()).unwrap())
        });
    }
    g.finish();
}

/// One prediction of the plain model on a paper case: the unit in which
/// the audit's time estimate prices the work around each prediction
/// (`cli/audit.rs`: audit time over counted predictions, in these units).
fn plain_prediction(c: &mut Criterion) {
    let model = swimbot::model::Model::base();
    let case = swimbot::data::paper().cases[0].clone();
    c.bench_function("plain prediction, paper tail 1", |b| {
        b.iter(|| model.predict(black_box(&case)).unwrap())
    });
}

criterion_group!(benches, plain_prediction, audit_at_scale);
criterion_main!(benches);
