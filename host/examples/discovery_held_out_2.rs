//! The second held-out batch of discovery (docs/held-out-2.md): twelve
//! kinds of physical effect (K14-K25, `held_out/batch2.rs`), none a kind
//! of batch 1 or of the development sets, drawn as truths on 32 designs
//! (16 single kinds, 8 pairs, 4 threes on 36 cases, 4 fours on 40) and
//! frozen before the search is changed. Two single designs carry a bad
//! run beside the law: one case's rate mis-set, at the end of the feature
//! where the law acts.
//!
//! `MODE=freeze cargo run --release -p swimbot --example
//! discovery_held_out_2` draws every design, checks each truth is
//! detectable without the search (the base model's and the truth's reduced
//! chi-square by `workbench::compare`), writes it to `$OUT/<id>.toml`
//! (`/tmp/held_out_2` unless given) and prints the frozen table.
//! `MODE=check` draws the designs again and compares each hash with the
//! table in docs/held-out-2.md (exit 1 on a difference). `MODE=measure`
//! diagnoses each design once from the base model and prints the scored
//! table (scored as batch 1 is, `held_out/mod.rs`), with the reading of a
//! constant truth and whether a planted bad run was named.

#[path = "held_out/batch2.rs"]
mod batch2;
#[path = "held_out/mod.rs"]
mod held_out;

use batch2::{draw_kind, elastoviscous, vary_for, Kind};
use held_out::{
    expected, load_scale_mn, readings, rng, score, stability, stated, vary, Tally, Truth,
};
use rand::Rng;
use std::sync::Arc;
use std::time::Instant;
use swimbot::data::{Case, Dataset};
use swimbot::effects::EffectInstance;
use swimbot::model::Model;
use swimbot::workbench::compare::compare;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, Diagnosis};
use swimbot::workbench::noise::{chi2_noise_floor, error_dofs};
use swimbot::workbench::synth::{generate, SynthSettings};

/// The 32 frozen designs: (id, seed, kind numbers, cases, bad run).
const DESIGNS: [(&str, u64, &[usize], usize, bool); 32] = [
    ("H201", 5201, &[14], 36, false),
    ("H202", 5202, &[15], 36, false),
    ("H203", 5203, &[16], 36, false),
    ("H204", 5204, &[17], 36, false),
    ("H205", 5205, &[18], 36, false),
    ("H206", 5206, &[19], 36, false),
    ("H207", 5207, &[20], 36, false),
    ("H208", 5208, &[21], 36, false),
    ("H209", 5209, &[22], 36, false),
    ("H210", 5210, &[23], 36, false),
    ("H211", 5211, &[24], 36, false),
    ("H212", 5212, &[25], 36, false),
    ("H213", 5213, &[14], 36, true),
    ("H214", 5214, &[24], 36, true),
    ("H215", 5215, &[19], 36, false),
    ("H216", 5216, &[22], 36, false),
    ("H217", 5217, &[14, 23], 36, false),
    ("H218", 5218, &[15, 21], 36, false),
    ("H219", 5219, &[16, 20], 36, false),
    ("H220", 5220, &[18, 25], 36, false),
    ("H221", 5221, &[19, 22], 36, false),
    ("H222", 5222, &[24, 21], 36, false),
    ("H223", 5223, &[17, 20], 36, false),
    ("H224", 5224, &[21, 14], 36, false),
    ("H225", 5225, &[14, 19, 25], 36, false),
    ("H226", 5226, &[15, 20, 24], 36, false),
    ("H227", 5227, &[16, 18, 23], 36, false),
    ("H228", 5228, &[22, 16, 25], 36, false),
    ("H229", 5229, &[14, 15, 18, 25], 40, false),
    ("H230", 5230, &[16, 19, 20, 21], 40, false),
    ("H231", 5231, &[22, 23, 24, 14], 40, false),
    ("H232", 5232, &[15, 20, 23, 25], 40, false),
];

