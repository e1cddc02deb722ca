//! `swimbot audit`: checks of the data themselves (geometry consistency,
//! ratio tests against the model family, influence and outliers); see
//! [`crate::workbench::audit`].

use super::model_args::{DataArgs, ModelArgs};
use super::output::{print_csv, print_json, TableJsonCsv};
use super::CliError;
use crate::provenance::Inputs;
use crate::workbench::audit::{audit, Audit, AuditSettings};
use crate::workbench::progress::Progress;
use clap::Args;

#[derive(Args, Debug)]
pub struct AuditArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// The base of the model family (the catalogue's cheap effects are added to it).
    #[command(flatten)]
    pub model: ModelArgs,
    /// Output format on stdout (json: the whole audit; csv: one row per flag, `case,kind,detail,severity`).
    #[arg(long, value_enum, default_value = "table")]
    pub format: TableJsonCsv,
    /// Members of the model family sampled for the ratio test.
    #[arg(long, default_value_t = 256, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub family_samples: usize,
    /// Seed of the family's Latin hypercube (the same seed gives the same audit).
    #[arg(long, default_value_t = 12, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<u64>)]
    pub seed: u64,
    /// Refuse the audit when its estimated run time (from timed predictions
    /// of the model before the work) is longer [default: no limit; an audit
    /// estimated over 10 s is announced on stderr].
    #[arg(long, value_name = "SECONDS")]
    pub max_seconds: Option<f64>,
    #[command(flatten)]
    pub likelihood: super::likelihood::LikelihoodArgs,
}

pub fn run(a: AuditArgs, inputs: &Inputs) -> Result<(), CliError> {
    let data = a.data.load(inputs)?;
    let spinner = crate::progress::stages(crate::workbench::audit::AUDIT_STAGES, "audit");
    let report = audited(
        &a,
        &data,
        Some(crate::progress::to_bar(&spinner, "audit: ")),
        inputs,
    )?;
    spinner.finish_and_clear();
    match a.format {
        TableJsonCsv::Json => print_json(&report, inputs),
        TableJsonCsv::Csv => print_csv(&report.flags, inputs)?,
        TableJsonCsv::Table => print_table(&report),
    }
    Ok(())
}

/// `audit`'s work on `data` with the flags in `a` (its `--data` is not
/// read), its stages told to `progress`. The Python package calls it too,
/// so that its numbers are the command's.
pub fn audited(
    a: &AuditArgs,
    data: &crate::data::Dataset,
    progress: Option<Progress>,
    inputs: &Inputs,
) -> Result<crate::workbench::audit::Audit, CliError> {
    if !(16..=100_000).contains(&a.family_samples) {
        return Err(CliError::input(format!(
            "--family-samples must be between 16 and 100000, got {}",
            a.family_samples
        )));
    }
    let budget = super::budget::parse_budget(a.max_seconds)?;
    let data = data.clone();
    let model = a.model.model(inputs)?;
    super::budget::check(
        &format!("the audit of {} cases", data.cases.len()),
        estimate_seconds(&model, &data, a.family_samples),
        budget,
    )?;
    let settings = AuditSettings {
        family_samples: a.family_samples,
        seed: a.seed,
        likelihood: a.likelihood.get(),
        progress,
    };
    Ok(audit(&model, &data, &settings)?)
}

