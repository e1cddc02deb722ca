//! `swimbot compare`: model against measurement, per case and in summary.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, pct, print_json, Format};
use super::CliError;
use crate::report::fmt_sig;
use crate::workbench::compare::{compare, Comparison};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    #[arg(long, value_enum, default_value = "table")]
    pub format: Format,
    /// Directory for the HTML report.
    #[arg(long, default_value = "report")]
    pub report: PathBuf,
    /// Do not write the HTML report.
    #[arg(long)]
    pub no_report: bool,
}

pub fn run(args: CompareArgs) -> Result<(), CliError> {
    let data = args.data.load()?;
    let model = args.model.model()?;
    if !args.no_report {
        super::output::check_output_dir(&args.report)?;
    }
    let cmp = compare(&model, &data, 0).map_err(super::model_args::in_data(&args.data.data))?;
    super::output::check_finite("comparison", &cmp)?;
    // The report is written before anything is printed, so that a failure
    // does not follow a complete-looking table.
    let report = if args.no_report {
        None
    } else {
        Some(
            crate::report::write_report(&args.report, &model, &data, None).map_err(|e| {
                CliError::input(format!(
                    "writing the report to {}: {e}",
                    args.report.display()
                ))
            })?,
        )
    };
    match args.format {
        Format::Table => print_table(&cmp),
        Format::Json => print_json(&cmp),
        Format::Csv => print_csv(&cmp)?,
    }
    if let Some(path) = report {
        if args.format == Format::Table {
            println!("\nreport: {}", path.display());
        } else {
            eprintln!("report: {}", path.display());
        }
    }
    Ok(())
}

fn print_table(c: &Comparison) {
    println!("model: {}\ndata:  {}\n", c.model, c.dataset);
    println!(
        "{:<10} {:>6} {:>9} {:>17} {:>9} {:>7} {:>9} {:>17} {:>9} {:>7}",
        "case",
        "f Hz",
        "U pred",
        "U obs ± CI",
        "U err",
        "U σ",
        "Ω pred",
        "Ω obs ± CI",
        "Ω err",
        "Ω σ"
    );
    for k in &c.cases {
        let obs = |m: Option<f64>, ci: Option<f64>| match (m, ci) {
            (Some(m), Some(ci)) => format!("{} ± {}", fmt_sig(m, 4), fmt_sig(ci, 2)),
            _ => "-".into(),
        };
        println!(
            "{:<10} {:>6} {:>9} {:>17} {:>9} {:>7} {:>9} {:>17} {:>9} {:>7}",
            k.id,
            fmt_sig(k.frequency_hz, 3),
            fmt_sig(k.u_pred_mm_s, 4),
            obs(k.u_obs_mm_s, k.u_ci_mm_s),
            pct(k.u_rel_err),
            opt(k.u_err_sigma, 3),
            fmt_sig(k.omega_pred_hz, 4),
            obs(k.omega_obs_hz, k.omega_ci_hz),
            pct(k.omega_rel_err),
            opt(k.omega_err_sigma, 3),
        );
    }
    let s = &c.summary;
    println!("\n(U in mm/s, Ω = body counter-rotation in Hz; σ = error in standard errors of the measured mean)");
    println!(
        "MARE {:.1} %   max |rel err| {:.1} %   reduced chi-square {}   ({} quantities)",
        100.0 * s.mare,
        100.0 * s.max_abs_rel_err,
        opt(s.chi2_reduced, 4),
        s.n
    );
}

fn print_csv(c: &Comparison) -> Result<(), CliError> {
    let mut w = csv::Writer::from_writer(std::io::stdout());
    for k in &c.cases {
        w.serialize(k)
            .map_err(|e| CliError::failure(format!("writing CSV: {e}")))?;
    }
    w.flush()
        .map_err(|e| CliError::failure(format!("writing CSV: {e}")))
}
