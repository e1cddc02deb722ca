//! Recovery study of the search over subsets (docs/discovery.md, "Subset
//! search: recovery seeds"): drawn truths with several effects at once,
//! diagnosed from the base model, ten seeds per category.
//!
//! Categories (constants and designs drawn per seed, host/tests/fixtures/
//! drawn.rs, 36 cases, 2 % noise per trial, five trials):
//! - `three`: body drag `D_x (1 + a (D_b/D_ch)^q)`, a shear-thinning tail
//!   oil and a tail drag rising near the wall, all at once;
//! - `constant`: a constant drive slip (the tail turns at 0.80-0.93 of the
//!   recorded rate) with the tail drag rising near the wall;
//! - `density`: an axial force proportional to the oil's density (0.5-2 mN
//!   at the median density; the density drawn per case, x0.9-1.1).
//!
//! Per seed: **found** (every true place located in an accepted feature),
//! **placed right** (found, and no law at another place, no catalogue
//! effect), **at the floor** (the last step), **wrong** (a law at a place
//! the truth does not touch, or a catalogue effect named).
//!
//! `FIRST_SEED=1601 ONLY=three cargo run --release -p swimbot --example
//! discovery_subsets` (held-out ranges: three 1601, constant 1611, density
//! 1621; development 1701 for every category). `VERBOSE=1` prints each
//! verdict's note.

#[path = "../tests/fixtures/drawn.rs"]
mod drawn;

use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Instant;
use swimbot::data::quantities::FIELDS;
use swimbot::data::Dataset;
use swimbot::effects::correction::{Form, LocatedCorrection};
use swimbot::effects::place::Place;
use swimbot::effects::EffectInstance;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::synth::{generate, SynthSettings};

const BODY: &[&str] = &["body_ratio", "body_gap_ratio", "body_over_gap"];
const WALL: &[&str] = &["wire_over_gap", "tail_clearance", "tail_gap_ratio"];

/// A true place and the features accepted there (`&[]`: a constant).
type Want = (&'static str, &'static [&'static str]);

fn rng(seed: u64, salt: u64) -> StdRng {
    StdRng::seed_from_u64(seed.wrapping_mul(999_983).wrapping_add(salt))
}

fn constant_slip(seed: u64) -> EffectInstance {
    let c = LocatedCorrection::new(Place::DriveRate, None, Form::Constant, 1.0, 1.0)
        .expect("a constant fits the drive")
        .leak();
    EffectInstance {
        effect: c,
        values: vec![rng(seed, 11).gen_range(0.80..0.93)],
    }
}

fn density_design(paper: &Dataset, seed: u64) -> Dataset {
    let mut d = drawn::design(paper, seed);
    let mut r = rng(seed, 12);
    for c in &mut d.cases {
        c.density_kg_m3 *= r.gen_range(0.9..1.1);
    }
    d
}

fn density_force(data: &Dataset, seed: u64) -> EffectInstance {
    let rho = FIELDS
        .iter()
        .find(|q| q.id == "density_kg_m3")
        .expect("density is a field");
    let mut v: Vec<f64> = data.cases.iter().map(|c| c.density_kg_m3).collect();
    v.sort_by(f64::total_cmp);
    let c = LocatedCorrection::new(
        Place::LoadForce,
        Some(rho),
        Form::Proportional,
        v[v.len() / 2],
        1.0,
    )
    .expect("a proportional load")
    .leak();
    let mut r = rng(seed, 13);
    let sign = if r.gen_bool(0.5) { 1.0 } else { -1.0 };
    EffectInstance {
        effect: c,
        values: vec![sign * r.gen_range(0.5..2.0)],
    }
}

fn truth(cat: &str, seed: u64) -> (Model, Dataset, Vec<Want>) {
    let paper = swimbot::data::paper();
    let base = Model::base();
    match cat {
        "three" => (
            base.with_effect(drawn::body_law(seed))
                .with_effect(drawn::shear_law(seed))
                .with_effect(drawn::tail_wall_drag(seed)),
            drawn::design(&paper, seed),
            vec![
                ("body.D_x", BODY),
                ("tail.viscosity", &["shear_rate"]),
                ("tail.drag", WALL),
            ],
        ),
        "constant" => (
            base.with_effect(constant_slip(seed))
                .with_effect(drawn::tail_wall_drag(seed)),
            drawn::design(&paper, seed),
            vec![("drive.rate", &[]), ("tail.drag", WALL)],
        ),
        "density" => {
            let d = density_design(&paper, seed);
            let f = density_force(&d, seed);
            (
                base.with_effect(f),
                d,
                vec![("load.force", &["density_kg_m3"])],
            )
        }
        _ => panic!("unknown category {cat}"),
    }
}

fn main() {
    let first: u64 = std::env::var("FIRST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1701);
    let only = std::env::var("ONLY").ok();
    let verbose = std::env::var("VERBOSE").is_ok();
    println!("| category | seeds | found | placed right | at the floor | wrong | median s per diagnosis |");
    println!("|---|---|---|---|---|---|---|");
    for cat in ["three", "constant", "density"] {
        if only.as_deref().is_some_and(|o| o != cat) {
            continue;
        }
        let (mut found, mut right, mut floor, mut wrong) = (0, 0, 0, 0);
        let mut times = Vec::new();
        for seed in first..first + 10 {
            let (model, design, want) = truth(cat, seed);
            let settings = SynthSettings {
                seed,
                ..Default::default()
            };
            let data = generate(&model, &design, settings).expect("synth");
            let t = Instant::now();
            let d =
                diagnose(&Model::base(), &data, &DiagnoseSettings::default()).expect("diagnose");
            times.push(t.elapsed().as_secs_f64());
            let v = &d.verdict;
            let hit = |(p, feats): &Want| {
                v.located.iter().any(|l| {
                    l.place == *p
                        && match l.feature {
                            None => feats.is_empty(),
                            Some(f) => feats.contains(&f),
                        }
                })
            };
            let all = want.iter().all(hit);
            let stray = v
                .located
                .iter()
                .any(|l| !want.iter().any(|(p, _)| *p == l.place))
                || v.steps.iter().any(|s| s.kind == "catalogue");
            let at_floor = v.steps.last().is_some_and(|s| s.at_noise_floor);
            found += all as u32;
            right += (all && !stray) as u32;
            floor += at_floor as u32;
            wrong += stray as u32;
            let set: Vec<String> = v.steps.iter().map(|s| s.name.clone()).collect();
            eprintln!(
                "{cat} seed {seed}: {} found={all} stray={stray} floor={at_floor} [{}]",
                v.kind.name(),
                set.join("; ")
            );
            if verbose {
                eprintln!("  {}", v.note);
            }
        }
        times.sort_by(f64::total_cmp);
        println!(
            "| {cat} | {first}-{} | {found}/10 | {right}/10 | {floor}/10 | {wrong}/10 | {:.1} |",
            first + 9,
            times[times.len() / 2]
        );
    }
}
