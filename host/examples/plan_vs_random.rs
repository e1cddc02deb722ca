//! The planned experiment against as many random runs of the same rig.
//!
//! The world: the paper's six cases with the body confined by the tube
//! (`base + body-confinement`), measured with 2 % noise on five trials.
//! On one tube the confinement is a fixed rescaling of the body's
//! resistance, so the two-parameter `body-correction` mimics it; the lab
//! has three tubes (25, 35, 50 mm) and the paper's two oils. For each
//! seed: the data are drawn, `diagnose` is run, and its rivals are
//! separated by `RUNS` runs, chosen once by the plan (T-optimal, greedy
//! maximin) and once at random among the same runs the robot can hold.
//! Each set of runs goes through the simulated lab (the whole robot, the
//! truth as the world, the same measurement noise), joins the data, and
//! `diagnose` runs again. Right: its verdict names `body-confinement`
//! and not `body-correction`.
//!
//! ```text
//! cargo run --release -p swimbot --example plan_vs_random [SEEDS] [RUNS]
//! ```
//!
//! It asserts that the plan is right more often than random runs are.

use rand::seq::SliceRandom;
use rand::SeedableRng;
use swimbot::data::Dataset;
use swimbot::model::Model;
use swimbot::sim::lab::{run_sheet, LabSettings};
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::plan::{
    candidates, plan, reachable, rivals_of, sheet::labelled, Candidate, Goal, Noise, PlanRig,
};
use swimbot::workbench::synth::{generate, SynthSettings};

const TRUTH: &str = "body-confinement";
const RIVAL: &str = "body-correction";

fn truth() -> Model {
    let mut m = Model::base();
    m.effects.push(swimbot::effects::EffectInstance::default_of(
        swimbot::effects::by_name(TRUTH).expect("a catalogue effect"),
    ));
    m
}

/// The verdict's effect names the truth and not its mimic.
fn right(data: &Dataset) -> (bool, String) {
    let d = diagnose(&Model::base(), data, &DiagnoseSettings::default()).expect("diagnose");
    let named = d.verdict.effect.clone().unwrap_or_default();
    let ok = named.split(" + ").any(|e| e == TRUTH) && !named.contains(RIVAL);
    (ok, format!("{:?} {named}", d.verdict.kind))
}

/// `data` with `runs` measured in the simulated lab.
fn joined(data: &Dataset, runs: &[Candidate], seed: u64) -> Dataset {
    let robot = swimbot::sim::default_robot();
    let mut sheet = data.clone();
    sheet.cases = runs
        .iter()
        .enumerate()
        .map(|(i, c)| labelled(c, &format!("run-{}", i + 1)))
        .collect();
    let lab = LabSettings {
        measurement: SynthSettings {
            seed: 10_000 + seed,
            ..SynthSettings::default()
        },
        ..LabSettings::default()
    };
    let measured = run_sheet(&robot, &truth(), &sheet, &lab).expect("the lab runs the sheet");
    let mut out = data.clone();
    out.cases.extend(measured.into_iter().map(|r| r.case));
    out
}

fn main() {
    let mut args = std::env::args().skip(1);
    let seeds: u64 = args.next().map_or(50, |s| s.parse().expect("SEEDS"));
    let runs: usize = args.next().map_or(1, |s| s.parse().expect("RUNS"));
    let robot = swimbot::sim::default_robot();
    let (mut planned_right, mut random_right, mut tried) = (0, 0, 0);
    for seed in 1..=seeds {
        let t0 = std::time::Instant::now();
        let mut design = swimbot::data::paper();
        design.rig.channel_diameter_mm = Some(vec![25.0, 35.0, 50.0]);
        let s = SynthSettings {
            seed,
            ..SynthSettings::default()
        };
        let data = generate(&truth(), &design, s).expect("synthetic data");
        let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).expect("diagnose");
        let rivals = rivals_of(&d);
        if rivals.goal != Goal::Separate {
            println!(
                "seed {seed}: no rivals to separate ({:?} {:?}); not counted",
                d.verdict.kind, d.verdict.effect
            );
            continue;
        }
        tried += 1;
        let rig = PlanRig::of(&data, None, None, false);
        let cands = candidates(&data, &rig).expect("the rig runs something");
        let p = plan(cands.clone(), &rivals, &Noise::of(&data), runs, &robot);
        let chosen: Vec<Candidate> = p.runs.iter().map(|r| r.candidate.clone()).collect();
        let pool = reachable(cands, &rivals, &robot);
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let random: Vec<Candidate> = pool.choose_multiple(&mut rng, runs).cloned().collect();
        let (a, va) = right(&joined(&data, &chosen, seed));
        let (b, vb) = right(&joined(&data, &random, seed));
        planned_right += usize::from(a);
        random_right += usize::from(b);
        let tubes = |c: &[Candidate]| {
            c.iter()
                .map(|c| format!("{}", c.case.channel_diameter_mm))
                .collect::<Vec<_>>()
                .join(",")
        };
        println!(
            "seed {seed}: planned (tubes {}) {} [{va}]; random (tubes {}) {} [{vb}]; {:.1} s",
            tubes(&chosen),
            if a { "right" } else { "wrong" },
            tubes(&random),
            if b { "right" } else { "wrong" },
            t0.elapsed().as_secs_f64()
        );
    }
    println!(
        "over {tried} seeds with rivals, {runs} runs each: planned right {planned_right}, random right {random_right}"
    );
    assert!(tried > 0, "no seed left rivals to separate");
    assert!(
        planned_right > random_right,
        "the plan did no better than random runs"
    );
}
