//! `swimbot diagnose`: where the model fails and which effect is missing.

use super::model_args::{DataArgs, ModelArgs};
use super::output::{opt, print_csv, print_json, TableJsonCsv};
use super::CliError;
use crate::data::Dataset;
use crate::format::{fmt_estimate, fmt_sig};
use crate::provenance::Inputs;
use crate::workbench::diagnose::{diagnose, Candidate, DiagnoseSettings, Diagnosis};
use crate::workbench::diagnosis::DIAGNOSE_STAGES;
use crate::workbench::discovery::Located;
use crate::workbench::progress::Progress;
use clap::Args;

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub model: ModelArgs,
    /// Output format on stdout (csv: the ranking of catalogue effects and
    /// pairs, one row per candidate, `kind,effect,params,mare,cv_mare,chi2,
    /// chi2_reduced,aicc,at_noise_floor,converged`; json: the whole diagnosis).
    #[arg(long, value_enum, default_value = "table")]
    pub format: TableJsonCsv,
    /// Quantile of a perfect model's chi-square distribution taken as the noise floor (0.5 to 1).
    #[arg(long, default_value_t = 0.95)]
    pub level: f64,
    /// AICc margin by which the best candidate must beat the next to be a clear winner.
    #[arg(long, default_value_t = 4.0)]
    pub margin: f64,
    /// Do not try pairs of effects.
    #[arg(long)]
    pub no_pairs: bool,
    /// Also try the costly wall-resolved (regularized-Stokeslet tube) effects; seconds per case on first use, then cached.
    #[arg(long)]
    pub nonlocal: bool,
    /// Judge residuals against the combined uncertainty (measurement and the
    /// dataset's input uncertainties, in quadrature), so that a residual the
    /// inputs explain does not call for an effect.
    #[arg(long)]
    pub input_uncertainty: bool,
    /// Do not search beyond the catalogue (place x feature x form).
    #[arg(long)]
    pub no_discovery: bool,
    /// Also write the best located correction as a user-effect file (TOML), fitted values as
    /// defaults [default: none written].
    #[arg(long, value_name = "FILE.toml")]
    pub write_effect: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub likelihood: super::likelihood::LikelihoodArgs,
    /// Refuse the diagnosis when its estimated run time (the diagnosis timed on subsets of the
    /// cases growing to a twelfth of them, grown to all) is longer [default: no limit; from 200 cases the estimate
    /// is made, and one over 10 s is announced on stderr].
    #[arg(long, value_name = "SECONDS")]
    pub max_seconds: Option<f64>,
    /// Print every table behind the answer (the residuals, the trends, the
    /// catalogue's ranking, the searches' laws) before it [default: the
    /// answer alone].
    #[arg(long)]
    pub verbose: bool,
}

/// `diagnose`'s work on `data` with the flags in `a` (its `--data` is not
/// read): the diagnosis and the data it judged (with the input
/// uncertainty folded in if asked), its stages told to `progress`. The
/// Python package calls it too, so that its numbers are the command's.
pub fn diagnosed(
    a: &DiagnoseArgs,
    data: Dataset,
    progress: Option<Progress>,
    inputs: &Inputs,
) -> Result<(Diagnosis, Dataset), CliError> {
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
    let measured = data.measured_cases();
    if measured < 2 {
        // Cross-validation leaves a case out; with one measured case there
        // is nothing to predict it from, and every one-parameter effect fits
        // its two quantities, so no ranking could mean anything (unmeasured
        // cases beside it change nothing: they enter no error).
        return Err(CliError::input(format!(
            "{}: diagnose needs at least 2 cases with a measured speed or rotation rate, the dataset has {measured} (of {} cases): with one, cross-validation \
             has nothing to predict from and every effect with a free parameter fits its two quantities; \
             `swimbot compare` shows the model's error on it and `swimbot fit` calibrates on it",
            data.name,
            data.cases.len()
        )));
    }
    let (model, catalogue) = a.model.model_and_catalogue(inputs)?;
    let data = if a.input_uncertainty {
        crate::workbench::propagate::with_input_uncertainty(&model, &data)?
    } else {
        data
    };
    let settings = DiagnoseSettings {
        level: a.level,
        clear_margin: a.margin,
        second_effect: !a.no_pairs,
        include_costly: a.nonlocal,
        discover: !a.no_discovery,
        progress,
        likelihood: a.likelihood.get(),
        catalogue,
        ..Default::default()
    };
    let budget = super::budget::parse_budget(a.max_seconds)?;
    if budget.is_some() || data.cases.len() >= super::budget::ESTIMATE_FROM_CASES {
        let quiet = DiagnoseSettings {
            progress: None,
            ..settings.clone()
        };
        let estimate = estimate_seconds(&model, &data, &quiet);
        let what = format!("the diagnosis of {} cases", data.cases.len());
        match estimate {
            Some(s) => super::budget::check(&what, s, budget)?,
            None => super::budget::unestimated(&what, budget),
        }
    }
    let d = diagnose(&model, &data, &settings).map_err(CliError::input)?;
    super::output::check_finite("diagnosis", &d)?;
    Ok((d, data))
}