/// The audit's predictions per case beyond the family's `samples + 1`
/// (the input bands, the candidates' multi-start fits, the leave-one-out
/// refits), counted on the plain model (`base`, nine candidates) with a
/// per-thread counter of force balances (`model::force_balances_on_this_thread`):
/// exact leave-one-out refits (up to 40 cases) make about
/// `959 + 85 n` per case (6, 12, 24, 40 cases: 1 470, 2 010, 2 982, 4 366),
/// the one-step deletion about 1 100 (41 to 1 000 cases: 1 083 to 1 123).
/// The test `the_counted_predictions_match_the_audits_own` holds the count
/// to a factor of 1.5 on data it was not fitted to. A base that already
/// has effects leaves fewer candidates (`paper`: 0.4 of the count) but costs
/// more per prediction; its estimate was within a factor of 2 (100 cases).
pub fn predictions(cases: usize, samples: usize) -> (f64, f64) {
    let n = cases as f64;
    let family = n * (samples as f64 + 1.0);
    let per_case = if cases <= crate::workbench::audit::loo::EXACT_MAX_CASES {
        959.0 + 85.0 * n
    } else {
        1_100.0
    };
    (family, per_case * n)
}

/// CPU seconds of the audit's work around each of its non-family
/// predictions (fits, leave-one-out algebra, noise floors), in units of
/// one prediction of the plain model on a paper case: measured as
/// `(CPU s of the audit - family predictions) / counted predictions / that
/// prediction's CPU s`, on one thread, `base` model, synthetic cases
/// (`cargo bench -p swimbot --bench audit` holds both figures): 3.5 with
/// exact leave-one-out (24-40 cases; a fixed 0.03 s dominates below), 16
/// with the one-step deletion (100-1 000 cases: 15.7-17.4 times 0.25 us).
/// The benchmark, on both threads of a machine under a load of 13, gave
/// 1.46 us a prediction and 2.19 s for 100 cases: 27 per prediction, the
/// contention's share; the estimate is for a machine the run has to itself.
const OVERHEAD_EXACT: f64 = 3.5;
const OVERHEAD_ONE_STEP: f64 = 16.0;

/// The audit's run time on this machine's cores: the counted predictions
/// ([`predictions`]) at the model's own timed cost, plus the overhead in
/// timed predictions of the plain model, plus each geometry's first,
/// wall-solving prediction once ([`geometries_of`]).
pub(super) fn estimate_seconds(
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    samples: usize,
) -> f64 {
    let n = data.cases.len();
    let sample = n.min(16);
    // The first prediction of a geometry may solve and cache a wall-resolved
    // matrix (seconds); every later one of the thousands the audit makes
    // reads the cache (microseconds). Timing cold calls as if all were cold
    // announced 41 min for an audit of the physics preset that took 6 s:
    // the cold cost is counted once per case, the warm one per prediction.
    let start = std::time::Instant::now();
    for i in 0..sample {
        let _ = model.predict(&data.cases[i * n / sample]);
    }
    let cold = start.elapsed().as_secs_f64() / sample.max(1) as f64;
    // A prediction takes a fraction of a microsecond: time many.
    let calls = 64 * sample.max(1);
    let per = super::budget::seconds_per_call(calls, |i| {
        let _ = model.predict(&data.cases[(i % sample.max(1)) * n / sample.max(1)]);
    });
    let plain = crate::model::Model::base();
    let reference = super::budget::seconds_per_call(1_024, |i| {
        let _ = plain.predict(&data.cases[i % n]);
    });
    let geometries: usize = data.cases.iter().map(geometries_of).sum();
    let first_solves = (cold - per).max(0.0) * geometries as f64;
    let overhead = if n <= crate::workbench::audit::loo::EXACT_MAX_CASES {
        OVERHEAD_EXACT
    } else {
        OVERHEAD_ONE_STEP
    };
    let (family, rest) = predictions(n, samples);
    let work = family * per + rest * (per + overhead * reference);
    (first_solves + work + pair_seconds(n, samples)) / rayon::current_num_threads() as f64
        + FLOORS * crate::workbench::noise::floor_seconds(quantities(data))
}

/// The Monte Carlo noise floors an audit draws, at most: the outlier
/// check's one set of draws (every case left out from it), and for each
/// of the bad-run checks (in measurement and in combined standard errors,
/// whose degrees of freedom differ) the floor over every quantity and the
/// floor over those left without the named runs. The test
/// `the_counted_floors_bound_the_audits_own` holds an audit to it.
const FLOORS: f64 = 5.0;

