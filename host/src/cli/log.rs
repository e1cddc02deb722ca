//! `swimbot log`: the robot's run log, from a saved image or the robot's
//! USB port, decoded by the firmware's own code; its steady windows as a
//! dataset's cases and trials (`--case`), the trace figure and table.
//! Reading the port does not erase the robot's copy (the log stays in
//! flash until a later run overwrites it), so a failed read loses nothing.

use super::model_args::load_data;
use super::CliError;
use crate::provenance::Inputs;
use crate::runlog::steady::{pool, show_rate, Pooled, CONFIDENCE, MIN_TURNS};
use crate::runlog::{figure, read_current, steady_windows, trials, Source, SteadyWindow, Trace};
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;
use swimbot_shared::run_log::LogOf;

/// Where `swimbot log` writes unless told.
pub const DEFAULT_LOG_DIR: &str = "swimbot-out/log";

#[derive(Args, Debug)]
pub struct LogArgs {
    /// A saved log image, or the robot's USB port (/dev/ttyACM0, COM3): the robot answers LOG with its last run's log.
    #[arg(value_name = "FILE|PORT")]
    pub source: String,
    /// Write trials.toml: one case per set-point, this dataset case's tail, robot, tube and oil with the log's rate as frequency_hz [default: no dataset].
    #[arg(long, value_name = "ID")]
    pub case: Option<String>,
    /// Dataset holding --case (TOML or CSV) [default: the paper's built-in data].
    #[arg(long, value_name = "FILE", requires = "case")]
    pub data: Option<PathBuf>,
    /// Read an earlier power-up's run even though the robot says its current power-up's run was dropped (not logged) [default: refused, exit 2].
    #[arg(long)]
    pub earlier: bool,
    /// A bench run's can temperature (CSV `t_s,temp_c`, a thermocouple meter's, on the log's clock): fit the motor housing's thermal resistance and time constant to the log's copper loss, print the board constants they set and write thermal.toml for `cargo xtask uf2 --thermal` [default: no fit].
    #[arg(long, value_name = "CSV")]
    pub thermal: Option<PathBuf>,
    /// Output directory for log.svg, log.csv, trials.toml (and run.swlog, the image read from a port).
    #[arg(short, long, value_name = "DIR", default_value = DEFAULT_LOG_DIR)]
    pub output: PathBuf,
}

pub fn run(args: LogArgs, inputs: &Inputs) -> Result<(), CliError> {
    let source = Source::of(&args.source);
    let base = match &args.case {
        Some(id) => Some(named_case(&args.data, id, inputs)?),
        None => None,
    };
    super::output::check_output_dir(&args.output, "log", inputs)?;
    let (log, bytes, warnings) =
        read_current(&source, args.earlier, inputs).map_err(CliError::input)?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", source.name());
    }
    let trace = Trace::of(&log);
    let thermal_toml = match &args.thermal {
        Some(csv) => {
            let (report, toml) = thermal_fit(csv, &trace, &source.name())?;
            print!("{report}");
            Some(toml)
        }
        None => None,
    };
    let windows = steady_windows(&trace);
    let pooled = pool(&windows);
    let title = format!("run log {}", source.name());
    let svg = figure::svg(&trace, &windows, &title)
        .map_err(|e| CliError::failure(format!("drawing the trace: {e}")))?;
    let provenance = crate::provenance::Provenance::capture(inputs);
    let mut files = vec![
        (
            args.output.join("log.svg"),
            provenance.into_svg(&svg).into_bytes(),
        ),
        (
            args.output.join("log.csv"),
            // The warnings go with the data: a trace of an earlier
            // power-up's run must not pass for today's once saved.
            (provenance.comment_block() + &warning_comments(&warnings) + &csv(&trace)).into_bytes(),
        ),
    ];
    if let Some(case) = &base {
        if pooled.is_empty() {
            return Err(CliError::input(format!(
                "{}: no steady window (a set-point held with the rate within 2 % for {MIN_TURNS} turns or more): no trials to write for `{}`",
                source.name(),
                case.id
            )));
        }
        let toml = trials::dataset_toml(case, &pooled, &source.name());
        files.push((args.output.join("trials.toml"), toml.into_bytes()));
    }
    if let Some(toml) = thermal_toml {
        files.push((args.output.join("thermal.toml"), toml.into_bytes()));
    }
    if matches!(source, Source::Port(_)) {
        files.push((args.output.join("run.swlog"), bytes));
    }
    super::output::write_all_atomically(&files, inputs)?;
    print!("{}", summary(&trace, &windows, &pooled, &log.header));
    if base.is_none() {
        println!(
            "no --case: no dataset written (give the dataset case the run was, e.g. --case tail-3)"
        );
    }
    let names: Vec<String> = files.iter().map(|f| f.0.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
    Ok(())
}