pub fn run(a: DiagnoseArgs, inputs: &Inputs) -> Result<(), CliError> {
    if let Some(path) = &a.write_effect {
        super::output::check_output_file(path, inputs)?;
    }
    let data = a.data.load(inputs)?;
    // Shown once the work has lasted 2 s (paper-sized data takes less).
    let spinner = crate::progress::stages(
        DIAGNOSE_STAGES,
        &format!("diagnosing {} cases: the data's quality", data.cases.len()),
    );
    spinner.set_position(1);
    let (d, data) = diagnosed(
        &a,
        data,
        Some(crate::progress::to_bar(&spinner, "")),
        inputs,
    )?;
    let lik = a.likelihood.get();
    spinner.finish_and_clear();
    // The file the user asked for is written before stdout is touched: a
    // reader that stops early (`| head`) ends the process by SIGPIPE while
    // the table is printed, and the file must already be there.
    if let Some(path) = &a.write_effect {
        write_effect(&d, &data.name, path, inputs)?;
    }
    match a.format {
        TableJsonCsv::Json => {
            print_json(&super::likelihood::diagnosis_json(&d, &data, lik)?, inputs)
        }
        TableJsonCsv::Csv => print_csv(&ranking_rows(&d), inputs)?,
        TableJsonCsv::Table => {
            if a.verbose {
                if a.input_uncertainty {
                    println!("(judged against the combined uncertainty: each standard error below is the measurement's and the inputs' in quadrature)\n");
                }
                // Every "by AICc" below is that deviance's AICc (workbench::score).
                println!(
                    "{}; every AICc below is that deviance's\n",
                    super::likelihood::minimised_line(lik)
                );
                print_table(&d);
                println!();
            }
            let h = super::screen::headline::headline(&d, a.write_effect.as_deref());
            println!(
                "{}",
                super::screen::render::render(&h, super::screen::width())
            );
        }
    }
    Ok(())
}

/// The corrections to write ([`Diagnosis::laws_to_write`]). A verdict of
/// none-needed writes nothing: that is an answer, not an error.
fn write_effect(
    d: &Diagnosis,
    dataset: &str,
    path: &std::path::Path,
    inputs: &Inputs,
) -> Result<(), CliError> {
    let list = d.laws_to_write();
    if list.is_empty() {
        eprintln!(
            "--write-effect {}: nothing was located (verdict: {}), so no file was written",
            path.display(),
            d.verdict.kind.name()
        );
        return Ok(());
    }
    let text = crate::provenance::Provenance::capture(inputs).comment_block()
        + &crate::workbench::discovery::write::to_toml_steps(&list, dataset);
    super::output::write_atomically(path, text.as_bytes(), inputs)?;
    let what: Vec<String> = list.iter().map(Located::describe).collect();
    eprintln!("wrote {} ({})", path.display(), what.join("; then "));
    Ok(())
}