fn quantities(data: &crate::data::Dataset) -> usize {
    crate::workbench::noise::error_dofs(data).len()
}

/// CPU seconds of the ratio test's pair loop
/// ([`crate::workbench::audit::ratio`]): for each quantity, every pair of
/// cases folds the members' ratios into a range, `n (n - 1) / 2` pairs of
/// `samples + 1` divisions. Negligible up to a few hundred cases, it is
/// most of an audit of 10 000 (5e7 pairs a quantity): the estimate that
/// left it out said 19 s for a run of 131 s. Timed here on the same fold.
fn pair_seconds(cases: usize, samples: usize) -> f64 {
    let members = samples + 1;
    let a: Vec<f64> = (0..members).map(|i| 1.0 + i as f64 * 1e-3).collect();
    let b: Vec<f64> = (0..members).map(|i| 2.0 - i as f64 * 1e-3).collect();
    let mut sink = 0.0;
    let per_pair = super::budget::seconds_per_call(4_096, |i| {
        let (lo, hi) = a
            .iter()
            .zip(&b)
            .map(|(x, y)| x / (y + i as f64 * 1e-12))
            .filter(|x| x.is_finite())
            .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)));
        sink += lo + hi;
    });
    std::hint::black_box(sink);
    let pairs = cases as f64 * (cases as f64 - 1.0) / 2.0;
    2.0 * pairs * per_pair
}

/// The distinct geometries the audit predicts a case at: its own, and two
/// per uncertain input for the input bands (`workbench::propagate`), each
/// a cold wall-resolved solve for a costly model (the physics preset's 6
/// paper cases: 78 geometries, 10.8 CPU s cold, where counting 6 had
/// announced 1 s). The rate and the viscosity change no solve (the cached
/// matrices are per 1 Pa s and do not depend on the rate); the other
/// inputs change the tail's or the body's, so this counts up to twice the
/// solves there are (measured 1.4 times: 78 counted for 9.4 cases' worth
/// of cold CPU time).
pub(super) fn geometries_of(case: &crate::data::Case) -> usize {
    let solving = case
        .inputs
        .nonzero(case)
        .iter()
        .filter(|(f, _)| !matches!(*f, "frequency_hz" | "viscosity_pa_s"))
        .count();
    1 + 2 * solving
}

