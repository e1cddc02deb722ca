//! Cost of the non-local tail models vs resolution (criterion).
//!
//! `cargo bench -p swimbot --bench nonlocal`. Tail #1 (the longest, 8.4
//! turns, 183 mm of wire) by regularized Stokeslets and by slender-body
//! theory; `segments_per_turn` is the resolution.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use swimbot::nonlocal::{tail_resistance, NonlocalSettings, TailMethod};
use swimbot::physics::geometry::Helix;

fn bench(c: &mut Criterion) {
    let helix = Helix::from_mm(15.5, 2.5, 130.0, 1.0);
    let mut group = c.benchmark_group("tail1");
    group.sample_size(10);
    let runs = [
        (
            TailMethod::RegularizedStokeslets,
            vec![8usize, 12, 16, 24, 48],
        ),
        (TailMethod::SlenderBody, vec![6, 10, 14]),
    ];
    for (method, spts) in runs {
        for spt in spts {
            let s = NonlocalSettings::default()
                .with_method(method)
                .with_segments_per_turn(spt);
            let id = BenchmarkId::new(format!("{method:?}"), spt);
            group.bench_with_input(id, &s, |b, s| {
                b.iter(|| tail_resistance(&helix, 3.5, s).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