fn print_steps(steps: &[crate::workbench::diagnose::SetMember]) {
    if steps.is_empty() {
        return;
    }
    println!("\nthe found set, at its joint values (each row: the members up to it):");
    println!(
        "  {:<3} {:<62} {:>8} {:>8} {:>10} {:>8} {:>5}",
        "", "step", "MARE", "CV MARE", "chi2_red", "explains", "noise"
    );
    for (i, s) in steps.iter().enumerate() {
        println!(
            "  {:<3} {:<62} {:>7.2}% {:>7.2}% {:>10} {:>8} {:>5}",
            format!("{}.", i + 1),
            format!("{} {}", s.kind, s.name),
            100.0 * s.mare,
            100.0 * s.cv_mare,
            opt(s.chi2_reduced, 3),
            s.explained_fraction
                .map(|f| format!("{:.0}%", 100.0 * f))
                .unwrap_or_else(|| "-".into()),
            if s.at_noise_floor { "yes" } else { "no" }
        );
    }
}

/// The sets the data cannot tell apart, each with its key difference and
/// the measurement that would separate it from the first.
fn print_sets(v: &crate::workbench::diagnose::Verdict) {
    if v.sets.is_empty() {
        return;
    }
    println!("\nsets the data cannot tell apart (AICc + charges within the margin):");
    let mut rig_said = false;
    for (i, s) in v.sets.iter().enumerate() {
        println!(
            "  {}. {} (key {:+.1}{})",
            i + 1,
            s.members.join(" + "),
            s.key_difference,
            if s.at_noise_floor {
                ", at the noise floor"
            } else {
                ""
            }
        );
        if let Some(g) = &s.suggestion {
            println!("     {}", g.hint_within(rig_said).trim_start_matches("; "));
            rig_said = true;
        }
    }
    if !v.agreed_places.is_empty() {
        println!("  found in every set: {}", v.agreed_places.join(", "));
    }
}

fn print_located(title: &str, list: &[Located]) {
    if list.is_empty() {
        return;
    }
    println!("\n{title}");
    println!(
        "  {:<58} {:>8} {:>8} {:>10} {:>7} {:>5}  parameters (95 % CI)",
        "correction", "MARE", "CV MARE", "chi2_red", "explains", "noise"
    );
    for l in list {
        let ps = l
            .params
            .iter()
            .map(|p| format!("{}={}", p.name, fmt_estimate(p.value, p.ci95)))
            .collect::<Vec<_>>()
            .join(", ");
        println!(
            "  {:<58} {:>7.2}% {:>7.2}% {:>10} {:>7} {:>5}  {}",
            format!("{} = {}", l.place, l.formula),
            100.0 * l.score.mare,
            100.0 * l.score.cv_mare,
            opt(l.score.chi2_reduced, 3),
            l.explained_fraction
                .map(|f| format!("{:.0}%", 100.0 * f))
                .unwrap_or_else(|| "-".into()),
            if l.score.at_noise_floor { "yes" } else { "no" },
            ps
        );
        println!("  {:<58} {}", "", l.interpretation);
    }
}

