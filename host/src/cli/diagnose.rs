//! `swimbot diagnose`: where the model fails and which effect is missing.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, print_json, Format};
use super::CliError;
use crate::report::fmt_sig;
use crate::workbench::diagnose::{diagnose, Candidate, DiagnoseSettings, Diagnosis};
use clap::Args;
use indicatif::ProgressBar;

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    #[arg(long, value_enum, default_value = "table")]
    pub format: Format,
    /// Quantile of a perfect model's chi-square taken as the noise floor.
    #[arg(long, default_value_t = 0.95)]
    pub level: f64,
    /// AICc margin that makes a winner clear.
    #[arg(long, default_value_t = 4.0)]
    pub margin: f64,
    /// Do not try pairs of effects.
    #[arg(long)]
    pub no_pairs: bool,
    /// Also try the costly wall-resolved (regularized-Stokeslet tube) effects; seconds per case on first use, then cached.
    #[arg(long)]
    pub nonlocal: bool,
}

pub fn run(a: DiagnoseArgs) -> Result<(), CliError> {
    if !(a.level > 0.5 && a.level < 1.0) {
        return Err(CliError::input(format!(
            "--level must be between 0.5 and 1, got {}",
            a.level
        )));
    }
    if !(a.margin.is_finite() && a.margin >= 0.0) {
        return Err(CliError::input(format!(
            "--margin must be a number >= 0, got {}",
            a.margin
        )));
    }
    let data = a.data.load()?;
    let model = a.model.model()?;
    let settings = DiagnoseSettings {
        level: a.level,
        clear_margin: a.margin,
        second_effect: !a.no_pairs,
        include_costly: a.nonlocal,
    };
    let spinner = if data.cases.len() >= 20 || a.nonlocal {
        let s = ProgressBar::new_spinner();
        s.set_message(format!(
            "diagnosing {} cases against the catalogue",
            data.cases.len()
        ));
        s.enable_steady_tick(std::time::Duration::from_millis(120));
        s
    } else {
        ProgressBar::hidden()
    };
    let d = diagnose(&model, &data, &settings).map_err(CliError::input)?;
    super::output::check_finite("diagnosis", &d)?;
    spinner.finish_and_clear();
    match a.format {
        Format::Json => print_json(&d),
        _ => print_table(&d),
    }
    Ok(())
}

fn params(c: &Candidate) -> String {
    if c.params.is_empty() {
        return "-".into();
    }
    c.params
        .iter()
        .map(|p| {
            let ci = p
                .ci95
                .map(|x| format!(" ± {}", fmt_sig(x, 2)))
                .unwrap_or_else(|| " (±?)".into());
            let bound = if p.at_bound { " [at bound]" } else { "" };
            format!("{}={}{ci}{bound}", p.name, fmt_sig(p.value, 4))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_candidates(title: &str, list: &[Candidate]) {
    if list.is_empty() {
        return;
    }
    let best = list[0].aicc.unwrap_or(f64::NAN);
    println!("\n{title}");
    println!(
        "  {:<34} {:>8} {:>8} {:>10} {:>10} {:>7} {:>5}  parameters (95 % CI)",
        "effect", "MARE", "CV MARE", "chi2_red", "AICc", "ΔAICc", "noise"
    );
    for c in list {
        println!(
            "  {:<34} {:>7.2}% {:>7.2}% {:>10} {:>10} {:>7} {:>5}  {}",
            c.effect,
            100.0 * c.mare,
            100.0 * c.cv_mare,
            opt(c.chi2_reduced, 4),
            opt(c.aicc, 5),
            c.aicc
                .map(|a| format!("{:.1}", a - best))
                .unwrap_or_else(|| "-".into()),
            if c.at_noise_floor { "yes" } else { "no" },
            params(c)
        );
        for w in &c.non_identifiable {
            println!("  {:<34} not identifiable: {w}", "");
        }
        if !c.converged {
            println!("  {:<34} warning: the fit did not report convergence", "");
        }
    }
}

fn print_table(d: &Diagnosis) {
    let b = &d.baseline;
    println!("model: {}\ndata:  {}\n", b.model, d.comparison.dataset);
    println!("baseline: MARE {:.1} %, max |rel err| {:.1} %, reduced chi-square {} (a perfect model stays below {} at this data's precision)",
        100.0 * b.mare, 100.0 * b.max_abs_rel_err, opt(b.chi2_reduced, 4), opt(b.noise_floor_chi2_reduced, 3));
    println!("\nresiduals in standard errors of the measured mean:");
    println!("  {:<18} {:>9} {:>9}", "case", "U", "Omega_b");
    for c in &d.comparison.cases {
        println!(
            "  {:<18} {:>9} {:>9}",
            c.id,
            opt(c.u_err_sigma, 3),
            opt(c.omega_err_sigma, 3)
        );
    }
    println!("\nwhere it fails (relative error against case features, strongest first):");
    for t in d.trends.iter().take(6) {
        println!(
            "  {:<8} vs {:<18} r = {:+.2}   slope {:+.3} per unit",
            t.quantity.label(),
            t.feature,
            t.r,
            t.slope
        );
    }
    if d.trends.is_empty() {
        println!("  (fewer than three cases, or no feature varies)");
    }
    print_candidates(
        "each candidate effect added alone, fitted, ranked by AICc:",
        &d.ranking,
    );
    print_candidates(
        "forward selection, the best effect with a second one:",
        &d.pairs,
    );
    println!("\nverdict: {}", d.verdict.note);
}
