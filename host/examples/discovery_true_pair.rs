//! Does the data single out what `diagnose` locates? For the drawn
//! two-effect truth (body drag `D_x x (1 + a (D_b/D_ch)^q)` and a
//! shear-thinning tail oil, host/tests/fixtures/drawn.rs), each seed's
//! verdict is set beside the TRUE pair: the best law at `body.D_x` in a
//! body feature and the best at `tail.viscosity` in the shear rate (each
//! taken from the search beyond the catalogue, the second on top of the
//! first, both orders), refitted jointly. Both are scored by the key the
//! backfitting uses, `AICc + sum 2 ln M` (`M`: the laws screened for a law,
//! the catalogue's size for a catalogue effect), and the noise floor.
//!
//! This knows the truth and is a measurement, not a check `diagnose` runs
//! (docs/discovery.md, "Does the data single out the found set?").
//!
//! `cargo run --release -p swimbot --example discovery_true_pair`;
//! `FIRST_SEED=201` (default) starts the ten seeds there.

#[path = "../tests/fixtures/drawn.rs"]
mod drawn;

use swimbot::data::Dataset;
use swimbot::model::Model;
use swimbot::workbench::candidate::candidates;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::discovery::{aicc, discover, DiscoverySettings, Located, Reference};
use swimbot::workbench::fit::{fit_with, free_params_of};
use swimbot::workbench::noise::{chi2_noise_floor, error_dofs};
use swimbot::workbench::robust::Likelihood;
use swimbot::workbench::synth::{generate, SynthSettings};

const BODY: &[&str] = &["body_ratio", "body_gap_ratio", "body_over_gap"];
const SHEAR: &[&str] = &["shear_rate"];

type Floor<'a> = &'a (dyn Fn(usize) -> Option<f64> + Sync);

/// The best law at `place` in one of `features`, on top of `model`; every
/// candidate is refitted exactly so that a place the screen ranks low is
/// still found.
fn best_at(
    model: &Model,
    data: &Dataset,
    reference: (f64, usize),
    floor: Floor,
    place: &str,
    features: &[&str],
) -> Option<Located> {
    let s = DiscoverySettings {
        top: 400,
        ..Default::default()
    };
    let r = Reference {
        chi2: reference.0,
        k: reference.1,
        floor,
        likelihood: Likelihood::Gaussian,
    };
    let d = discover(model, data, &r, &s).ok()?;
    d.located
        .into_iter()
        .find(|l| l.place == place && l.feature.as_deref().is_some_and(|f| features.contains(&f)))
}

/// The true pair in the order given, refitted jointly: (chi2, k, at the
/// floor, AICc + twice `charge`, the `2 ln M` of one law).
fn true_pair(
    base: &Model,
    data: &Dataset,
    chi2_0: f64,
    floor: Floor,
    order: [(&str, &[&str]); 2],
    charge: f64,
) -> Option<(f64, usize, bool, f64)> {
    let a = best_at(base, data, (chi2_0, 0), floor, order[0].0, order[0].1)?;
    let ka = a.params.len();
    let b = best_at(
        &a.model,
        data,
        (a.score.chi2, ka),
        floor,
        order[1].0,
        order[1].1,
    )?;
    let added: Vec<usize> = (base.effects.len()..b.model.effects.len()).collect();
    let free = free_params_of(&b.model, &added);
    let f = fit_with(&b.model, data, None, &free, false, Likelihood::Gaussian).ok()?;
    let n = swimbot::workbench::compare::compare(&f.model, data, free.len())
        .ok()?
        .summary
        .n;
    let k = free.len();
    let at = floor(k).is_some_and(|fl| f.chi2 <= fl);
    Some((f.chi2, k, at, aicc(f.chi2, n, k)? + 2.0 * charge))
}

fn main() {
    let first: u64 = std::env::var("FIRST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(201);
    let base = Model::base();
    let paper = swimbot::data::paper();
    let n_cat = candidates(&swimbot::effects::Catalogue::builtin(), &base, true)
        .len()
        .max(1) as f64;
    println!("| seed | verdict | found set (places) | found at floor | found AICc + charges | true pair chi2 (floor) | true pair AICc + charges | found - true |");
    println!("|---|---|---|---|---|---|---|---|");
    for seed in first..first + 10 {
        let truth = base
            .clone()
            .with_effect(drawn::body_law(seed))
            .with_effect(drawn::shear_law(seed));
        let design = drawn::design(&paper, seed);
        let settings = SynthSettings {
            seed,
            ..Default::default()
        };
        let data = generate(&truth, &design, settings).expect("synth");
        let s = DiagnoseSettings::default();
        let d = diagnose(&base, &data, &s).expect("diagnose");
        let n = d.comparison.summary.n;
        let q0 = chi2_noise_floor(&error_dofs(&data), 0, s.level);
        let floor = move |k: usize| q0.filter(|_| n > k).map(|q| q * (n - k) as f64 / n as f64);
        let laws = d.discovery.as_ref().map_or(1, |x| x.screened).max(1) as f64;
        let steps = &d.verdict.steps;
        let charges: f64 = steps
            .iter()
            .map(|st| 2.0 * if st.kind == "located" { laws } else { n_cat }.ln())
            .sum();
        let found = steps.last().and_then(|st| st.aicc).map(|a| a + charges);
        let places: Vec<&str> = steps
            .iter()
            .map(|st| st.name.split(" = ").next().unwrap_or(&st.name))
            .collect();
        let at = steps.last().is_some_and(|st| st.at_noise_floor);
        let orders = [
            [("body.D_x", BODY), ("tail.viscosity", SHEAR)],
            [("tail.viscosity", SHEAR), ("body.D_x", BODY)],
        ];
        let best = orders
            .into_iter()
            .filter_map(|o| true_pair(&base, &data, d.baseline.chi2, &floor, o, 2.0 * laws.ln()))
            .min_by(|a, b| a.3.total_cmp(&b.3));
        let (pair_chi2, pair_key) = match best {
            Some((c, k, _, key)) => (format!("{c:.1} ({:.1})", floor(k).unwrap_or(f64::NAN)), key),
            None => ("not found".into(), f64::NAN),
        };
        let found_s = found.map_or("-".into(), |f| format!("{f:.1}"));
        let diff = found.map_or("-".into(), |f| format!("{:+.1}", f - pair_key));
        println!(
            "| {seed} | {:?} | {} | {at} | {found_s} | {pair_chi2} | {pair_key:.1} | {diff} |",
            d.verdict.kind,
            places.join(", "),
        );
    }
}