/// A truth is detectable when the base model's chi-square on its data is
/// at least this many noise floors (the 95 % quantile of a right model's
/// chi-square, Student-t residuals: `workbench::noise`), and every
/// observable member is needed: the rest of the truth, exact, stays above
/// one floor without it.
const BASE_FLOORS: f64 = 2.0;
/// Constants are redrawn (a new stream) at most this often, and only when
/// the drawn truth is not detectable.
const MAX_DRAWS: u64 = 5;

/// The drawn design: the paper's six tails in turn, `n` conditions over
/// them (36: six each; 40: tails 1-4 seven times), each kind's column or
/// field drawn after the condition.
fn design(seed: u64, ks: &[usize], n: usize) -> Dataset {
    let paper = swimbot::data::paper();
    let mut r = rng(seed, 1);
    let mut out = paper.clone();
    out.name = format!("{} (held-out design 2, seed {seed})", paper.name);
    out.cases.clear();
    for j in 0..n {
        let mut v = vary(
            &paper.cases[j % paper.cases.len()],
            j / paper.cases.len(),
            &mut r,
        );
        for k in ks {
            vary_for(*k, &mut v, &mut r);
        }
        v.recorded.values.sort_by(|a, b| a.0.cmp(&b.0));
        out.cases.push(v);
    }
    out
}

/// The bad run: the case second from the end of the feature where the
/// law acts (the second-nearest the closed end; the second-thinnest oil),
/// its rate mis-set by 6-10 % while the recorded rate stays. Returns its
/// index and the factor.
fn plant(seed: u64, d: &Dataset, kind: usize) -> (usize, f64) {
    let feature = |c: &Case| match kind {
        14 => c.recorded.value("window_below_end_mm").unwrap_or(f64::MAX),
        _ => c.viscosity_pa_s,
    };
    let mut order: Vec<usize> = (0..d.cases.len()).collect();
    order.sort_by(|a, b| feature(&d.cases[*a]).total_cmp(&feature(&d.cases[*b])));
    let mut r = rng(seed, 3);
    let shift = r.gen_range(0.06..0.10) * if r.gen_bool(0.5) { 1.0 } else { -1.0 };
    (order[1], 1.0 + shift)
}

struct Drawn {
    kinds: Vec<Kind>,
    data: Dataset,
    want: Vec<&'static str>,
    bad: Option<(String, f64)>,
    /// Reduced chi-squares on the data without the bad run: the base
    /// model's, the truth's, the truth's without its least needed member,
    /// and the noise floor's.
    base_chi2: f64,
    truth_chi2: f64,
    weakest_member_chi2: Option<f64>,
    floor_chi2: f64,
    /// The truth's lowest predicted U (mm/s): the robot climbs in every case.
    min_u_mm_s: f64,
    redraws: u64,
}

fn model_of(kinds: &[Kind]) -> Model {
    kinds.iter().fold(Model::base(), |m, k| {
        m.with_effect(EffectInstance::default_of(Arc::new(Truth(*k))))
    })
}

fn chi2_reduced(m: &Model, d: &Dataset) -> f64 {
    compare(m, d, 0)
        .expect("a held-out model predicts its design")
        .summary
        .chi2_reduced
        .expect("more quantities than parameters")
}

/// The noise floor as a reduced chi-square (no fitted parameter).
fn floor_reduced(d: &Dataset) -> f64 {
    let dofs = error_dofs(d);
    chi2_noise_floor(&dofs, 0, 0.95).expect("quantities to test") / dofs.len() as f64
}

fn min_u_mm_s(m: &Model, d: &Dataset) -> f64 {
    d.cases
        .iter()
        .map(|c| m.predict(c).expect("the truth predicts its design").u_mm_s)
        .fold(f64::INFINITY, f64::min)
}

