//! `swimbot compare`: model against measurement, per case and in summary.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, pct, print_json, Format};
use super::CliError;
use crate::format::{fmt_sig, fmt_value_unc};
use crate::workbench::compare::{compare, Comparison};
use crate::workbench::propagate::{
    affordable, bands, has_input_uncertainty, monte_carlo, MonteCarloCheck,
};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    #[arg(long, value_enum, default_value = "table", help = super::output::FORMAT_HELP)]
    pub format: Format,
    // `--report`: its old name, hidden, for old scripts.
    /// Directory for the HTML report (index.html).
    #[arg(short, long, alias = "report", value_name = "DIR", default_value = super::output::DEFAULT_REPORT_DIR)]
    pub output: PathBuf,
    /// Do not write the HTML report.
    #[arg(long, conflicts_with = "output")]
    pub no_report: bool,
    /// Judge residuals against the combined uncertainty: measurement and the
    /// dataset's input uncertainties propagated through the model, in quadrature
    /// (for costly models, also the only way to get the input bands at all).
    #[arg(long)]
    pub input_uncertainty: bool,
    /// Monte-Carlo draws per case that check the linearised bands (0: no check; always
    /// skipped for costly models: non-local tail or wall-resolved effects).
    #[arg(long, default_value_t = 300)]
    pub mc_draws: usize,
}

