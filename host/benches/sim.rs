//! Wall time of a long whole-robot simulation (criterion): 10 minutes of
//! robot time (600 000 one-millisecond controller ticks) with the built-in
//! robot and tail #1, run until the controller's 10-minute limit stops it.
//!
//! `cargo bench -p swimbot --bench sim`. The target is well under a
//! second in release.
use criterion::{criterion_group, criterion_main, Criterion};
use swimbot::sim::{default_robot, simulate, End, Options, Script};

fn bench(c: &mut Criterion) {
    let robot = default_robot();
    let script = Script::on_at_zero();
    let opts = Options {
        stop_at_top: false,
        max_time_s: 700.0,
        ..Options::default()
    };
    let mut group = c.benchmark_group("sim");
    group.sample_size(10);
    group.bench_function("ten_minutes_tail1", |b| {
        b.iter(|| {
            let o = simulate(&robot, &script, &opts).unwrap();
            assert!(o.last.t_s >= 600.0 && matches!(o.end, End::Stopped(_)));
            o.ticks
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
