//! Recovery study of the search over subsets (docs/discovery.md,
//! "Measured: the recovery study"): drawn truths with one to three
//! effects, diagnosed from the base model, ten seeds per category.
//!
//! Categories (constants and designs drawn per seed, host/tests/fixtures/
//! drawn.rs: 36 cases, 2 % noise per trial, five trials):
//! - `three`: body drag `D_x (1 + a (D_b/D_ch)^q)`, a shear-thinning tail
//!   oil and a tail drag rising near the wall, all at once;
//! - `constant`: a constant (drawn per seed: a drive slip, the tail turning
//!   at 0.80-0.93 of the recorded rate; an axial force; or a bearing torque
//!   on the body, each load 0.5-2 times the place's load scale, either
//!   sign) with a channel law (the tail drag rising near the wall) or a
//!   pitch law (`tail.torque = 1 + a (pitch/median)^q`, a 0.2-0.6, q 1-2),
//!   drawn per seed;
//! - `density`: an axial force proportional to the oil's density (0.5-2 mN
//!   at the median density, either sign; the density drawn per case,
//!   x0.9-1.1);
//! - `slip`: a drive slip set by the tail's load torque, `f_true =
//!   f_recorded (1 - tau_load/tau_s)`, the stall torque drawn per seed
//!   (host/tests/fixtures/load_slip.rs: the largest slip 12-20 %);
//! - `null`: the base model, honest intervals.
//!
//! Scored per seed, from the verdict alone (a catalogue effect counts as
//! the place it acts at when it acts at one: `buoyancy` as `load.force`,
//! `body-correction` as `body.D_x` and `body.E_x`; any other catalogue
//! effect touches no true place):
//! - **truth in the stated set**: every true place is in the verdict's
//!   found set or in one of the sets it states the data cannot tell apart
//!   (for a null: `none-needed`); a second count takes `tail.torque` and
//!   `body.E_x` as one (the reciprocal law: the same model exactly); a
//!   third reads each member of a stated set at every place the verdict
//!   states as its equivalent (`discovery::interpret::equivalents`: also
//!   the speed-only places `body.D_x`, `tail.drag`, `tail.thrust` as one
//!   another), one member for each true place;
//! - **wrong set claimed alone**: a `located` or `identified` verdict whose
//!   set has a place the truth does not touch (with that equivalence; for a
//!   null: any such verdict); a second count only those with a member
//!   none of whose stated readings is a true place;
//! - **located exactly**: a `located` or `identified` verdict whose one set
//!   has exactly the true places (for a null: `none-needed`);
//! - **at the floor**: the verdict's found set (or the base model, for
//!   `none-needed`) is at the noise floor.
//!
//! `FIRST_SEED=1701 cargo run --release -p swimbot --example
//! discovery_subsets` (development: 1701, 1801 and 1901 for every
//! category). Held-out ranges are fixed in docs/discovery.md before each
//! round's code and run once after it is frozen (`ONLY=three
//! FIRST_SEED=2101`, and so on). `VERBOSE=1` prints each
//! verdict's note; `SEEDS=n` runs n seeds from the first (10).

#[path = "../tests/fixtures/drawn.rs"]
mod drawn;
mod held_out;

use held_out::{read_as, readings};
#[path = "../tests/fixtures/load_slip.rs"]
mod load_slip;

use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Instant;
use swimbot::data::quantities::by_id;
use swimbot::data::Dataset;
use swimbot::effects::correction::{Form, LocatedCorrection};
use swimbot::effects::place::Place;
use swimbot::effects::EffectInstance;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, Verdict, VerdictKind};
use swimbot::workbench::discovery::Table;
use swimbot::workbench::synth::{generate, SynthSettings};

fn rng(seed: u64, salt: u64) -> StdRng {
    StdRng::seed_from_u64(seed.wrapping_mul(999_983).wrapping_add(salt))
}

fn field(id: &str) -> &'static swimbot::data::quantities::Quantity {
    by_id(id).expect("a quantity of the dataset")
}

