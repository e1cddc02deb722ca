//! Cost of the leak-free tube solver (criterion), a small case: paper tail
//! #6 cut to two turns in the closed 35 mm tube, MFS wall 6 mm and 4.5 mm
//! apart (cold solves by the ring solver, and by the dense reference at
//! 4.5 mm), and the memoised effect (warm: the matrix from memory).
//!
//! `cargo bench -p swimbot --bench tail_tube`.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use swimbot::data::paper;
use swimbot::nonlocal::tube::{tail_resistance_in_tube, TubeSettings, WallSolver};

fn bench(c: &mut Criterion) {
    let case = {
        let mut c = paper().cases[5].clone();
        c.tail_length_mm = 2.0 * c.wavelength_mm;
        c
    };
    let (helix, channel) = (case.helix(), case.channel());
    let mut group = c.benchmark_group("tail6_two_turns_tube35");
    group.sample_size(10);
    for wall_mm in [6.0, 4.5] {
        let s = TubeSettings {
            wall_spacing_m: wall_mm * 1e-3,
            ..TubeSettings::default()
        };
        group.bench_with_input(BenchmarkId::new("cold", wall_mm), &s, |b, s| {
            b.iter(|| tail_resistance_in_tube(&helix, &channel, 3.5, s).unwrap())
        });
    }
    let dense = TubeSettings {
        wall_spacing_m: 4.5e-3,
        solver: WallSolver::Dense,
        ..TubeSettings::default()
    };
    group.bench_function("cold_dense/4.5", |b| {
        b.iter(|| tail_resistance_in_tube(&helix, &channel, 3.5, &dense).unwrap())
    });
    // warm: the effect's memoised matrix (first call solves, then memory)
    let dir = tempfile::tempdir().unwrap();
    std::env::set_var(swimbot::nonlocal::cache::CACHE_DIR_ENV, dir.path());
    let model = swimbot::model::Model::base()
        .with_effect(swimbot::effects::parse_effect_spec("tail-confinement-stokeslets").unwrap());
    let _ = model.tail_matrix(&case).unwrap();
    group.bench_function("cached", |b| b.iter(|| model.tail_matrix(&case).unwrap()));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
