//! `swimbot fit`: calibrate effect parameters on chosen cases, report the
//! error on all cases (as the paper calibrated on the B_o/R_body = 0.45 tails).

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, pct, print_csv, print_json, TableJsonCsv};
use super::CliError;
use crate::format::{fmt_estimate, fmt_sig, with_unit};
use crate::provenance::Inputs;
use crate::workbench::compare::compare;
use crate::workbench::fit::{fit_with, free_params_of};
use clap::Args;

#[derive(Args, Debug)]
pub struct FitArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    /// Calibrate on these case ids only (comma-separated) [default: all cases].
    #[arg(long, value_delimiter = ',')]
    pub cases: Vec<String>,
    /// Output format on stdout (csv: one row per calibrated parameter,
    /// `effect,name,unit,value,ci95,at_bound`; the per-case errors of the
    /// calibrated model are `compare --format csv` with the same effects).
    #[arg(long, value_enum, default_value = "table")]
    pub format: TableJsonCsv,
    #[command(flatten)]
    pub likelihood: super::likelihood::LikelihoodArgs,
}

/// What `fit` computes, before anything is printed: the fit, the
/// comparison of the calibrated model on every case, the bad-run test.
/// The Python package calls it too, so that its numbers are the command's.
pub struct Fitted {
    pub result: crate::workbench::fit::FitResult,
    pub all: crate::workbench::compare::Comparison,
    pub lone: Option<crate::workbench::data_quality::bad_runs::BadRuns>,
}

impl Fitted {
    /// `fit --format json`'s document (without the provenance block).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({ "fit": self.result, "comparison": self.all, "bad_runs": self.lone })
    }
}

/// `fit`'s work on `data` with the flags in `a` (its `--data` is not read).
pub fn fitted(
    a: &FitArgs,
    data: &crate::data::Dataset,
    inputs: &Inputs,
) -> Result<Fitted, CliError> {
    let data = data.clone();
    let model = a.model.model(inputs)?;
    if a.model.effects.is_empty() {
        return Err(CliError::input(
            "give the effect(s) to calibrate with --effect NAME",
        ));
    }
    let first_new = model.effects.len() - a.model.effects.len();
    let added: Vec<usize> = (first_new..model.effects.len()).collect();
    let free = free_params_of(&model, &added);
    if free.is_empty() {
        return Err(CliError::input(format!(
            "{} has no free parameter to fit",
            a.model.effects.join(", ")
        )));
    }
    if let Some((i, id)) = a
        .cases
        .iter()
        .enumerate()
        .find(|(i, id)| a.cases[..*i].contains(id))
    {
        return Err(CliError::input(format!(
            "--cases: case `{id}` is given twice (item {})",
            i + 1
        )));
    }
    let only: Option<Vec<usize>> = if a.cases.is_empty() {
        None
    } else {
        let idx = a
            .cases
            .iter()
            .map(|id| {
                data.cases.iter().position(|c| &c.id == id).ok_or_else(|| {
                    let known: Vec<&str> = data.cases.iter().map(|c| c.id.as_str()).collect();
                    CliError::input(format!(
                        "--cases: no case `{id}` in the data; cases: {}",
                        known.join(", ")
                    ))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Some(idx)
    };
    let n_obs: usize = only
        .as_deref()
        .map(|i| i.iter().map(|&k| &data.cases[k]).collect::<Vec<_>>())
        .unwrap_or_else(|| data.cases.iter().collect())
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum();
    if n_obs < free.len() {
        return Err(CliError::input(format!(
            "{} free parameters cannot be fitted to {} measured quantities: add cases or fix parameters",
            free.len(),
            n_obs
        )));
    }
    let result = fit_with(
        &model,
        &data,
        only.as_deref(),
        &free,
        true,
        a.likelihood.get(),
    )
    .map_err(|e| {
        let file = a
            .data
            .data
            .as_ref()
            .map_or("<built-in paper data>".to_string(), |p| {
                p.display().to_string()
            });
        CliError::input(format!("{file}: {e}"))
    })?;
    let all = compare(&result.model, &data, free.len())
        .map_err(super::model_args::in_data(&a.data.data))?;
    super::output::check_finite("fit", &result)?;
    super::output::check_finite("comparison", &all)?;
    // The same bad-run test as diagnose and audit (workbench::data_quality).
    let lone = crate::workbench::data_quality::bad_runs::bad_runs(&result.model, &data, 0.95)
        .map_err(super::model_args::in_data(&a.data.data))?;
    Ok(Fitted { result, all, lone })
}

pub fn run(a: FitArgs, inputs: &Inputs) -> Result<(), CliError> {
    let data = a.data.load(inputs)?;
    let Fitted { result, all, lone } = fitted(&a, &data, inputs)?;
    match a.format {
        TableJsonCsv::Json => {
            print_json(&Fitted { result, all, lone }.to_json(), inputs);
            return Ok(());
        }
        TableJsonCsv::Csv => return print_csv(&result.estimates, inputs),
        TableJsonCsv::Table => {}
    }
    println!(
        "calibrated on: {}",
        if a.cases.is_empty() {
            "all cases".to_string()
        } else {
            a.cases.join(", ")
        }
    );
    for e in &result.estimates {
        println!(
            "  {}.{} = {}  (± 95 % CI){}",
            e.effect,
            e.name,
            with_unit(&fmt_estimate(e.value, e.ci95), &e.unit),
            if e.at_bound {
                "  [at its bound: the data push beyond the allowed range]"
            } else {
                ""
            }
        );
    }
    for h in &result.held {
        println!("  (the intervals above are with {h} held on its fitted value)");
    }
    for w in &result.non_identifiable {
        println!("  not identifiable: {w}");
    }
    if !result.converged {
        println!(
            "  warning: the optimiser did not report convergence; treat the estimates with care"
        );
    }
    println!("{}", super::likelihood::minimised_line(a.likelihood.get()));
    println!(
        "chi-square on the calibration cases: {}",
        fmt_sig(result.chi2, 5)
    );
    if let Some(d) = result.t_deviance {
        println!(
            "Student-t deviance on the calibration cases (minimised): {}",
            fmt_sig(d, 5)
        );
    }
    println!(
        "\nerror on all cases with the calibrated model ({}):",
        all.model
    );
    for k in &all.cases {
        println!(
            "  {:<12} U {:>9}   Omega_b {:>9}",
            k.id,
            pct(k.u().rel_err),
            pct(k.omega().rel_err)
        );
    }
    println!(
        "MARE {:.1} %, max |rel err| {:.1} %, reduced chi-square {}",
        100.0 * all.summary.mare,
        100.0 * all.summary.max_abs_rel_err,
        opt(all.summary.chi2_reduced, 3)
    );
    if let Some(l) = lone {
        println!("{}", l.sentence());
    }
    Ok(())
}