/// Draw one design's truth and data (attempt `a` of its constants).
fn draw_once(seed: u64, ks: &[usize], n: usize, bad: bool, a: u64, s_ref: f64) -> Drawn {
    let load = load_scale_mn();
    let mut r = rng(seed, 2 + 100 * a);
    let kinds: Vec<Kind> = ks
        .iter()
        .map(|k| draw_kind(*k, &mut r, load, s_ref))
        .collect();
    let mut d = design(seed, ks, n);
    let planted = bad.then(|| plant(seed, &d, ks[0]));
    if let Some((i, f)) = planted {
        d.cases[i].frequency_hz *= f;
    }
    let settings = SynthSettings {
        seed,
        ..Default::default()
    };
    let mut data =
        generate(&model_of(&kinds), &d, settings).expect("the truth predicts its design");
    let mut clean = data.clone();
    if let Some((i, f)) = planted {
        // the recorded rate is the one the lab meant to set
        data.cases[i].frequency_hz /= f;
        clean.cases.remove(i);
    }
    let mut want: Vec<&'static str> = kinds.iter().filter_map(|k| k.place()).collect();
    want.sort();
    want.dedup();
    // detectability on the data without the bad run: the law must show on its own
    let weakest = (0..kinds.len())
        .filter(|i| kinds[*i].place().is_some())
        .map(|i| {
            let rest: Vec<Kind> = (0..kinds.len())
                .filter(|j| *j != i)
                .map(|j| kinds[j])
                .collect();
            chi2_reduced(&model_of(&rest), &clean)
        })
        .reduce(f64::min);
    Drawn {
        floor_chi2: floor_reduced(&clean),
        min_u_mm_s: min_u_mm_s(&model_of(&kinds), &d),
        base_chi2: chi2_reduced(&Model::base(), &clean),
        truth_chi2: chi2_reduced(&model_of(&kinds), &clean),
        weakest_member_chi2: weakest,
        bad: planted.map(|(i, f)| (data.cases[i].id.clone(), f)),
        kinds,
        data,
        want,
        redraws: a,
    }
}

fn detectable(d: &Drawn) -> bool {
    d.want.is_empty()
        || (d.base_chi2 >= BASE_FLOORS * d.floor_chi2
            && d.weakest_member_chi2.is_none_or(|c| c > d.floor_chi2))
}

/// Draw a design, redrawing its constants only while the truth is not
/// detectable or the robot would not climb in some case.
fn draw(seed: u64, ks: &[usize], n: usize, bad: bool, s_ref: f64) -> Drawn {
    let mut d = draw_once(seed, ks, n, bad, 0, s_ref);
    while !(detectable(&d) && d.min_u_mm_s > 0.0) && d.redraws + 1 < MAX_DRAWS {
        d = draw_once(seed, ks, n, bad, d.redraws + 1, s_ref);
    }
    d
}

/// The paper's median elastoviscous number: K18's threshold scale.
fn paper_elastoviscous() -> f64 {
    let mut s: Vec<f64> = swimbot::data::paper()
        .cases
        .iter()
        .map(elastoviscous)
        .collect();
    s.sort_by(f64::total_cmp);
    0.5 * (s[s.len() / 2 - 1] + s[s.len() / 2])
}

/// K23's torque must slow the body's counter-rotation (the swirl turns the
/// body with the tail): a wrong sign would be another effect.
fn check_swirl_sense() {
    let c = &swimbot::data::paper().cases[0];
    let omega = |m: &Model| m.predict(c).expect("the paper's case").omega_body_hz;
    let with = omega(&model_of(&[Kind::BodySwirl { k: 0.2 }]));
    let without = omega(&Model::base());
    assert!(
        with.abs() < without.abs(),
        "the swirl's torque speeds the body up ({with} against {without} Hz): flip SWIRL_SENSE"
    );
}

/// The expected verdict, with the constant and the bad run it names.
fn expected_row(d: &Drawn) -> String {
    let mut e = expected(&d.want);
    for k in d.kinds.iter().filter(|k| k.is_constant()) {
        e += &format!(" (a constant at {})", k.place().unwrap_or("-"));
    }
    if let Some((case, _)) = &d.bad {
        e += &format!("; bad run {case}");
    }
    e
}

