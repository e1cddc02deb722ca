//! Speed of the RFT model: the tail matrix by each method, the x-only
//! solve of one case, a sweep's cost per geometry, and the workbench's
//! diagnosis of the paper data.
//! Run: `cargo bench -p swimbot --bench model`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use swimbot::model::{preset, Model};
use swimbot::physics::coefficients::CoefficientSet;
use swimbot::physics::tail::{
    axial_closed_form, matrix_exact, matrix_quadrature, PAPER_NODES_PER_WAVELENGTH,
};
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};

fn tail(c: &mut Criterion) {
    let case = &swimbot::data::paper().cases[0];
    let helix = case.helix();
    let drag = CoefficientSet::GrayHancock.local_drag(&helix, 3.5).unwrap();
    c.bench_function("tail #1 axial closed form", |b| {
        b.iter(|| axial_closed_form(black_box(&helix), drag))
    });
    c.bench_function("tail #1 exact 6x6", |b| {
        b.iter(|| matrix_exact(black_box(&helix), drag))
    });
    c.bench_function("tail #1 quadrature 6x6 (839 nodes)", |b| {
        b.iter(|| matrix_quadrature(black_box(&helix), drag, PAPER_NODES_PER_WAVELENGTH))
    });
}

fn solve(c: &mut Criterion) {
    let case = swimbot::data::paper().cases[0].clone();
    let base = Model::base();
    let paper = preset("paper").unwrap();
    c.bench_function(
        "predict one case, base model (exact tail + x-only solve)",
        |b| b.iter(|| base.predict(black_box(&case)).unwrap()),
    );
    c.bench_function("predict one case, paper preset", |b| {
        b.iter(|| paper.predict(black_box(&case)).unwrap())
    });
    // What `swimbot sweep` spends per geometry on one thread: the base
    // model's prediction and its CSV line as cli/sweep.rs writes it (the
    // grid's five cells formatted once per range, the four predictions
    // by format::push_csv_f64).
    let inputs: Vec<String> = [
        case.wavelength_mm,
        case.amplitude_mm,
        case.tail_length_mm,
        case.frequency_hz,
        case.channel_diameter_mm,
    ]
    .iter()
    .map(|&v| swimbot::format::csv_f64(v))
    .collect();
    let mut line = Vec::with_capacity(256);
    c.bench_function("sweep: one geometry, predicted and written", |b| {
        b.iter(|| {
            let p = base.predict(black_box(&case)).unwrap();
            line.clear();
            for cell in &inputs {
                line.extend_from_slice(cell.as_bytes());
                line.push(b',');
            }
            for (k, v) in [p.u_mm_s, p.omega_body_hz, p.u_over_u_wave, p.omega_ratio]
                .into_iter()
                .enumerate()
            {
                if k > 0 {
                    line.push(b',');
                }
                swimbot::format::push_csv_f64(&mut line, v);
            }
            line.push(b'\n');
            black_box(line.len())
        })
    });
    // The same line through `{}` for all nine cells, as the sweep wrote it
    // before: the same text, the formatting more than half the cost.
    c.bench_function("sweep: one geometry, predicted and written with {}", |b| {
        b.iter(|| {
            use std::io::Write;
            let p = base.predict(black_box(&case)).unwrap();
            line.clear();
            let _ = writeln!(
                line,
                "{},{},{},{},{},{},{},{},{}",
                case.wavelength_mm,
                case.amplitude_mm,
                case.tail_length_mm,
                case.frequency_hz,
                case.channel_diameter_mm,
                p.u_mm_s,
                p.omega_body_hz,
                p.u_over_u_wave,
                p.omega_ratio
            );
            black_box(line.len())
        })
    });
}

fn workbench(c: &mut Criterion) {
    let data = swimbot::data::paper();
    let mut g = c.benchmark_group("workbench");
    g.sample_size(10);
    g.bench_function("diagnose paper data, whole catalogue", |b| {
        b.iter(|| {
            diagnose(
                &Model::base(),
                black_box(&data),
                &DiagnoseSettings::default(),
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, tail, solve, workbench);
criterion_main!(benches);