fn warning_comments(warnings: &[String]) -> String {
    warnings
        .iter()
        .map(|w| format!("# warning: {w}\n"))
        .collect()
}

fn named_case(
    data: &Option<PathBuf>,
    id: &str,
    inputs: &Inputs,
) -> Result<crate::data::Case, CliError> {
    let data = load_data(data, inputs)?;
    data.cases
        .iter()
        .find(|c| c.id == id)
        .cloned()
        .ok_or_else(|| {
            let ids: Vec<&str> = data.cases.iter().map(|c| c.id.as_str()).collect();
            CliError::input(format!(
                "--case `{id}`: no such case in {}; its cases: {}",
                data.name,
                ids.join(", ")
            ))
        })
}

/// The trace as CSV, one row per record (empty: not measured / no reading).
pub fn csv(trace: &Trace) -> String {
    let mut out = String::from("time_s,set_hz,rate_hz,duty,cell_v,events\n");
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    for p in &trace.points {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{}",
            p.t_s,
            opt(p.set_hz),
            opt(p.rate_hz),
            p.duty,
            opt(p.cell_v),
            p.events.join(";")
        );
    }
    out
}

fn summary(
    trace: &Trace,
    windows: &[SteadyWindow],
    pooled: &[Pooled],
    header: &swimbot_shared::run_log::Header,
) -> String {
    let mut s = String::new();
    let (t0, t1) = (
        trace.points.first().map_or(0.0, |p| p.t_s),
        trace.points.last().map_or(0.0, |p| p.t_s),
    );
    let _ = writeln!(
        s,
        "{} records every {} ms, {t0:.1}-{t1:.1} s since power-up, {}; {} dropped by the power-up that read it out; {} frames from other remotes ignored; remote {}",
        trace.points.len(),
        header.sample_period_ms,
        match LogOf::of(header) {
            LogOf::EarlierPowerUp => "an EARLIER power-up's run",
            _ => "this power-up's run",
        },
        header.dropped_records,
        header.foreign_frames,
        header
            .paired_address
            .map_or("not paired".to_string(), |a| format!("{a:#04x}"))
    );
    let _ = writeln!(
        s,
        "steady windows (set-point held, rate within 2 % for good, >= {MIN_TURNS} turns; {} % CI over whole-turn means):",
        100.0 * CONFIDENCE
    );
    if windows.is_empty() {
        let _ = writeln!(s, "  none");
    }
    for w in windows {
        let _ = writeln!(
            s,
            "  {:>7.1}-{:<7.1} s  set {:.3} Hz  rate {} ({} turns)  duty {:.1} %",
            w.from_s,
            w.to_s,
            w.set_hz,
            show_rate(w.mean_hz, w.ci_hz),
            w.turn_means_hz.len(),
            100.0 * w.mean_duty
        );
    }
    for p in pooled {
        let _ = writeln!(
            s,
            "set-point {:.3} Hz: {} over {} turns in {} window(s)",
            p.set_hz,
            show_rate(p.mean_hz, p.ci_hz),
            p.turns,
            p.windows.len()
        );
    }
    s
}

/// `--thermal`: the housing node fitted to the bench readings in `csv`:
/// the printed report and `thermal.toml` (for `cargo xtask fw|uf2 --thermal`).
fn thermal_fit(
    csv: &std::path::Path,
    trace: &Trace,
    log_name: &str,
) -> Result<(String, String), CliError> {
    use crate::runlog::thermal;
    let name = csv.display().to_string();
    let text = std::fs::read_to_string(csv).map_err(|e| CliError::input(format!("{name}: {e}")))?;
    let temps = thermal::read_temperatures(&text, &name).map_err(CliError::input)?;
    let r_ohm = f64::from(
        swimbot_shared::board::SUPERVISOR
            .thermal
            .motor_resistance_mohm,
    ) * 1e-3;
    let fit = thermal::fit(&thermal::losses(trace, r_ohm), &temps)
        .map_err(|e| CliError::input(format!("{name}: {e}")))?;
    Ok((
        thermal::report(&fit),
        thermal::toml_text(&fit, log_name, &name),
    ))
}