fn main() {
    let mode = std::env::var("MODE").unwrap_or_else(|_| "freeze".into());
    let out = std::env::var("OUT").unwrap_or_else(|_| "/tmp/held_out_2".into());
    std::fs::create_dir_all(&out).expect("the output folder");
    let s_ref = paper_elastoviscous();
    check_swirl_sense();
    let frozen = if mode == "check" {
        held_out::frozen_hashes("held-out-2.md")
    } else {
        Vec::new()
    };
    match mode.as_str() {
        "freeze" => {
            println!("| design | seed | kinds | cases | truth | expected verdict | base chi2/nu | truth chi2/nu | weakest member chi2/nu | floor chi2/nu | min U mm/s | redraws | SHA-256 of the drawn data |");
            println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        }
        "measure" => {
            println!("| design | kinds | expected | verdict | stated sets | right | with rivals | wrong alone | floor | constant | data quality | stability | s |");
            println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        }
        _ => {}
    }
    let (mut tally, mut differ) = (Tally::default(), 0);
    for (id, seed, ks, n, bad) in DESIGNS {
        let d = draw(seed, ks, n, bad, s_ref);
        let kinds: Vec<String> = ks.iter().map(|k| format!("K{k}")).collect();
        let hex = held_out::freeze(&out, id, &d.data);
        match mode.as_str() {
            "freeze" => println!(
                "| {id} | {seed} | {} | {n} | {:?}{} | {} | {:.2} | {:.2} | {} | {:.2} | {:.3} | {} | `{hex}` |",
                kinds.join(" + "),
                d.kinds,
                d.bad
                    .as_ref()
                    .map_or(String::new(), |(c, f)| format!(", rate of {c} x{f:.4}")),
                expected_row(&d),
                d.base_chi2,
                d.truth_chi2,
                d.weakest_member_chi2
                    .map_or("-".into(), |c| format!("{c:.2}")),
                d.floor_chi2,
                d.min_u_mm_s,
                d.redraws,
            ),
            "check" => differ += !held_out::same_hash(&frozen, id, &hex) as u32,
            _ => {
                let t = Instant::now();
                let g = diagnose(&Model::base(), &d.data, &DiagnoseSettings::default())
                    .expect("diagnose");
                let secs = t.elapsed().as_secs_f64();
                let s = score(&g.verdict, &d.want);
                tally.add(&s);
                println!(
                    "| {id} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {secs:.1} |",
                    kinds.join(" + "),
                    expected_row(&d),
                    g.verdict.kind.name(),
                    stated(&s),
                    s.right,
                    s.with_rivals,
                    s.wrong_alone,
                    s.at_floor,
                    constant_reading(&g, &d),
                    data_quality(&g, &d),
                    stability(&g.verdict)
                );
            }
        }
    }
    match mode.as_str() {
        "measure" => println!("\n{}", tally.line()),
        "check" if differ > 0 => {
            eprintln!("{differ} designs differ from docs/held-out-2.md");
            std::process::exit(1);
        }
        _ => {}
    }
}

/// How the verdict reads a constant truth: `constant` when the located
/// term at its place has no feature, the feature otherwise.
fn constant_reading(g: &Diagnosis, d: &Drawn) -> String {
    let Some(place) = d
        .kinds
        .iter()
        .find(|k| k.is_constant())
        .and_then(|k| k.place())
    else {
        return String::new();
    };
    g.verdict
        .located
        .iter()
        .find(|l| readings(l.place).contains(&place))
        .map_or("not located".into(), |l| {
            l.feature
                .as_ref()
                .map_or("constant".into(), |f| format!("law in {f}"))
        })
}

/// Whether the planted bad run was named, and how many other cases were.
fn data_quality(g: &Diagnosis, d: &Drawn) -> String {
    let Some((case, _)) = &d.bad else {
        return String::new();
    };
    let named: Vec<&str> = g
        .data_quality
        .bad_runs
        .iter()
        .flat_map(|b| b.runs.iter().map(|r| r.case.as_str()))
        .collect();
    let others = named.iter().filter(|c| *c != case).count();
    format!(
        "{case} named {}, other cases named {others}",
        named.contains(&case.as_str())
    )
}
