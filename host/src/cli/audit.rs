//! `swimbot audit`: checks of the data themselves (geometry consistency,
//! ratio tests against the model family, influence and outliers); see
//! [`crate::workbench::audit`].

use super::model_args::{DataArgs, ModelArgs};
use super::output::{print_csv, print_json, TableJsonCsv};
use super::CliError;
use crate::workbench::audit::{audit, Audit, AuditSettings};
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
    #[arg(long, default_value_t = 256)]
    pub family_samples: usize,
    /// Seed of the family's Latin hypercube (the same seed gives the same audit).
    #[arg(long, default_value_t = 12)]
    pub seed: u64,
    /// Refuse the audit when its estimated run time (from timed predictions
    /// of the model before the work) is longer [default: no limit; an audit
    /// estimated over 10 s is announced on stderr].
    #[arg(long, value_name = "SECONDS")]
    pub max_seconds: Option<f64>,
}

pub fn run(a: AuditArgs) -> Result<(), CliError> {
    if !(16..=100_000).contains(&a.family_samples) {
        return Err(CliError::input(format!(
            "--family-samples must be between 16 and 100000, got {}",
            a.family_samples
        )));
    }
    let budget = super::budget::parse_budget(a.max_seconds)?;
    let data = a.data.load()?;
    let model = a.model.model()?;
    super::budget::check(
        &format!("the audit of {} cases", data.cases.len()),
        estimate_seconds(&model, &data, a.family_samples),
        budget,
    )?;
    let settings = AuditSettings {
        family_samples: a.family_samples,
        seed: a.seed,
    };
    let spinner = crate::progress::spinner("audit");
    let report = audit(&model, &data, &settings)?;
    spinner.finish_and_clear();
    match a.format {
        TableJsonCsv::Json => print_json(&report),
        TableJsonCsv::Csv => print_csv(&report.flags)?,
        TableJsonCsv::Table => print_table(&report),
    }
    Ok(())
}

/// Predictions the audit makes per case beyond the family's: the input
/// bands and the candidates' multi-start fits (counted on the paper data:
/// about 4 000), and per case pair when the leave-one-out fits are exact.
const PREDICTIONS_PER_CASE: f64 = 4_000.0;
const PREDICTIONS_PER_PAIR_EXACT: f64 = 600.0;

/// The audit's run time: a timed prediction of every case (at most 16)
/// times the predictions it will make, over the cores.
fn estimate_seconds(
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
    let per = super::budget::seconds_per_call(sample, |i| {
        let _ = model.predict(&data.cases[i * n / sample]);
    });
    let first_solves = (cold - per).max(0.0) * n as f64;
    let exact = n <= crate::workbench::audit_loo::EXACT_MAX_CASES;
    let per_case = PREDICTIONS_PER_CASE
        + samples as f64
        + if exact {
            PREDICTIONS_PER_PAIR_EXACT * n as f64
        } else {
            0.0
        };
    first_solves + per * per_case * n as f64 / rayon::current_num_threads() as f64
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