fn median(data: &Dataset, id: &str) -> f64 {
    let q = field(id);
    let mut v: Vec<f64> = data.cases.iter().map(|c| q.of(c)).collect();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn law(
    place: Place,
    feature: Option<&str>,
    form: Form,
    scale: f64,
    values: Vec<f64>,
) -> EffectInstance {
    let c = LocatedCorrection::new(
        place,
        feature.map(|f| swimbot::data::Feature::Quantity(field(f))),
        form,
        scale,
        1.0,
    )
    .expect("the drawn law fits its place");
    EffectInstance {
        effect: std::sync::Arc::new(c).into(),
        values,
    }
}

/// A drawn constant (module docs) and its place.
fn constant(design: &Dataset, seed: u64) -> (EffectInstance, &'static str) {
    let mut r = rng(seed, 11);
    let sign = if r.gen_bool(0.5) { 1.0 } else { -1.0 };
    match r.gen_range(0..3) {
        0 => (
            law(
                Place::DriveRate,
                None,
                Form::Constant,
                1.0,
                vec![r.gen_range(0.80..0.93)],
            ),
            "drive.rate",
        ),
        k => {
            let place = if k == 1 {
                Place::LoadForce
            } else {
                Place::LoadTorque
            };
            let table = Table::build(&Model::base(), design).expect("the base model predicts");
            let size = sign * r.gen_range(0.5..2.0) * table.load_scale(place);
            (
                law(place, None, Form::Constant, 1.0, vec![size]),
                place.name(),
            )
        }
    }
}

/// A channel law or a pitch law, drawn per seed (module docs).
fn channel_or_pitch(design: &Dataset, seed: u64) -> (EffectInstance, &'static str) {
    let mut r = rng(seed, 14);
    if r.gen_bool(0.5) {
        (drawn::tail_wall_drag(seed), "tail.drag")
    } else {
        let pitch = median(design, "pitch_angle_deg");
        let v = vec![r.gen_range(0.2..0.6), r.gen_range(1.0..2.0)];
        (
            law(
                Place::TailTorque,
                Some("pitch_angle_deg"),
                Form::Power,
                pitch,
                v,
            ),
            "tail.torque",
        )
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

fn truth(cat: &str, seed: u64) -> (Model, Dataset, Vec<&'static str>) {
    let paper = swimbot::data::paper();
    let base = Model::base();
    let design = drawn::design(&paper, seed);
    match cat {
        "three" => (
            drawn::three_laws(seed)
                .into_iter()
                .fold(base, |m, l| m.with_effect(l)),
            design,
            vec!["body.D_x", "tail.viscosity", "tail.drag"],
        ),
        "constant" => {
            let (c, at) = constant(&design, seed);
            let (l, lat) = channel_or_pitch(&design, seed);
            (base.with_effect(c).with_effect(l), design, vec![at, lat])
        }
        "density" => {
            let d = density_design(&paper, seed);
            let mut r = rng(seed, 13);
            let sign = if r.gen_bool(0.5) { 1.0 } else { -1.0 };
            let rho = median(&d, "density_kg_m3");
            let f = law(
                Place::LoadForce,
                Some("density_kg_m3"),
                Form::Proportional,
                rho,
                vec![sign * r.gen_range(0.5..2.0)],
            );
            (base.with_effect(f), d, vec!["load.force"])
        }
        "slip" => {
            let mut m = base;
            m.effects.extend(load_slip::load_slip(&design, seed));
            (m, design, vec!["drive.rate"])
        }
        "null" => (base, design, Vec::new()),
        _ => panic!("unknown category {cat}"),
    }
}

/// The places a catalogue effect acts at, for the two whose action is one
/// place's (`buoyancy`: a net axial force; `body-correction`: the body's
/// two resistances); any other catalogue effect stands for itself and
/// touches no true place.
fn catalogue_places(name: &str) -> Vec<String> {
    match name {
        "buoyancy" => vec!["load.force".into()],
        "body-correction" => vec!["body.D_x".into(), "body.E_x".into()],
        _ => vec![name.into()],
    }
}

/// A set's places, catalogue effects read as their places.
fn places_of(set: &[String]) -> Vec<String> {
    let mut v: Vec<String> = set.iter().flat_map(|p| catalogue_places(p)).collect();
    v.sort();
    v.dedup();
    v
}

/// `tail.torque` and `body.E_x` are one model (the torque balance makes a
/// law on one the reciprocal law on the other, exactly): with
/// `exact_equivalents`, either counts for the other.
fn has(set: &[String], place: &str, exact_equivalents: bool) -> bool {
    let twin = match place {
        "tail.torque" => Some("body.E_x"),
        "body.E_x" => Some("tail.torque"),
        _ => None,
    };
    set.iter()
        .any(|x| x == place || (exact_equivalents && twin == Some(x.as_str())))
}

/// Every set the verdict states: the found set (its located places and
/// catalogue effects) and each set it cannot tell from it.
fn stated_sets(v: &Verdict) -> Vec<Vec<String>> {
    stated_names(v).iter().map(|s| places_of(s)).collect()
}

fn stated_names(v: &Verdict) -> Vec<Vec<String>> {
    if !v.sets.is_empty() {
        return v.sets.iter().map(|s| s.places.clone()).collect();
    }
    let mut found: Vec<String> = v.located.iter().map(|l| l.place.to_string()).collect();
    found.extend(
        v.steps
            .iter()
            .filter(|s| s.kind == "catalogue")
            .map(|s| s.name.clone()),
    );
    if let Some(e) = &v.effect {
        found.extend(e.split(" + ").map(str::to_string));
    }
    match v.kind {
        // The single-step rivals: each located law (and catalogue name) is
        // one set.
        VerdictKind::Indistinguishable => v
            .located
            .iter()
            .map(|l| vec![l.place.to_string()])
            .chain(
                v.indistinguishable
                    .iter()
                    .filter(|n| !n.contains(" = "))
                    .map(|n| vec![n.clone()]),
            )
            .collect(),
        _ => vec![found],
    }
}

struct Score {
    in_stated: bool,
    in_stated_equivalent: bool,
    /// The truth is one of the stated sets read with its stated readings.
    in_stated_read: bool,
    wrong_alone: bool,
    /// Claimed alone, with a member none of whose stated readings is a
    /// true place.
    wrong_alone_read: bool,
    exact: bool,
    floor: bool,
}

fn score(v: &Verdict, want: &[&str]) -> Score {
    let sets = stated_sets(v);
    let alone = matches!(v.kind, VerdictKind::Located | VerdictKind::Identified);
    let floor = match v.kind {
        VerdictKind::NoneNeeded => true,
        _ => v.steps.last().map_or(v.explained, |s| s.at_noise_floor),
    };
    if want.is_empty() {
        return Score {
            in_stated: v.kind == VerdictKind::NoneNeeded,
            in_stated_equivalent: v.kind == VerdictKind::NoneNeeded,
            in_stated_read: v.kind == VerdictKind::NoneNeeded,
            wrong_alone: alone,
            wrong_alone_read: alone,
            exact: v.kind == VerdictKind::NoneNeeded,
            floor,
        };
    }
    let within = |eq: bool| sets.iter().any(|s| want.iter().all(|p| has(s, p, eq)));
    let (in_stated, in_stated_equivalent) = (within(false), within(true));
    let found: Vec<String> = sets.first().cloned().unwrap_or_default();
    let touched = |p: &String| want.iter().any(|w| has(std::slice::from_ref(p), w, true));
    let wrong_alone = alone && !found.iter().all(touched);
    let mut w: Vec<String> = want.iter().map(|s| s.to_string()).collect();
    w.sort();
    let exact = alone && found == w;
    Score {
        in_stated,
        in_stated_equivalent,
        in_stated_read: sets.iter().any(|s| read_as(s, want)),
        wrong_alone,
        wrong_alone_read: alone
            && !found
                .iter()
                .all(|p| readings(p).iter().any(|r| want.contains(r))),
        exact,
        floor,
    }
}

fn main() {
    let first: u64 = std::env::var("FIRST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1701);
    let count: u64 = std::env::var("SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let only = std::env::var("ONLY").ok();
    let verbose = std::env::var("VERBOSE").is_ok();
    println!("| category | seeds | truth in the stated set | same, tail.torque = body.E_x | same, read with the stated readings | wrong set claimed alone | same, a member with no true reading | located exactly | at the floor | median s per diagnosis |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for cat in ["three", "constant", "density", "slip", "null"] {
        if only.as_deref().is_some_and(|o| o != cat) {
            continue;
        }
        let (mut stated, mut stated_eq, mut stated_read) = (0, 0, 0);
        let (mut wrong, mut wrong_read, mut exact, mut floor) = (0, 0, 0, 0);
        let mut times = Vec::new();
        for seed in first..first + count {
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
            let s = score(v, &want);
            stated += s.in_stated as u32;
            stated_eq += s.in_stated_equivalent as u32;
            stated_read += s.in_stated_read as u32;
            wrong += s.wrong_alone as u32;
            wrong_read += s.wrong_alone_read as u32;
            exact += s.exact as u32;
            floor += s.floor as u32;
            let sets: Vec<String> = stated_names(v).iter().map(|s| s.join(", ")).collect();
            eprintln!(
                "{cat} seed {seed}: truth [{}] verdict {} sets [{}] in_stated={} (with equivalents {}, read {}) wrong_alone={} (read {}) exact={} floor={}",
                want.join(", "),
                v.kind.name(),
                sets.join(" | "),
                s.in_stated,
                s.in_stated_equivalent,
                s.in_stated_read,
                s.wrong_alone,
                s.wrong_alone_read,
                s.exact,
                s.floor
            );
            if verbose {
                eprintln!("  {}", v.note);
            }
        }
        times.sort_by(f64::total_cmp);
        println!(
            "| {cat} | {first}-{} | {stated}/{count} | {stated_eq}/{count} | {stated_read}/{count} | {wrong}/{count} | {wrong_read}/{count} | {exact}/{count} | {floor}/{count} | {:.1} |",
            first + count - 1,
            times[times.len() / 2]
        );
    }
}