fn params(c: &Candidate) -> String {
    if c.params.is_empty() {
        return "-".into();
    }
    c.params
        .iter()
        .map(|p| {
            let bound = if p.at_bound { " [at bound]" } else { "" };
            format!("{}={}{bound}", p.name, fmt_estimate(p.value, p.ci95))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_candidates(title: &str, list: &[Candidate]) {
    if list.is_empty() {
        return;
    }
    let best = list[0].score.aicc.unwrap_or(f64::NAN);
    println!("\n{title}");
    println!(
        "  {:<34} {:>8} {:>8} {:>10} {:>10} {:>7} {:>5}  parameters (95 % CI)",
        "effect", "MARE", "CV MARE", "chi2_red", "AICc", "ΔAICc", "noise"
    );
    for c in list {
        println!(
            "  {:<34} {:>7.2}% {:>7.2}% {:>10} {:>10} {:>7} {:>5}  {}",
            c.effect,
            100.0 * c.score.mare,
            100.0 * c.score.cv_mare,
            opt(c.score.chi2_reduced, 3),
            opt(c.score.aicc, 5),
            c.score
                .aicc
                .map(|a| fmt_sig(a - best, 3))
                .unwrap_or_else(|| "-".into()),
            if c.score.at_noise_floor { "yes" } else { "no" },
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
        100.0 * b.mare, 100.0 * b.max_abs_rel_err, opt(b.chi2_reduced, 3), opt(b.noise_floor_chi2_reduced, 3));
    println!("\nresiduals in standard errors of the measured mean:");
    println!("  {:<18} {:>9} {:>9}", "case", "U", "Omega_b");
    for c in &d.comparison.cases {
        println!(
            "  {:<18} {:>9} {:>9}",
            c.id,
            opt(c.u().err_sigma, 3),
            opt(c.omega().err_sigma, 3)
        );
    }
    println!("\nwhere it fails (relative error against case features, strongest first):");
    for t in d.trends.iter().take(6) {
        println!(
            "  {:<8} vs {:<18} r = {:+.2}   slope {} per unit",
            t.quantity.label(),
            t.feature,
            t.r,
            fmt_sig(t.slope, 3)
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
    if let Some(x) = &d.discovery {
        print_located(
            &format!(
                "beyond the catalogue: the best of {} laws (place x feature x form), refitted exactly, by AICc:",
                x.screened
            ),
            &x.located[..x.located.len().min(6)],
        );
    }
    if let Some(r) = &d.remainder {
        print_located(
            &format!("what {} leaves, located on top of it:", r.effect),
            &r.discovery.located[..r.discovery.located.len().min(3)],
        );
    }
    print_steps(&d.verdict.steps);
    print_sets(&d.verdict);
    println!("\nverdict ({}): {}", d.verdict.kind.name(), d.verdict.note);
}

/// One row of `diagnose --format csv`: a candidate of the ranking.
#[derive(serde::Serialize)]
struct RankingRow<'a> {
    /// `single` (one catalogue effect) or `pair` (two at once).
    kind: &'static str,
    effect: &'a str,
    /// `effect.name=value` for each fitted parameter, `;`-separated.
    params: String,
    mare: f64,
    cv_mare: f64,
    chi2: f64,
    chi2_reduced: Option<f64>,
    aicc: Option<f64>,
    at_noise_floor: bool,
    converged: bool,
}

fn ranking_rows(d: &Diagnosis) -> Vec<RankingRow<'_>> {
    let singles = d.ranking.iter().map(|c| ranking_row("single", c));
    singles
        .chain(d.pairs.iter().map(|c| ranking_row("pair", c)))
        .collect()
}

fn ranking_row<'a>(kind: &'static str, c: &'a Candidate) -> RankingRow<'a> {
    let params: Vec<String> = c
        .params
        .iter()
        .map(|e| format!("{}.{}={}", e.effect, e.name, e.value))
        .collect();
    RankingRow {
        kind,
        effect: &c.effect,
        params: params.join(";"),
        mare: c.score.mare,
        cv_mare: c.score.cv_mare,
        chi2: c.score.chi2,
        chi2_reduced: c.score.chi2_reduced,
        aicc: c.score.aicc,
        at_noise_floor: c.score.at_noise_floor,
        converged: c.converged,
    }
}

/// The diagnosis's run time, from the diagnosis itself timed on two
/// subsets of the cases ([`super::budget::extrapolate`]).
pub(super) fn estimate_seconds(
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    settings: &DiagnoseSettings,
) -> Option<f64> {
    super::budget::extrapolate(data.cases.len(), |k| {
        let part = super::budget::subset(data, k);
        let (done, s) = super::budget::timed(|| diagnose(model, &part, settings));
        done.ok()?;
        Some(s)
    })
}