pub fn run(args: CompareArgs) -> Result<(), CliError> {
    let data = args.data.load()?;
    let model = args.model.model()?;
    let declared = has_input_uncertainty(&data);
    let cheap = affordable(&model);
    if declared && !cheap && !args.input_uncertainty {
        eprintln!("note: input-uncertainty bands skipped: this model's solves are costly (non-local tail or wall-resolved effects); --input-uncertainty computes them (two solves per uncertain input per case)");
    }
    let has_inputs = declared && (cheap || args.input_uncertainty);
    // The Monte-Carlo check would be hundreds of cold solves per case.
    let mc_draws = if cheap { args.mc_draws } else { 0 };
    if args.input_uncertainty && !declared {
        return Err(CliError::input(
            "--input-uncertainty: the dataset declares no input uncertainties (add a [setup.uncertainty] table, see docs/data-format.md)",
        ));
    }
    if args.mc_draws > 100_000 {
        return Err(CliError::input(format!(
            "--mc-draws must be at most 100000, got {}",
            args.mc_draws
        )));
    }
    if !args.no_report {
        super::output::check_output_dir(&args.output)?;
    }
    let spinner = crate::progress::spinner(&format!("compare: {}", model.describe()));
    let mut cmp = compare(&model, &data, 0).map_err(super::model_args::in_data(&args.data.data))?;
    let mut checks = Vec::new();
    if has_inputs {
        let bands = bands(&model, &data)?;
        if mc_draws >= 2 {
            for (case, b) in data.cases.iter().zip(&bands) {
                if !case.inputs.is_empty() {
                    checks.push(monte_carlo(&model, case, b, mc_draws, 0x5eed)?);
                }
            }
        }
        cmp = cmp.with_bands(&data, &bands);
    }
    spinner.set_message("compare: writing the report");
    super::output::check_finite("comparison", &cmp)?;
    // The report is written before anything is printed, so that a failure
    // does not follow a complete-looking table.
    let report = if args.no_report {
        None
    } else {
        Some(
            crate::report::write_report(&args.output, &model, &data, None).map_err(|e| {
                CliError::input(format!(
                    "writing the report to {}: {e}",
                    args.output.display()
                ))
            })?,
        )
    };
    spinner.finish_and_clear();
    match args.format {
        Format::Table => print_table(&cmp, args.input_uncertainty, &checks),
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

fn print_table(c: &Comparison, combined: bool, checks: &[MonteCarloCheck]) {
    println!("model: {}\ndata:  {}\n", c.model, c.dataset);
    let bands = c.summary_combined.is_some();
    let sigma = |m: Option<f64>, comb: Option<f64>| opt(if combined { comb } else { m }, 3);
    let band = |v: Option<f64>| match v {
        Some(x) if bands => format!("±{}", fmt_sig(x, 2)),
        _ => "-".into(),
    };
    println!(
        "{:<10} {:>6} {:>9} {:>9} {:>17} {:>9} {:>7} {:>9} {:>9} {:>17} {:>9} {:>7}",
        "case",
        "f Hz",
        "U pred",
        "± inputs",
        "U obs ± CI",
        "U err",
        "U σ",
        "Ω pred",
        "± inputs",
        "Ω obs ± CI",
        "Ω err",
        "Ω σ"
    );
    for k in &c.cases {
        let obs = |m: Option<f64>, ci: Option<f64>| match (m, ci) {
            (Some(m), Some(ci)) => fmt_value_unc(m, ci),
            _ => "-".into(),
        };
        println!(
            "{:<10} {:>6} {:>9} {:>9} {:>17} {:>9} {:>7} {:>9} {:>9} {:>17} {:>9} {:>7}",
            k.id,
            fmt_sig(k.frequency_hz, 3),
            fmt_sig(k.u_pred_mm_s, 4),
            band(k.u_input_sd_mm_s),
            obs(k.u_obs_mm_s, k.u_ci_mm_s),
            pct(k.u_rel_err),
            sigma(k.u_err_sigma, k.u_err_sigma_combined),
            fmt_sig(k.omega_pred_hz, 4),
            band(k.omega_input_sd_hz),
            obs(k.omega_obs_hz, k.omega_ci_hz),
            pct(k.omega_rel_err),
            sigma(k.omega_err_sigma, k.omega_err_sigma_combined),
        );
    }
    let s = if combined {
        c.summary_combined.as_ref().unwrap_or(&c.summary)
    } else {
        &c.summary
    };
    println!("\n(U in mm/s; Ω = Omega_b, the body's counter-rotation rate in Hz, positive when it turns against the tail; ± CI = 95 % confidence half-width; ± inputs = standard uncertainty of the prediction from the input uncertainties;");
    if combined {
        println!(" σ = error in combined standard errors: measurement and inputs in quadrature, Welch-Satterthwaite degrees of freedom)");
    } else {
        println!(" σ = error in standard errors of the measured mean)");
    }
    println!(
        "MARE {:.1} %   max |rel err| {:.1} %   reduced chi-square {}   ({} quantities)",
        100.0 * s.mare,
        100.0 * s.max_abs_rel_err,
        opt(s.chi2_reduced, 4),
        s.n
    );
    if let (false, Some(sc)) = (combined, &c.summary_combined) {
        println!(
            "against the combined uncertainty (measurement + inputs): reduced chi-square {} (--input-uncertainty judges with it)",
            opt(sc.chi2_reduced, 4)
        );
    }
    if bands {
        println!("\ndominant input of each band (U, Ω):");
        for k in &c.cases {
            println!(
                "  {:<10} {:<20} {}",
                k.id,
                k.u_dominant_input.as_deref().unwrap_or("-"),
                k.omega_dominant_input.as_deref().unwrap_or("-")
            );
        }
    }
    if !checks.is_empty() {
        let poor: Vec<&MonteCarloCheck> = checks.iter().filter(|m| m.nonlinear).collect();
        println!(
            "\nMonte-Carlo check ({} draws per case): Monte-Carlo spread / linear band, U {}..{}, Ω {}..{}",
            checks[0].draws,
            fmt_sig(checks.iter().map(|m| m.u_sd_ratio).fold(f64::MAX, f64::min), 3),
            fmt_sig(checks.iter().map(|m| m.u_sd_ratio).fold(f64::MIN, f64::max), 3),
            fmt_sig(checks.iter().map(|m| m.omega_sd_ratio).fold(f64::MAX, f64::min), 3),
            fmt_sig(checks.iter().map(|m| m.omega_sd_ratio).fold(f64::MIN, f64::max), 3),
        );
        for m in poor {
            println!(
                "  {}: the linearisation is poor (Monte Carlo / linear: U {}, Ω {}); trust the Monte-Carlo spread",
                m.id,
                fmt_sig(m.u_sd_ratio, 3),
                fmt_sig(m.omega_sd_ratio, 3)
            );
        }
    }
}

fn print_csv(c: &Comparison) -> Result<(), CliError> {
    super::output::write_csv_rows(&c.cases, std::io::stdout().lock())
}
