//! Cost of one exact body solve (`nonlocal::axisym`, criterion): the
//! paper's body (spheroid and the three-section profile) in the paper's
//! closed 35 x 350 mm tube and in free space, at resolutions 4, 8 (the
//! default) and 16 elements per gap; and the coupler's spin below the
//! profile with a 1 mm gap (`axisym::spin`) at resolutions 2, 4 (the
//! `coupler` effect's) and 8.
//!
//! `cargo bench -p swimbot --bench axisym`
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use swimbot::nonlocal::axisym::spin::{solve_spin, Stack};
use swimbot::nonlocal::axisym::{solve_body, AxisymSettings, Confinement};
use swimbot::physics::profile::BodyProfile;

fn bench(c: &mut Criterion) {
    let tube = Confinement::Closed {
        diameter_m: 0.035,
        length_m: 0.35,
    };
    let bodies = [
        ("spheroid", BodyProfile::spheroid(50.0, 20.0)),
        (
            "profile",
            BodyProfile::parse_sections("10:20,30:18,10:20", 0.0).unwrap(),
        ),
    ];
    let mut group = c.benchmark_group("body_solve");
    group.sample_size(10);
    for (name, body) in &bodies {
        for (where_, conf) in [("closed", tube), ("free", Confinement::Free)] {
            for res in [4.0, 8.0, 16.0] {
                let s = AxisymSettings {
                    resolution: res,
                    ..AxisymSettings::default()
                };
                let id = BenchmarkId::new(format!("{name}-{where_}"), res);
                group.bench_with_input(id, &s, |b, s| {
                    b.iter(|| solve_body(body, &conf, 0.0, 3.5, s).unwrap())
                });
            }
        }
    }
    group.finish();
    let stack = Stack {
        rotor: BodyProfile::cylinder(10.0, 6.0, 0.0),
        stator: Some(bodies[1].1.clone()),
        gap_m: 1e-3,
    };
    let mut group = c.benchmark_group("coupler_spin");
    group.sample_size(10);
    for res in [2.0, 4.0, 8.0] {
        let s = AxisymSettings {
            resolution: res,
            ..AxisymSettings::default()
        };
        group.bench_with_input(BenchmarkId::new("closed", res), &s, |b, s| {
            b.iter(|| solve_spin(&stack, &tube, 0.0, 3.5, s).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
