//! `swimbot compare`: model against measurement, per case and in summary.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, pct, print_json, Format};
use super::CliError;
use crate::format::{fmt_sig, fmt_value_unc};
use crate::provenance::Inputs;
use crate::workbench::compare::Comparison;
use crate::workbench::input_covariance::CorrelatedChi2;
use crate::workbench::path::{user_path, Path};
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
    /// Directory for the HTML page (index.html, figures as SVG, tables as CSV and JSON,
    /// manifest.json); a directory another command wrote is refused.
    #[arg(short, long, alias = "report", value_name = "DIR", default_value = DEFAULT_COMPARE_DIR)]
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
    #[arg(long, default_value_t = 300, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub mc_draws: usize,
}

/// `compare`'s own folder: `report`'s page in `swimbot-out/report` is
/// never overwritten by a `compare` with default options.
pub const DEFAULT_COMPARE_DIR: &str = "swimbot-out/compare";

/// How many effects of the model come with its preset (the start of the
/// user's path); the effects after them are the user's steps.
pub fn preset_effects(m: &ModelArgs) -> usize {
    crate::model::preset(m.preset.as_deref().unwrap_or("base")).map_or(0, |p| p.effects.len())
}

/// What `compare` computes, before anything is printed or written: the
/// user's path (its last step is the comparison) and the Monte-Carlo
/// checks of the input bands. The Python package calls it too, so that
/// its numbers are the command's.
pub struct Compared {
    pub path: Path,
    pub checks: Vec<MonteCarloCheck>,
}

/// `compare`'s work on `data` with the flags in `args` (its `--data` is
/// not read: the caller loaded the data); effect files it reads are
/// recorded in `inputs`.
pub fn compared(
    args: &CompareArgs,
    data: &crate::data::Dataset,
    inputs: &Inputs,
) -> Result<Compared, CliError> {
    let model = args.model.model(inputs)?;
    let declared = has_input_uncertainty(data);
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
    let to_input = super::model_args::in_data(&args.data.data);
    // The path is computed once; the table, the JSON and the page print it.
    let mut path = user_path(&model, preset_effects(&args.model), data).map_err(&to_input)?;
    let mut checks = Vec::new();
    if has_inputs {
        let bands = bands(&model, data)?;
        if mc_draws >= 2 {
            for (case, b) in data.cases.iter().zip(&bands) {
                if !case.inputs.is_empty() {
                    checks.push(monte_carlo(&model, case, b, mc_draws, 0x5eed)?);
                }
            }
        }
        let last = path.steps.last_mut().expect("a path has its start");
        if last.comparison.summary_combined.is_none() {
            last.comparison = last.comparison.clone().with_bands(data, &bands);
        }
    }
    Ok(Compared { path, checks })
}

pub fn run(args: CompareArgs, inputs: &Inputs) -> Result<(), CliError> {
    let data = args.data.load(inputs)?;
    if !args.no_report {
        super::output::check_output_dir(&args.output, "compare", inputs)?;
        crate::report::check_bundle_dir(&args.output, "compare").map_err(CliError::input)?;
    }
    let spinner = crate::progress::stages(
        if args.no_report { 1 } else { 2 },
        &format!("compare: the model on {} cases", data.cases.len()),
    );
    spinner.set_position(1);
    let Compared { path, checks } = compared(&args, &data, inputs)?;
    let cmp = path.last().comparison.clone();
    spinner.set_message("compare: writing the report");
    spinner.set_position(2);
    super::output::check_finite("comparison", &cmp)?;
    // The report is written before anything is printed, so that a failure
    // does not follow a complete-looking table.
    let report = if args.no_report {
        None
    } else {
        Some(
            crate::report::write_report(
                &args.output,
                &path,
                &data,
                None,
                &|p| super::output::not_an_input(p, inputs),
                inputs,
            )
            .map_err(|e| {
                CliError::input(format!(
                    "writing the report to {}: {e}",
                    args.output.display()
                ))
            })?,
        )
    };
    spinner.finish_and_clear();
    match args.format {
        Format::Table => {
            print_table(&cmp, args.input_uncertainty, &checks);
            print_steps(&path);
        }
        Format::Json => print_json(&cmp, inputs),
        Format::Csv => print_csv(&cmp, inputs)?,
    }
    if let Some(path) = report {
        if args.format == Format::Table {
            println!("\npage: {}", path.display());
        } else {
            eprintln!("page: {}", path.display());
        }
    }
    Ok(())
}

