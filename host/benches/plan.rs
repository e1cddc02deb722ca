//! Wall time of `swimbot plan`'s work on a 50-case study (criterion): the
//! diagnosis that names the rivals, the candidate runs of a rig of three
//! tubes and two oils, and the greedy choice of 6 runs.
//!
//! The study: the paper's six tails in its 35 mm tube, in two oils at five
//! rates (60 cases, the first 50 kept), measured in a world with the body
//! confined by the tube (`base + body-confinement`, 2 % noise, five
//! trials): in one tube the confinement is a constant factor, which
//! `body-correction` mimics, so there are rivals to separate. The rig adds
//! the 25 and 50 mm tubes. `cargo bench -p swimbot --bench plan`; the target is 10 s
//! on the 2-core machine.
use criterion::{criterion_group, criterion_main, Criterion};
use swimbot::data::Dataset;
use swimbot::effects::{by_name, EffectInstance};
use swimbot::model::Model;
use swimbot::workbench::diagnose::DiagnoseSettings;
use swimbot::workbench::plan::{plan_for, PlanRig};
use swimbot::workbench::synth::{generate, SynthSettings};

fn study() -> Dataset {
    let paper = swimbot::data::paper();
    let mut design = paper.clone();
    design.cases.clear();
    for c in &paper.cases {
        for mu in [1.0, 3.5] {
            for f in [0.7, 0.9, 1.1, 1.3, 1.5] {
                let mut k = c.clone();
                k.id = format!("{}-{mu}pas-{f}hz", c.id);
                k.viscosity_pa_s = mu;
                k.frequency_hz = f;
                design.cases.push(k);
            }
        }
    }
    design.cases.truncate(50);
    let mut truth = Model::base();
    truth.effects.push(EffectInstance::default_of(
        by_name("body-confinement").unwrap(),
    ));
    generate(&truth, &design, SynthSettings::default()).unwrap()
}

fn bench(c: &mut Criterion) {
    let data = study();
    let rig = PlanRig::of(&data, Some(vec![25.0, 35.0, 50.0]), None, false);
    let robot = swimbot::sim::default_robot();
    let settings = DiagnoseSettings::default();
    let (rivals, plan) = plan_for(&Model::base(), &data, &settings, &rig, 6, &robot).unwrap();
    let plan = plan.expect("the 50-case study leaves something to plan");
    eprintln!(
        "plan on {} cases: {} ({} models), {} runs of {} the robot can hold",
        data.cases.len(),
        rivals.why,
        rivals.models.len(),
        plan.runs.len(),
        plan.reachable
    );
    let mut group = c.benchmark_group("plan");
    group.sample_size(10);
    group.bench_function("fifty_case_study_six_runs", |b| {
        b.iter(|| {
            let (rivals, plan) =
                plan_for(&Model::base(), &data, &settings, &rig, 6, &robot).unwrap();
            (rivals.models.len(), plan.map(|p| p.runs.len()))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
