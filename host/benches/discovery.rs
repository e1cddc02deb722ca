//! Speed of discovery beyond the catalogue on the paper's data: building
//! the response table (11 places x 161 multipliers x 6 cases), screening
//! every law on it, and the whole search with exact refits; and the
//! model's own quantities attached to the cases (once per diagnosis), on
//! the paper's data and on the rich synthetic design.
//! Run: `cargo bench -p swimbot --bench discovery`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use swimbot::model::Model;
use swimbot::workbench::discovery::screen::Table;
use swimbot::workbench::discovery::search::{corrections, screen_one};
use swimbot::workbench::discovery::{discover, DiscoverySettings, Reference};

fn discovery(c: &mut Criterion) {
    let data = swimbot::data::paper();
    let model = Model::base();
    c.bench_function("response table, paper data", |b| {
        b.iter(|| Table::build(black_box(&model), &data).unwrap())
    });
    let table = Table::build(&model, &data).unwrap();
    let laws = corrections(&table, &data);
    let all: Vec<usize> = (0..table.obs.len()).collect();
    c.bench_function("screening every law on the table, paper data", |b| {
        b.iter(|| {
            laws.iter()
                .map(|l| screen_one(&table, l, &data, &all, None).chi2)
                .sum::<f64>()
        })
    });
    c.bench_function("model quantities attached, paper data", |b| {
        b.iter(|| swimbot::model::columns::attach(black_box(&model), &data).unwrap())
    });
    let big = swimbot::workbench::synth::rich_design(&data);
    c.bench_function(
        &format!("model quantities attached, {} cases", big.cases.len()),
        |b| b.iter(|| swimbot::model::columns::attach(black_box(&model), &big).unwrap()),
    );
    let floor = |_k: usize| Some(1e300);
    let chi2 = swimbot::workbench::compare::compare(&model, &data, 0)
        .unwrap()
        .summary
        .chi2;
    let reference = Reference {
        chi2,
        k: 0,
        floor: &floor,
        likelihood: swimbot::workbench::robust::Likelihood::Gaussian,
    };
    c.bench_function(
        "whole discovery (screen + exact refits + CV), paper data",
        |b| b.iter(|| discover(&model, &data, &reference, &DiscoverySettings::default()).unwrap()),
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = discovery
}
criterion_main!(benches);