fn print_table(c: &Comparison, combined: bool, checks: &[MonteCarloCheck]) {
    println!("model: {}\ndata:  {}\n", c.model, c.dataset);
    let bands = c.summary_combined.is_some();
    let sigma = |m: Option<f64>, comb: Option<f64>| opt(if combined { comb } else { m }, 3);
    // the prediction to its band's two significant figures (the number
    // policy of `swimbot::format`), or to 4 figures without a band
    let pred = |v: f64, sd: Option<f64>| match sd {
        Some(u) if bands && u > 0.0 => fmt_value_unc(v, u),
        _ => fmt_sig(v, 4),
    };
    println!(
        "{:<10} {:>6} {:>19} {:>17} {:>9} {:>7} {:>19} {:>17} {:>9} {:>7}",
        "case",
        "f Hz",
        if bands { "U pred ± inputs" } else { "U pred" },
        "U obs ± CI",
        "U err",
        "U σ",
        if bands {
            "Ω pred ± inputs"
        } else {
            "Ω pred"
        },
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
            "{:<10} {:>6} {:>19} {:>17} {:>9} {:>7} {:>19} {:>17} {:>9} {:>7}",
            k.id,
            fmt_sig(k.frequency_hz, 3),
            pred(k.u().pred, k.u().input_sd),
            obs(k.u().obs, k.u().ci),
            pct(k.u().rel_err),
            sigma(k.u().err_sigma, k.u().err_sigma_combined),
            pred(k.omega().pred, k.omega().input_sd),
            obs(k.omega().obs, k.omega().ci),
            pct(k.omega().rel_err),
            sigma(k.omega().err_sigma, k.omega().err_sigma_combined),
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
    // Against the inputs too, the statistic is the chi-square with their
    // covariance (printed below); the measurement-alone one otherwise.
    let chi2_here = match (&c.chi2_correlated, combined) {
        (Some(_), true) => String::new(),
        _ => format!("reduced chi-square {}   ", opt(s.chi2_reduced, 3)),
    };
    println!(
        "MARE {:.1} %   max |rel err| {:.1} %   {chi2_here}({} quantities - {} free parameters)",
        100.0 * s.mare,
        100.0 * s.max_abs_rel_err,
        s.n,
        s.free_params
    );
    if let Some(cov) = &c.coverage {
        let outside: Vec<String> = cov
            .outside
            .iter()
            .map(|o| format!("{} {} {}", o.case, o.quantity.label(), fmt_sig(o.sigmas, 3)))
            .collect();
        println!(
            "coverage: {}{}",
            cov.describe(),
            if outside.is_empty() {
                String::new()
            } else {
                format!("; outside: {}", outside.join(", "))
            }
        );
    }
    if let Some(x) = &c.chi2_correlated {
        print_correlated(x, combined);
    }
    if bands {
        println!("\ndominant input of each band (U, Ω):");
        for k in &c.cases {
            println!(
                "  {:<10} {:<20} {}",
                k.id,
                k.u().dominant_input.as_deref().unwrap_or("-"),
                k.omega().dominant_input.as_deref().unwrap_or("-")
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

/// The chi-square against measurement and inputs with the inputs'
/// covariance, in the words the page uses, and the shared inputs' pulls.
fn print_correlated(x: &CorrelatedChi2, combined: bool) {
    println!(
        "against measurement and inputs: {}{}",
        x.describe(),
        if combined {
            ""
        } else {
            " (--input-uncertainty judges with it)"
        }
    );
    println!(
        "  the same residuals: chi-square {}",
        x.describe_independent()
    );
    let shown: Vec<String> = x
        .pulls
        .iter()
        .filter(|p| p.informative())
        .map(|p| format!("  {}", p.describe()))
        .collect();
    if !shown.is_empty() {
        println!(
            "what the data would want of the inputs shared by cases (each alone, the others at their declared uncertainty; reported, not applied; pinned to within 3 declared uncertainties):\n{}",
            shown.join("\n")
        );
    }
}

/// The user's steps, each against the one before (nothing when the model
/// has no added effect): the same numbers the page's step table shows.
fn print_steps(path: &Path) {
    if path.steps.len() < 2 {
        return;
    }
    println!("\nthe model step by step (\"+ X\": X added on top of the step before):");
    for s in &path.steps {
        let m = s.summary();
        println!(
            "  {:<28} MARE {:>7}   reduced chi-square {:>8} ({} quantities - {} free parameters)",
            s.label,
            format!("{:.1} %", 100.0 * m.mare),
            opt(m.chi2_reduced, 3),
            m.n,
            m.free_params
        );
    }
}

/// The CSV: one row per case, the body rate's columns named
/// `omega_body_counter_*` as the README and the data format call Ω_b
/// (the JSON keeps the field names of the library's types).
fn print_csv(c: &Comparison, inputs: &Inputs) -> Result<(), CliError> {
    let mut bytes = Vec::new();
    super::output::write_csv_rows(&c.cases, &mut bytes, inputs)?;
    let text = String::from_utf8(bytes).expect("the CSV writer writes UTF-8");
    // the provenance block's `#` lines come first, then the header
    let table_at = text
        .match_indices('\n')
        .map(|(i, _)| i + 1)
        .find(|&i| !text[i..].starts_with('#'))
        .filter(|_| text.starts_with('#'))
        .unwrap_or(0);
    let (comments, table) = text.split_at(table_at);
    let (header, rows) = table.split_once('\n').unwrap_or((table, ""));
    let header: Vec<String> = header.split(',').map(csv_column).collect();
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let done = out
        .write_all(comments.as_bytes())
        .and_then(|()| writeln!(out, "{}", header.join(",")))
        .and_then(|()| out.write_all(rows.as_bytes()));
    super::stdout::stdout_written(done, "the CSV")
}

/// `omega_pred_hz` -> `omega_body_counter_pred_hz`, and so on.
fn csv_column(name: &str) -> String {
    match name.strip_prefix("omega_") {
        Some(rest) if rest.ends_with("_hz") => format!("omega_body_counter_{rest}"),
        _ => name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::csv_column;

    #[test]
    fn the_csv_names_the_body_rate_as_the_readme_does() {
        assert_eq!(csv_column("omega_pred_hz"), "omega_body_counter_pred_hz");
        assert_eq!(csv_column("omega_ci_hz"), "omega_body_counter_ci_hz");
        assert_eq!(
            csv_column("omega_input_sd_hz"),
            "omega_body_counter_input_sd_hz"
        );
        // not a rate in Hz: kept
        assert_eq!(csv_column("omega_rel_err"), "omega_rel_err");
        assert_eq!(csv_column("u_pred_mm_s"), "u_pred_mm_s");
    }
}
