//! Could the laws at several places be screened together on the response
//! table? The table holds each place's answer alone; a joint screen would
//! combine them. In the log-additive combination each case's quantity
//! under laws at several places is the base prediction times each law's
//! own ratio to it,
//!
//! `y_add = y0 * prod_i (y_i / y0)`,
//!
//! exact when the places act on the quantity as independent factors. For
//! the drawn three-effect truth of the recovery study (body drag `D_x (1 +
//! a (D_b/D_ch)^q)`, a shear-thinning tail oil and a tail drag rising near
//! the wall, host/tests/fixtures/drawn.rs) this compares `y_add` with the
//! model's exact answer to all three, in standard errors of the measured
//! means: `chi2(add - exact)` beside `chi2(base - exact)`, how far the
//! three effects move the prediction, and the noise floor.
//!
//! A measurement for the design of a joint screen (docs/discovery.md, "Is
//! a three-effect miss the search's or the data's?"), not a check
//! `diagnose` runs.
//!
//! `FIRST_SEED=1701 cargo run --release -p swimbot --example
//! discovery_additive_screen`; `SEEDS=n` runs n seeds from the first (10).

#[path = "../tests/fixtures/drawn.rs"]
mod drawn;

use swimbot::data::Dataset;
use swimbot::model::Model;
use swimbot::workbench::compare::case_residuals;
use swimbot::workbench::noise::{chi2_noise_floor, error_dofs};

/// Each measured quantity of each case: its predicted value and the
/// standard error of its measured mean.
fn predicted(model: &Model, data: &Dataset) -> Vec<(f64, f64)> {
    data.cases
        .iter()
        .flat_map(|case| {
            let p = model.predict(case).expect("the drawn model predicts");
            case_residuals(case, &p)
                .into_iter()
                .map(|(_, r)| (r.predicted, r.sigma))
        })
        .collect()
}

/// `sum ((a - b) / sigma)^2`.
fn chi2_between(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    a.iter()
        .zip(b)
        .map(|((ya, s), (yb, _))| ((ya - yb) / s).powi(2))
        .sum()
}

/// The log-additive combination of the single-law answers `ys` on `y0`.
fn log_additive(y0: &[(f64, f64)], ys: &[Vec<(f64, f64)>]) -> Vec<(f64, f64)> {
    y0.iter()
        .enumerate()
        .map(|(o, &(y, s))| (ys.iter().fold(y, |acc, yi| acc * yi[o].0 / y), s))
        .collect()
}

fn row(seed: u64, base: &Model, paper: &Dataset) -> String {
    let laws = drawn::three_laws(seed);
    let (truth, data) = drawn::three_effect_data(base, paper, seed);
    let y0 = predicted(base, &data);
    let exact = predicted(&truth, &data);
    let alone: Vec<Vec<(f64, f64)>> = laws
        .iter()
        .map(|l| predicted(&base.clone().with_effect(l.clone()), &data))
        .collect();
    let add = log_additive(&y0, &alone);
    // Each pair combined, against the model's answer to the pair.
    let pairs: Vec<String> = [(0, 1), (0, 2), (1, 2)]
        .iter()
        .map(|&(i, j)| {
            let m = base
                .clone()
                .with_effect(laws[i].clone())
                .with_effect(laws[j].clone());
            let pair = log_additive(&y0, &[alone[i].clone(), alone[j].clone()]);
            format!("{:.1}", chi2_between(&pair, &predicted(&m, &data)))
        })
        .collect();
    let n = exact.len();
    let floor = chi2_noise_floor(&error_dofs(&data), 0, 0.95).unwrap_or(f64::NAN);
    let worst = add
        .iter()
        .zip(&exact)
        .map(|((a, _), (e, _))| ((a - e) / e).abs())
        .fold(0.0, f64::max);
    format!(
        "| {seed} | {n} | {:.0} | {:.1} | {:.2} % | {} | {floor:.1} |",
        chi2_between(&y0, &exact),
        chi2_between(&add, &exact),
        100.0 * worst,
        pairs.join(" / "),
    )
}

fn main() {
    let base = Model::base();
    let paper = swimbot::data::paper();
    println!("| seed | quantities | chi2(base - exact) | chi2(add - exact), all three | largest relative error | chi2(add - exact), pairs body+oil / body+wall / oil+wall | noise floor |");
    println!("|---|---|---|---|---|---|---|");
    for seed in drawn::seeds_from_env(1701) {
        println!("{}", row(seed, &base, &paper));
    }
}