fn print_table(a: &Audit) {
    println!(
        "data:   {}\nfamily: {} + any of {{{}}}\n",
        a.dataset,
        a.model,
        a.ratio.family_effects.join(", ")
    );
    if !a.chords.is_empty() {
        println!("chord length implied by the recorded helix (the chord was kept fixed):");
        println!(
            "  {:<12} {:>16} {:>10} {:>8} {:>6}",
            "case", "ell ± sd mm", "ref mm", "diff", "z"
        );
        for c in &a.chords {
            println!(
                "  {:<12} {:>16} {:>10} {:>+7.1}% {:>+6.1}",
                c.case,
                crate::format::fmt_value_unc(c.chord_mm, c.chord_sd_mm),
                crate::format::fmt_sig(c.reference_mm, 4),
                100.0 * c.rel_diff,
                c.z
            );
        }
        println!();
    }
    println!(
        "ratio test: {} pairs tested against {} family members ({} with finite predictions), {} out of range",
        a.ratio.pairs_tested, a.ratio.members, a.ratio.members_used, a.ratio.pairs_out_of_range
    );
    println!(
        "{}",
        super::likelihood::minimised_line_of(&a.influence.likelihood)
    );
    println!(
        "influence: best-supported model on all cases: {}",
        a.influence
            .conclusion
            .as_deref()
            .unwrap_or("undecided (no candidate ahead by 4 in AICc)")
    );
    println!();
    if a.flags.is_empty() {
        println!("no flags: the data are consistent with themselves and with the model family");
        return;
    }
    println!("{} flag(s):", a.flags.len());
    for f in &a.flags {
        println!("  [{:?}] {}: {}", f.severity, f.kind, f.detail);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{by_name, EffectInstance};
    use crate::model::{force_balances_on_this_thread, Model};
    use crate::workbench::synth::{generate, SynthSettings};

    /// `n` cases of fresh geometry (not the calibration's: wavelengths,
    /// amplitudes and rates spread by a golden-ratio walk), measured from a
    /// truth with buoyancy and wall contact, 5 % noise, its own seed.
    fn fresh(n: usize) -> crate::data::Dataset {
        let paper = crate::data::paper();
        let mut design = paper.clone();
        design.cases = (0..n)
            .map(|i| {
                let mut c = paper.cases[(i * 5) % 6].clone();
                let u = (i as f64 * 0.618_034).fract();
                c.id = format!("f{i}");
                c.wavelength_mm *= 0.85 + 0.3 * u;
                c.amplitude_mm *= 0.9 + 0.15 * (1.0 - u);
                c.frequency_hz *= 0.7 + 0.6 * (u * 7.0).fract();
                c
            })
            .collect();
        let truth = Model::base()
            .with_effect(EffectInstance::default_of(by_name("buoyancy").unwrap()))
            .with_effect(EffectInstance::default_of(by_name("wall-contact").unwrap()));
        let s = SynthSettings {
            noise_rel: 0.05,
            seed: 97,
            ..SynthSettings::default()
        };
        generate(&truth, &design, s).unwrap()
    }

    /// The audit's settings in these tests: a small family.
    const COUNTED: AuditSettings = AuditSettings {
        family_samples: 16,
        seed: 5,
        likelihood: crate::workbench::robust::Likelihood::Gaussian,
        progress: None,
    };

    /// How much the per-thread counter `per_thread` grows while the audit
    /// of `data` runs on a pool of its own (other tests' work does not count).
    fn counted_in_audit(data: &crate::data::Dataset, per_thread: fn() -> u64) -> f64 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let count = || -> u64 { pool.broadcast(|_| per_thread()).iter().sum() };
        let before = count();
        pool.install(|| audit(&Model::base(), data, &COUNTED).unwrap());
        (count() - before) as f64
    }

    /// The floors an audit draws, counted per thread on a pool of its own,
    /// against the estimate's [`FLOORS`]; a dataset whose cases each have
    /// their own degrees of freedom (combined with the inputs') once drew
    /// one floor per case.
    #[test]
    fn the_counted_floors_bound_the_audits_own() {
        let mut data = fresh(45);
        // Trials that differ from case to case (more floors if each were drawn alone).
        for (i, c) in data.cases.iter_mut().enumerate() {
            if let Some(m) = c.u_mm_s.as_mut() {
                m.trials = 3 + (i as u32 % 7);
            }
        }
        let drawn = counted_in_audit(&data, crate::workbench::noise::floors_drawn_on_this_thread);
        assert!(
            (1.0..=FLOORS).contains(&drawn),
            "{drawn} floors drawn, {FLOORS} estimated"
        );
    }

    /// The estimate's count of predictions against the audit's own, counted
    /// per thread on a pool of its own (other tests' predictions do not
    /// count): a count, not a timing, so it holds on any machine.
    #[test]
    fn the_counted_predictions_match_the_audits_own() {
        // One size with exact leave-one-out refits, one with the one-step deletion.
        for n in [9, 42] {
            let made = counted_in_audit(&fresh(n), force_balances_on_this_thread);
            let (family, rest) = predictions(n, COUNTED.family_samples);
            let ratio = (family + rest) / made;
            println!(
                "{n} cases: {made} predictions made, {} estimated",
                family + rest
            );
            assert!(
                (1.0 / 1.5..=1.5).contains(&ratio),
                "{n} cases: {made} predictions made, {} estimated",
                family + rest
            );
        }
    }
}
