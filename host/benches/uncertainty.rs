//! Speed of input-uncertainty propagation and of the audit on the paper
//! data: the linear bands of all six cases (what `compare` adds), the
//! Monte-Carlo check of one case, and the whole audit.
//! Run: `cargo bench -p swimbot --bench uncertainty`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use swimbot::model::preset;
use swimbot::workbench::audit::{audit, AuditSettings};
use swimbot::workbench::compare::compare;
use swimbot::workbench::propagate::{bands, linear_band, monte_carlo};

fn propagation(c: &mut Criterion) {
    let data = swimbot::data::paper();
    let model = preset("paper").unwrap();
    c.bench_function("compare, paper data", |b| {
        b.iter(|| compare(black_box(&model), &data, 0).unwrap())
    });
    c.bench_function("linear bands, 6 cases x 8 inputs", |b| {
        b.iter(|| bands(black_box(&model), &data).unwrap())
    });
    let case = &data.cases[0];
    let band = linear_band(&model, case).unwrap();
    c.bench_function("Monte-Carlo check, 300 draws, one case", |b| {
        b.iter(|| monte_carlo(black_box(&model), case, &band, 300, 1).unwrap())
    });
}

fn whole_audit(c: &mut Criterion) {
    let data = swimbot::data::paper();
    let model = preset("base").unwrap();
    let mut g = c.benchmark_group("audit");
    g.sample_size(10);
    g.bench_function("audit, paper data", |b| {
        b.iter(|| audit(black_box(&model), &data, &AuditSettings::default()).unwrap())
    });
    g.finish();
}

criterion_group!(benches, propagation, whole_audit);
criterion_main!(benches);
